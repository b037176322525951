// `fx2d-bench merge OUT.h5 IN.h5...`: one sweep, stability or run file from the files its shards wrote
// (`--shard K/N`, common/shard.h), as if one process had run the whole work list.
//
// Reads top to bottom: each shard's file read (storage/), the checks and the join
// (analysis/shard_merge.h: each refusal one line, exit 2), then the file, written atomically like
// any result file.
#include <algorithm>
#include <filesystem>
#include <memory>

#include "analysis/shard_merge.h"
#include "commands/commands.h"
#include "common/bounded_read.h"
#include "common/errors.h"
#include "storage/file_integrity.h"
#include "storage/h5_tables.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

struct MergeOptions {
  std::string out;
  std::vector<std::string> inputs;
  bool force = false;
};

// Where each command records its shard: sweep and stability in their own table, run in /shard.
constexpr const char* shard_tables[] = {"/sweep", "/stability", "/shard"};

ShardFile read_shard(const std::string& path) {
  require_regular_file(path, path);
  if (carries_h5_seal(path)) verify_h5_seal(path);
  ShardFile file{path, read_results_h5(path), {}, {}, {}, 0, {}};
  const auto kind = std::ranges::find_if(shard_tables, [&](const char* table) { return has_table_h5(path, table); });
  if (kind == std::end(shard_tables))
    throw InputError(path + ": holds no /sweep, /stability or /shard; expected the file of a sweep, stability or run shard");
  file.table = read_table_h5(path, *kind);
  if (std::string(*kind) == "/stability") file.evaluations = read_table_h5(path, "/stability/evaluations");
  read_shard_attributes(file);
  return file;
}

void merge_command(const MergeOptions& options) {
  if (!options.force && std::filesystem::exists(options.out))
    throw InputError(options.out + ": exists; pass --force to overwrite it");
  std::vector<ShardFile> files;
  for (const std::string& path : options.inputs) files.push_back(read_shard(path));
  const MergedFile merged = merge_shards(std::move(files));
  if (merged.tables.empty())
    write_results_h5(merged.results, options.out, options.force);
  else
    write_results_with_tables_h5(merged.results, merged.tables, options.out, options.force);
}

}  // namespace

void register_merge(CLI::App& app) {
  auto options = std::make_shared<MergeOptions>();
  CLI::App* merge = app.add_subcommand("merge", "Join the files of a sweep's or stability run's shards (--shard K/N) into one");
  merge->add_option("OUT", options->out, "The merged HDF5 file")->required();
  merge->add_option("IN", options->inputs, "Every shard's file")->required();
  merge->add_flag("--force", options->force, "Overwrite OUT if it exists");
  merge->callback([options] { merge_command(*options); });
}

}  // namespace fxbench

// Joining the files of a command's shards: see shard_merge.h.
#include "analysis/shard_merge.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <set>
#include <variant>

#include "common/errors.h"
#include "stats/pareto.h"

namespace fxbench {
namespace {

// Where a merged row comes from.
struct RowSource {
  std::size_t file = 0;
  std::size_t row = 0;
};

template <class T>
const T& attribute(const ShardFile& file, const std::string& name) {
  for (const auto& [key, value] : file.table.attributes)
    if (key == name && std::holds_alternative<T>(value)) return std::get<T>(value);
  throw InputError(file.path + ": " + file.table.path + ": missing attribute " + name +
                   "; expected a file written by sweep or stability with --shard");
}

// The column `name` of values of type T, of a shard's table or of the merged one (whose columns
// are the first shard's, so `path` names that file).
template <class T, class Table>
auto& column(Table& table, const std::string& path, const std::string& name) {
  for (auto& candidate : table.columns)
    if (candidate.name == name && std::holds_alternative<std::vector<T>>(candidate.values))
      return std::get<std::vector<T>>(candidate.values);
  throw InputError(path + ": " + table.path + ": missing column " + name + ", or not of the type written");
}

// The build that measured a file: shards of two builds never merge.
std::string build_of(const Provenance& provenance) {
  return provenance.fx2d_version + " " + provenance.fx2d_git_revision + " " + provenance.build_type + " " +
         provenance.compiler;
}

// Each column's name and type, in order: what gathering rows from several files relies on.
std::string layout_of(const H5Table& table) {
  std::string layout;
  for (const H5Column& column : table.columns) layout += column.name + ":" + std::to_string(column.values.index()) + " ";
  return layout;
}

void check_same_work(const std::vector<ShardFile>& files) {
  const ShardFile& first = files.front();
  std::set<int> shards;
  for (const ShardFile& file : files) {
    const auto refuse = [&](const std::string& what, const std::string& theirs, const std::string& ours) {
      throw InputError(file.path + ": " + what + " '" + theirs + "', but " + first.path + " has '" + ours + "'");
    };
    if (file.table.path != first.table.path) refuse("table", file.table.path, first.table.path);
    if (layout_of(file.table) != layout_of(first.table) ||
        (file.evaluations && layout_of(*file.evaluations) != layout_of(*first.evaluations)))
      refuse("columns", layout_of(file.table), layout_of(first.table));
    if (build_of(file.results.provenance) != build_of(first.results.provenance))
      refuse("build (revisions differ)", build_of(file.results.provenance), build_of(first.results.provenance));
    if (file.work_list != first.work_list) refuse("work list (scenes, engines or settings differ)", file.work_list, first.work_list);
    if (file.shard.count != first.shard.count) refuse("shard count", file.shard.text(), first.shard.text());
    if (!shards.insert(file.shard.index).second) throw InputError(file.path + ": shard " + file.shard.text() + " given twice");
  }
}

// Every work item once, in work-list order. Refuses an item two shards both ran and one none ran.
std::vector<RowSource> rows_in_order(const std::vector<ShardFile>& files) {
  std::map<std::int32_t, RowSource> by_item;
  for (std::size_t f = 0; f < files.size(); ++f) {
    const std::vector<std::int32_t>& items = column<std::int32_t>(files[f].table, files[f].path, "work_item");
    for (std::size_t row = 0; row < items.size(); ++row) {
      if (items[row] < 0 || items[row] >= files[f].work_items)
        throw InputError(files[f].path + ": work item " + std::to_string(items[row]) + " is outside the work list of " +
                         std::to_string(files[f].work_items));
      const auto [at, inserted] = by_item.try_emplace(items[row], RowSource{f, row});
      if (!inserted)
        throw InputError(files[f].path + ": work item " + std::to_string(items[row]) + " is also in " + files[at->second.file].path);
    }
  }
  const std::int32_t total = files.front().work_items;
  for (std::int32_t item = 0; item < total; ++item) {
    if (by_item.contains(item)) continue;
    std::string missing;
    for (int k = 1; k <= files.front().shard.count; ++k)
      if (std::ranges::none_of(files, [&](const ShardFile& file) { return file.shard.index == k; }))
        missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(files.front().shard.count);
    throw InputError("merge: work item " + std::to_string(item) + " of " + std::to_string(total) + " is in no file given" +
                     (missing.empty() ? "" : "; shards missing: " + missing));
  }
  std::vector<RowSource> rows;
  for (const auto& [item, source] : by_item) rows.push_back(source);
  return rows;
}

// The table `path` of every file, its rows gathered in `rows` order.
H5Table gathered(const std::vector<const H5Table*>& tables, const std::vector<RowSource>& rows) {
  H5Table merged{tables.front()->path, tables.front()->attributes, {}};
  for (const H5Column& first : tables.front()->columns) {
    H5Column out{first.name, first.units, {}};
    std::visit(
        [&](const auto& typed) {
          std::remove_cvref_t<decltype(typed)> values;
          for (const RowSource& source : rows) {
            const auto& from = std::get<std::remove_cvref_t<decltype(typed)>>(
                std::ranges::find(tables[source.file]->columns, first.name, &H5Column::name)->values);
            values.push_back(from.at(source.row));
          }
          out.values = std::move(values);
        },
        first.values);
    merged.columns.push_back(std::move(out));
  }
  return merged;
}

void set_attribute(H5Table& table, const std::string& name, std::variant<std::string, double, std::int32_t> value) {
  for (auto& [key, current] : table.attributes)
    if (key == name) current = value;
}

// Row i's run, `run_of[i]` of its file, appended to `results` in row order, with its scene where
// the scene first comes, as the unsharded command lists them.
void gather_runs(const std::vector<ShardFile>& files, const std::vector<RowSource>& rows,
                 const std::vector<std::size_t>& run_of, ResultSet& results) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ShardFile& file = files[rows[i].file];
    if (run_of[i] >= file.results.runs.size())
      throw InputError(file.path + ": a row names run " + std::to_string(run_of[i]) + ", which is not in /runs");
    results.runs.push_back(file.results.runs[run_of[i]]);
    const std::string& hash = results.runs.back().scene_hash;
    const auto scene = std::ranges::find(file.results.scenes, hash, &SceneRecord::hash);
    if (scene == file.results.scenes.end()) throw InputError(file.path + ": no /scenes entry for scene hash " + hash);
    if (std::ranges::find(results.scenes, hash, &SceneRecord::hash) == results.scenes.end()) results.scenes.push_back(*scene);
  }
}

// A sweep: the runs in the merged order, the run column pointing at them, and the fronts.
void merge_sweep(const std::vector<ShardFile>& files, const std::vector<RowSource>& rows, ResultSet& results,
                 H5Table& table) {
  std::vector<std::int32_t>& run = column<std::int32_t>(table, files.front().path, "run");
  gather_runs(files, rows, std::vector<std::size_t>(run.begin(), run.end()), results);
  std::iota(run.begin(), run.end(), 0);
  const std::vector<std::int32_t>& group = column<std::int32_t>(table, files.front().path, "pareto_group");
  const std::vector<double>& cost = column<double>(table, files.front().path, "ms_per_simulated_s");
  const std::vector<double>& error = column<double>(table, files.front().path, "primary_error");
  std::vector<ParetoPoint> points;
  for (std::size_t i = 0; i < rows.size(); ++i) points.push_back({group[i], cost[i], error[i]});
  const FrontMarks marks = mark_fronts(points);
  std::vector<std::uint8_t>& on_front = column<std::uint8_t>(table, files.front().path, "on_front");
  std::vector<std::int32_t>& front_rank = column<std::int32_t>(table, files.front().path, "front_rank");
  std::vector<std::int32_t>& dominated_by = column<std::int32_t>(table, files.front().path, "dominated_by");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    on_front[i] = marks.on_front[i] ? 1 : 0;
    front_rank[i] = marks.front_rank[i];
    dominated_by[i] = marks.dominated_by[i] ? static_cast<std::int32_t>(*marks.dominated_by[i]) : -1;
  }
}

// A stability table: each merged row's evaluations after the previous row's, pointing at it.
H5Table merged_evaluations(const std::vector<ShardFile>& files, const std::vector<RowSource>& rows, H5Table& table) {
  std::vector<const H5Table*> evaluation_tables;
  std::vector<RowSource> evaluation_rows;
  for (const ShardFile& file : files) evaluation_tables.push_back(&*file.evaluations);
  std::vector<std::int32_t>& first = column<std::int32_t>(table, files.front().path, "first_evaluation");
  const std::vector<std::int32_t>& count = column<std::int32_t>(table, files.front().path, "evaluation_count");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::size_t from = static_cast<std::size_t>(first[i]);
    first[i] = static_cast<std::int32_t>(evaluation_rows.size());
    for (std::size_t e = 0; e < static_cast<std::size_t>(count[i]); ++e) evaluation_rows.push_back({rows[i].file, from + e});
  }
  H5Table evaluations = gathered(evaluation_tables, evaluation_rows);
  std::vector<std::int32_t>& owner = column<std::int32_t>(evaluations, files.front().path, "row");
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t e = 0; e < static_cast<std::size_t>(count[i]); ++e)
      owner[static_cast<std::size_t>(first[i]) + e] = static_cast<std::int32_t>(i);
  return evaluations;
}

}  // namespace

void read_shard_attributes(ShardFile& file) {
  file.shard = parse_shard(attribute<std::string>(file, "shard"), file.path + ": attribute shard");
  file.work_items = attribute<std::int32_t>(file, "work_items");
  file.work_list = attribute<std::string>(file, "work_list");
}

MergedFile merge_shards(std::vector<ShardFile> files) {
  check_same_work(files);
  std::ranges::sort(files, {}, [](const ShardFile& file) { return file.shard.index; });
  const std::vector<RowSource> rows = rows_in_order(files);
  MergedFile merged;
  merged.results.provenance = files.front().results.provenance;
  if (files.front().table.path == "/shard") {
    // A run's shards: the runs in order make the file the unsharded run writes, /shard and all.
    std::vector<std::size_t> run_of;
    for (const RowSource& source : rows) run_of.push_back(source.row);
    gather_runs(files, rows, run_of, merged.results);
    return merged;
  }
  std::vector<const H5Table*> tables;
  for (const ShardFile& file : files) tables.push_back(&file.table);
  merged.tables.push_back(gathered(tables, rows));
  H5Table& table = merged.tables.front();
  set_attribute(table, "shard", std::string("1/1"));
  table.attributes.emplace_back("merged_shards", static_cast<std::int32_t>(files.size()));
  // The provenance is shard 1's; where every other shard ran is kept here, one "K/N host" each.
  std::string hosts;
  for (const ShardFile& file : files)
    hosts += (hosts.empty() ? "" : "; ") + file.shard.text() + " " + file.results.provenance.hostname;
  table.attributes.emplace_back("shard_hosts", hosts);
  if (files.front().evaluations)
    merged.tables.push_back(merged_evaluations(files, rows, table));
  else
    merge_sweep(files, rows, merged.results, table);
  return merged;
}

}  // namespace fxbench

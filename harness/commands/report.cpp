// `fx2d-bench report FILE.h5 [FILE.h5 ...] [--compare-json FILE] -o DIR [--force]`: one HTML page
// with charts of every file given, drawn by reports/render_report.py (matplotlib, h5py).
//
// Reads top to bottom: the options, the checks made before Python is started (every input is a
// readable file of a schema the renderer knows; DIR may be written), where the renderer lives,
// running it, then putting its output in place.
//
// Invariants: bad input is refused here, in one line, before anything is drawn; DIR is either the
// complete new report or left as it was: the page is rendered into a sibling directory that is
// renamed into place, and --force replaces only an empty directory or a previous report (one
// holding index.html), never any other directory a typo may name.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/compare.h"
#include "commands/commands.h"
#include "common/bounded_read.h"
#include "common/child_process.h"
#include "common/errors.h"
#include "storage/file_integrity.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* python = "/usr/bin/python3";
constexpr const char* debian_packages = "python3 python3-h5py python3-matplotlib";
// A nightly history file may carry its own root schema (harness/RESULTS_FORMAT.md, /history).
constexpr std::string_view history_schema_prefix = "fx2d-bench.history/";

// The renderer's exit codes (reports/render_report.py).
constexpr int renderer_bad_input = 2;
constexpr int renderer_missing_package = 3;

struct ReportOptions {
  std::vector<std::string> files;
  std::vector<std::string> compare_json;
  std::string out;
  bool force = false;
};

// --- the inputs -----------------------------------------------------------------------------------

// A result file (runs, sweeps, stability tables all share its layout) is read in full, so a
// damaged one is named here; a history file's layout is the renderer's to read.
void check_h5_input(const std::string& path) {
  require_regular_file(path, path);
  // A sealed file, result or history, is checked against its seal before libhdf5 opens it
  // (file_integrity.h). An unsealed result file is refused by read_results_h5; an unsealed history
  // file comes from an fx2d-bench older than the seal on history files and is still accepted.
  if (carries_h5_seal(path)) verify_h5_seal(path);
  const std::string schema = h5_root_schema(path);
  if (schema == results_schema) {
    read_results_h5(path);
    return;
  }
  if (schema.starts_with(history_schema_prefix)) return;
  throw InputError(path + ": schema '" + schema + "' is not one the report reads; expected " + results_schema +
                   " (run, sweep, stability) or " + std::string(history_schema_prefix) + "N");
}

void check_compare_json(const std::string& path) {
  const nlohmann::json report =
      nlohmann::json::parse(read_bounded_file(path, "the output of fx2d-bench compare --json"), nullptr, false);
  if (report.is_discarded()) throw InputError(path + ": not JSON; expected the output of fx2d-bench compare --json");
  if (!report.is_object() || report.value("schema", "") != compare_schema)
    throw InputError(path + ": expected a " + std::string(compare_schema) + " object (fx2d-bench compare --json)");
}

// DIR as an absolute path without a trailing separator, so that its parent is where it lives.
fs::path out_dir(const ReportOptions& options) {
  const fs::path out = fs::absolute(options.out).lexically_normal();
  return out.has_filename() ? out : out.parent_path();
}

// DIR may be created, or replaced with --force when it is empty or a previous report.
void check_out_dir(const ReportOptions& options) {
  const fs::path out = out_dir(options);
  const fs::path parent = out.parent_path();
  if (!fs::is_directory(parent)) throw InputError(options.out + ": no such directory " + parent.string());
  if (!fs::exists(out)) return;
  if (!fs::is_directory(out)) throw InputError(options.out + ": exists and is not a directory");
  if (fs::is_empty(out)) return;
  if (!options.force) throw InputError(options.out + ": exists and is not empty; pass --force to replace it");
  if (!fs::exists(out / "index.html"))
    throw InputError(options.out + ": holds no index.html, so it is not a previous report; refusing to replace it");
}

// --- the renderer ---------------------------------------------------------------------------------

// FX2D_REPORTS_DIR overrides the source tree's reports/, e.g. for an installed copy.
fs::path renderer_script() {
  const char* override_dir = std::getenv("FX2D_REPORTS_DIR");
  const fs::path script = fs::path(override_dir != nullptr && *override_dir != '\0' ? override_dir
                                                                                     : FX2D_SOURCE_DIR "/reports") /
                          "render_report.py";
  if (!fs::is_regular_file(script))
    throw InputError(script.string() + ": the report renderer is missing; set FX2D_REPORTS_DIR to the reports/ directory");
  return script;
}

struct Finished {
  int status = -1;  // exit status, -1 when killed by a signal
  std::string err;
};

// Runs argv[0] with the given arguments, stdout inherited, stderr collected.
Finished run_collecting_stderr(const std::vector<std::string>& arguments) {
  int pipe_ends[2];
  // Close-on-exec, so the child holds only its stderr's copy of the write end, and the read below
  // ends when the child does.
  if (pipe2(pipe_ends, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  int spawn_error = 0;
  const pid_t child = spawn_child(arguments, {.in = -1, .out = -1, .err = pipe_ends[1]}, spawn_error);
  close(pipe_ends[1]);
  Finished finished;
  if (child < 0) {
    close(pipe_ends[0]);
    throw InputError(arguments[0] + ": cannot run (" + std::strerror(spawn_error) + "); install Debian's " +
                     debian_packages);
  }
  char buffer[4096];
  for (ssize_t n; (n = read(pipe_ends[0], buffer, sizeof buffer)) != 0;) {
    if (n > 0) finished.err.append(buffer, static_cast<std::size_t>(n));
    else if (errno != EINTR) break;
  }
  close(pipe_ends[0]);
  finished.status = wait_for_child(child).exit_status;
  return finished;
}

std::string last_line(const std::string& text) {
  std::size_t end = text.find_last_not_of("\r\n");
  if (end == std::string::npos) return {};
  const std::size_t begin = text.rfind('\n', end);
  return text.substr(begin == std::string::npos ? 0 : begin + 1, end - (begin == std::string::npos ? 0 : begin + 1) + 1);
}

void render(const ReportOptions& options, const fs::path& into) {
  if (access(python, X_OK) != 0)
    throw InputError(std::string(python) + " not found; install Debian's " + debian_packages);
  // -B: no __pycache__ written into the source tree.
  std::vector<std::string> arguments{python, "-B", renderer_script().string()};
  arguments.insert(arguments.end(), options.files.begin(), options.files.end());
  for (const std::string& path : options.compare_json) arguments.insert(arguments.end(), {"--compare-json", path});
  arguments.insert(arguments.end(), {"-o", into.string()});
  const Finished finished = run_collecting_stderr(arguments);
  if (finished.status == 0) {
    std::cerr << finished.err;  // the renderer's warnings, if any
    return;
  }
  const std::string reason = last_line(finished.err);
  if (finished.status == renderer_bad_input || finished.status == renderer_missing_package) throw InputError(reason);
  throw std::runtime_error(reason.empty() ? "render_report.py failed with status " + std::to_string(finished.status)
                                          : reason);
}

void report_command(const ReportOptions& options) {
  for (const std::string& path : options.files) check_h5_input(path);
  for (const std::string& path : options.compare_json) check_compare_json(path);
  check_out_dir(options);

  const fs::path out = out_dir(options);
  const fs::path staging = out.parent_path() / (out.filename().string() + ".tmp." + std::to_string(getpid()));
  fs::remove_all(staging);
  try {
    render(options, staging);
    if (fs::exists(out)) fs::remove_all(out);
    fs::rename(staging, out);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
  std::cout << (out / "index.html").string() << '\n';
}

}  // namespace

void register_report(CLI::App& app) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* report = app.add_subcommand("report", "Render run, sweep, stability and history files into an HTML report");
  report->add_option("files", options->files, "HDF5 files written by run, sweep, stability or the nightly job");
  report->add_option("--compare-json", options->compare_json, "Output of fx2d-bench compare --json; repeatable");
  report->add_option("-o,--out", options->out, "Directory to write index.html and its charts into")->required();
  report->add_flag("--force", options->force, "Replace DIR when it holds a previous report");
  report->callback([options] {
    if (options->files.empty() && options->compare_json.empty())
      throw InputError("report: nothing to report; give at least one HDF5 file or --compare-json");
    report_command(*options);
  });
}

}  // namespace fxbench

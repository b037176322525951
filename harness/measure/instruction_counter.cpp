// Starting the counting child under callgrind and reading its count; invariants in
// instruction_counter.h.
#include "measure/instruction_counter.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/child_process.h"
#include "common/errors.h"
#include "measure/interrupt.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

// A private directory for one child's files, removed with everything in it.
class TemporaryDirectory {
 public:
  TemporaryDirectory() {
    std::string pattern = (fs::temp_directory_path() / "fx2d-bench-count.XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot create a temporary directory like " + pattern);
    path_ = pattern;
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  ~TemporaryDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Runs `arguments` (the program looked up on PATH), stdin from /dev/null, stdout and stderr both
// to `log`, and waits for it.
ChildEnding run_logged_child(const std::vector<std::string>& arguments, const fs::path& log) {
  const int null = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  ChildEnding ending{.spawn_error = errno, .exit_status = -1, .signal = 0};
  if (null >= 0 && out >= 0) ending = run_child(arguments, {.in = null, .out = out, .err = out});
  if (null >= 0) ::close(null);
  if (out >= 0) ::close(out);
  return ending;
}

// Started, as valgrind means it: 127 is the shell's "cannot execute".
bool started(const ChildEnding& ending) { return ending.started() && ending.exit_status != 127; }

std::string file_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

std::string last_line(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  std::string last;
  while (std::getline(lines, line))
    if (!line.empty()) last = line;
  return last;
}

std::string installed_valgrind_version(const fs::path& directory) {
  const fs::path log = directory / "version.txt";
  const ChildEnding ending = run_logged_child({"valgrind", "--version"}, log);
  const std::string version = last_line(file_text(log));
  if (!started(ending) || ending.exit_status != 0 || !version.starts_with("valgrind-"))
    throw InputError("--counter instructions: valgrind is not installed (no working 'valgrind' on PATH); "
                     "install it, e.g. apt-get install valgrind");
  return version;
}

// The first whitespace-separated number after `prefix` on a line that starts with it.
std::optional<std::uint64_t> number_after(const std::string& line, std::string_view prefix) {
  if (!line.starts_with(prefix)) return std::nullopt;
  const std::size_t start = line.find_first_not_of(' ', prefix.size());
  if (start == std::string::npos) return std::nullopt;
  std::uint64_t value = 0;
  const char* end = line.data() + line.size();
  const auto [stop, error] = std::from_chars(line.data() + start, end, value);
  if (error != std::errc() || (stop != end && *stop != ' ')) return std::nullopt;
  return value;
}

}  // namespace

std::uint64_t callgrind_total_instructions(std::istream& output, const std::string& origin) {
  std::optional<std::uint64_t> totals;
  std::optional<std::uint64_t> summary;
  bool counts_instructions = false;
  std::string line;
  while (std::getline(output, line)) {
    if (line.starts_with("events:")) {
      std::istringstream events(line.substr(7));
      std::string first;
      events >> first;
      counts_instructions = first == "Ir";
    }
    if (auto value = number_after(line, "totals:")) totals = value;
    if (auto value = number_after(line, "summary:")) summary = value;
  }
  if (!counts_instructions) throw std::runtime_error(origin + ": expected callgrind output whose first event is Ir");
  if (!totals && !summary) throw std::runtime_error(origin + ": no 'totals:' or 'summary:' line in callgrind output");
  return totals ? *totals : *summary;
}

InstructionCounter::InstructionCounter(std::string bench_executable) : bench_executable_(std::move(bench_executable)) {
  if (built_with_address_sanitizer)
    throw InputError("--counter instructions: this fx2d-bench is built with AddressSanitizer, which valgrind "
                     "cannot run; use a build without FX2D_SANITIZE");
  const TemporaryDirectory directory;
  valgrind_version_ = installed_valgrind_version(directory.path());
}

std::optional<InstructionCount> InstructionCounter::count(const SceneSpec& scene, const std::string& engine_name) const {
  if (scene.resolved_json.empty()) throw std::invalid_argument("InstructionCounter::count: the scene has no resolved JSON");
  const TemporaryDirectory directory;
  const fs::path scene_file = directory.path() / "scene.json";
  std::ofstream(scene_file, std::ios::binary) << scene.resolved_json;
  const fs::path callgrind_out = directory.path() / "callgrind.out";
  const fs::path log = directory.path() / "child.log";
  const ChildEnding ending =
      run_logged_child({"valgrind", "--tool=callgrind", "--quiet", "--collect-atstart=no", "--dump-line=no",
                 "--callgrind-out-file=" + callgrind_out.string(), bench_executable_, "count-instructions", "--engine",
                 engine_name, scene_file.string(), "--scene-hash", scene.hash},
                log);
  if (ending.signal != 0 && interrupt_requested()) return std::nullopt;  // interrupt.h: Ctrl-C reached the child too
  const std::string what = "counting instructions of " + engine_name + " on " + scene.name;
  if (!started(ending)) throw std::runtime_error(what + ": cannot start valgrind");
  if (ending.exit_status != 0) {
    // The child's own one-line message, "fx2d-bench: ...", says what it refused.
    const std::string reason = last_line(file_text(log));
    if (ending.exit_status == exit_bad_input) throw InputError(what + ": " + reason);
    throw std::runtime_error(what + ": the child " +
                             (ending.signal != 0 ? "ended by signal " + std::to_string(ending.signal)
                                                 : "exited with " + std::to_string(ending.exit_status)) +
                             (reason.empty() ? std::string() : ": " + reason));
  }
  std::ifstream output(callgrind_out);
  if (!output) throw std::runtime_error(what + ": callgrind wrote no " + callgrind_out.string());
  return InstructionCount{callgrind_total_instructions(output, callgrind_out.string()), scene.steps,
                          instruction_count_tool, valgrind_version_};
}

}  // namespace fxbench

// Tests of the nightly history (history_h5.h, `fx2d-bench history`): rows round-trip through the
// file; `history append` records the gate's verdicts, detected steps and the accepted flag; a
// foreign file is refused in one line; the file is sealed (file_integrity.h), a damaged one is
// refused before libhdf5 reads it, and an unsealed one from an older fx2d-bench is still read; and
// the file survives a crash during an append.
//
// Crash safety is tested on the real binary in a child process. The append stops itself (SIGSTOP)
// at a chosen stage when FX2D_HISTORY_TEST_STOP_AT names it ("read", "written", "synced",
// "renamed"), so a SIGKILL or SIGINT lands exactly there; a loop of SIGKILLs at random moments
// covers the moments between the stages, the HDF5 write itself among them. Whatever the moment,
// the history must read back whole with either its old N rows or N + k.
#include "storage/history_h5.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "tests/support/bench_process.h"
#include "common/errors.h"
#include "storage/file_integrity.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using bench_test::BenchProcess;
using bench_test::Ending;
using nlohmann::json;

HistoryRow sample_row(int index) {
  HistoryRow row;
  row.date_utc = "2024-05-0" + std::to_string(1 + index % 9) + "T02:00:00Z";
  row.candidate = "cand" + std::to_string(index);
  row.baseline = "base";
  row.engine = index % 2 == 0 ? "fx2d" : "box2d";
  row.scene = "pile";
  row.bodies = 600 + index;
  row.metric = index % 3 == 0 ? "instructions_per_step" : "ms_per_step";
  row.a = 1.0 + index;
  row.b = 1.5 + index;
  row.ratio = row.b / row.a;
  row.ci_low = row.ratio - 0.01;
  row.ci_high = row.ratio + 0.01;
  row.p_value = row.metric == "ms_per_step" ? 0.001 * index : std::nan("");
  row.verdict = index % 2 == 0 ? "slower" : "control: no change";
  row.step_detected = index % 2 == 0;
  row.accepted = index == 4;
  return row;
}

void expect_same(const HistoryRow& x, const HistoryRow& y) {
  EXPECT_EQ(x.date_utc, y.date_utc);
  EXPECT_EQ(x.candidate, y.candidate);
  EXPECT_EQ(x.baseline, y.baseline);
  EXPECT_EQ(x.engine, y.engine);
  EXPECT_EQ(x.scene, y.scene);
  EXPECT_EQ(x.bodies, y.bodies);
  EXPECT_EQ(x.metric, y.metric);
  EXPECT_EQ(x.a, y.a);
  EXPECT_EQ(x.b, y.b);
  EXPECT_EQ(x.ratio, y.ratio);
  EXPECT_EQ(x.ci_low, y.ci_low);
  EXPECT_EQ(x.ci_high, y.ci_high);
  EXPECT_EQ(std::isnan(x.p_value), std::isnan(y.p_value));
  if (!std::isnan(x.p_value)) {
    EXPECT_EQ(x.p_value, y.p_value);
  }
  EXPECT_EQ(x.verdict, y.verdict);
  EXPECT_EQ(x.step_detected, y.step_detected);
  EXPECT_EQ(x.accepted, y.accepted);
}

// A comparison of `rows` pairs of gating rows: fx2d 10% slower (significant), Box2D unchanged.
json comparison(int pairs) {
  json rows = json::array();
  for (int i = 0; i < pairs; ++i) {
    for (const char* engine : {"fx2d", "box2d"}) {
      const bool slower = std::string(engine) == "fx2d";
      const double ratio = slower ? 1.1 : 1.0;
      rows.push_back({{"engine", engine}, {"scene", "pile"}, {"bodies", 600 + i}, {"metric", "ms_per_step"},
                      {"a", 1.0}, {"b", ratio}, {"ratio", ratio}, {"ci_low", ratio - 0.005},
                      {"ci_high", ratio + 0.005}, {"p_value", slower ? 0.001 : 0.8}, {"repeats_a", 10},
                      {"repeats_b", 10}, {"verdict", slower ? "slower" : "no change"}});
    }
  }
  return {{"schema", "fx2d-bench.compare/1"}, {"mode", "ab"}, {"rows", rows}};
}

class HistoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("fx2d_history_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    unsetenv("FX2D_HISTORY_TEST_STOP_AT");
    fs::remove_all(directory_);
  }

  std::string history() const { return (directory_ / "history.h5").string(); }

  std::string bytes_of(const std::string& path) const {
    std::ifstream file(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(file), {}};
  }

  std::string write_bytes(const std::string& name, const std::string& bytes) const {
    const std::string path = (directory_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  std::string compare_file(int pairs) const {
    const fs::path path = directory_ / ("compare_" + std::to_string(pairs) + ".json");
    if (!fs::exists(path)) std::ofstream(path) << comparison(pairs).dump();
    return path.string();
  }

  std::vector<std::string> append_arguments(int pairs, const std::string& candidate) const {
    return {"history", "append", history(), "--compare", compare_file(pairs), "--candidate", candidate,
            "--baseline", "base", "--date", "2024-05-01T02:00:00Z"};
  }

  Ending append(int pairs, const std::string& candidate, std::vector<std::string> extra = {}) const {
    std::vector<std::string> arguments = append_arguments(pairs, candidate);
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return bench_test::run_bench(arguments, directory_);
  }

  // Names in the directory other than the history, the comparisons and the child's output.
  std::vector<std::string> leftovers() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(directory_)) {
      const std::string name = entry.path().filename().string();
      if (name != "history.h5" && !name.starts_with("compare_") && name != "stdout.txt" && name != "stderr.txt")
        names.push_back(name);
    }
    return names;
  }

  fs::path directory_;
};

// Blocks until the child has stopped itself (true) or ended (false), without reaping it.
bool wait_until_stopped(pid_t pid) {
  siginfo_t info{};
  if (waitid(P_PID, static_cast<id_t>(pid), &info, WSTOPPED | WEXITED | WNOWAIT) != 0) return false;
  return info.si_code == CLD_STOPPED;
}

// --- the file -------------------------------------------------------------------------------------

TEST_F(HistoryTest, RowsRoundTripThroughTwoAppends) {
  std::vector<HistoryRow> rows;
  for (int i = 0; i < 5; ++i) rows.push_back(sample_row(i));
  append_history_h5(history(), std::span(rows).first(2));
  append_history_h5(history(), std::span(rows).subspan(2));
  const std::vector<HistoryRow> read = read_history_h5(history());
  ASSERT_EQ(read.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) expect_same(read[i], rows[i]);
  EXPECT_TRUE(leftovers().empty());
}

TEST_F(HistoryTest, EmptyAppendMakesAnEmptyButValidHistory) {
  append_history_h5(history(), {});
  EXPECT_TRUE(read_history_h5(history()).empty());
}

TEST_F(HistoryTest, ForeignAndBrokenFilesAreRefusedInOneLine) {
  std::ofstream(directory_ / "text.h5") << "not a history";
  for (const std::string& path : {(directory_ / "text.h5").string(), (directory_ / "absent.h5").string()}) {
    try {
      read_history_h5(path);
      ADD_FAILURE() << path;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    }
  }
  // An append to a file that is not a history refuses, and leaves the file as it was.
  EXPECT_THROW(append_history_h5((directory_ / "text.h5").string(), std::vector<HistoryRow>{sample_row(0)}), InputError);
  std::ifstream kept(directory_ / "text.h5");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "not a history");
}

// --- the seal -------------------------------------------------------------------------------------

// The message of the InputError read_history_h5(path) throws, or "" if it reads the file.
std::string read_error(const std::string& path) {
  try {
    read_history_h5(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST_F(HistoryTest, AppendWritesASealedHistoryThatReadsBack) {
  const std::vector<HistoryRow> rows{sample_row(0), sample_row(1), sample_row(2)};
  append_history_h5(history(), rows);
  EXPECT_TRUE(carries_h5_seal(history()));
  EXPECT_NO_THROW(verify_h5_seal(history()));  // the seal covers the bytes that were renamed into place
  const std::vector<HistoryRow> read = read_history_h5(history());
  ASSERT_EQ(read.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) expect_same(read[i], rows[i]);
}

TEST_F(HistoryTest, DamagedSealedHistoryIsRefusedInOneLineBeforeLibhdf5ReadsIt) {
  const std::vector<HistoryRow> rows{sample_row(0), sample_row(1)};
  append_history_h5(history(), rows);
  const std::string whole = bytes_of(history());
  std::vector<std::string> damaged;
  // The first byte libhdf5 reads, one in the middle, the last: each a change libhdf5 itself may
  // not notice (the middle one lands in string or number data), so only the seal can refuse it.
  for (const std::size_t at : {h5_seal_bytes, (h5_seal_bytes + whole.size()) / 2, whole.size() - 1}) {
    std::string flipped = whole;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x20);
    damaged.push_back(write_bytes("flipped_" + std::to_string(at) + ".h5", flipped));
  }
  for (const std::size_t length : {whole.size() / 2, whole.size() - 1})
    damaged.push_back(write_bytes("truncated_" + std::to_string(length) + ".h5", whole.substr(0, length)));
  for (const std::string& path : damaged) {
    const std::string message = read_error(path);
    EXPECT_TRUE(message.starts_with(path + ": corrupt or truncated (")) << path << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    // An append to it refuses too, and leaves it as it was.
    const std::string before = bytes_of(path);
    EXPECT_THROW(append_history_h5(path, rows), InputError) << path;
    EXPECT_TRUE(bytes_of(path) == before) << path << " was changed";
  }
  // Through the binary: exit code 2, one line naming the file.
  const Ending shown = bench_test::run_bench({"history", "show", damaged.front()}, directory_);
  EXPECT_EQ(shown.exit_code, 2) << shown.err;
  EXPECT_EQ(std::ranges::count(shown.err, '\n'), 1) << shown.err;
  EXPECT_NE(shown.err.find(damaged.front() + ": corrupt or truncated (checksum mismatch)"), std::string::npos)
      << shown.err;
}

TEST_F(HistoryTest, UnsealedHistoryOfAnOlderBenchIsReadAndSealedByTheNextAppend) {
  const std::vector<HistoryRow> rows{sample_row(0), sample_row(1), sample_row(2), sample_row(3)};
  append_history_h5(history(), std::span(rows).first(2));
  // The HDF5 file proper without its user block: a plain HDF5 file, as fx2d-bench wrote history
  // files before it sealed them (libhdf5 finds the superblock at byte 0 instead of 512).
  const std::string unsealed = write_bytes("old.h5", bytes_of(history()).substr(h5_seal_bytes));
  ASSERT_FALSE(carries_h5_seal(unsealed));
  std::vector<HistoryRow> read = read_history_h5(unsealed);
  ASSERT_EQ(read.size(), 2u);
  for (std::size_t i = 0; i < read.size(); ++i) expect_same(read[i], rows[i]);

  append_history_h5(unsealed, std::span(rows).subspan(2));
  EXPECT_TRUE(carries_h5_seal(unsealed));
  EXPECT_NO_THROW(verify_h5_seal(unsealed));
  read = read_history_h5(unsealed);
  ASSERT_EQ(read.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) expect_same(read[i], rows[i]);
}

// --- the command ----------------------------------------------------------------------------------

TEST_F(HistoryTest, AppendRecordsTheGateVerdictsStepsAndAcceptance) {
  const fs::path policy = fs::path(FX2D_SOURCE_DIR) / "ci" / "gating.json";
  Ending ending = append(2, "abc123", {"--policy", policy.string()});
  ASSERT_EQ(ending.exit_code, 0) << ending.err;
  ending = append(2, "def456", {"--policy", policy.string(), "--accepted"});
  ASSERT_EQ(ending.exit_code, 0) << ending.err;
  const std::vector<HistoryRow> rows = read_history_h5(history());
  ASSERT_EQ(rows.size(), 8u);
  EXPECT_EQ(rows[0].engine, "fx2d");
  EXPECT_EQ(rows[0].verdict, "slower");
  EXPECT_TRUE(rows[0].step_detected);
  EXPECT_EQ(rows[1].verdict, "control: no change");  // box2d is a control in ci/gating.json
  EXPECT_FALSE(rows[1].step_detected);
  EXPECT_FALSE(rows[0].accepted);
  EXPECT_TRUE(rows[7].accepted);
  EXPECT_EQ(rows[7].candidate, "def456");

  const Ending shown = bench_test::run_bench({"history", "show", history(), "--last", "1", "--json"}, directory_);
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  const json parsed = json::parse(shown.out);
  EXPECT_EQ(parsed["schema"], "fx2d-bench.history/1");
  EXPECT_EQ(parsed["rows"].size(), 8u);  // both appends carry the same --date: one night
}

// The report and `show --last` read the dates back: only dates that exist, in ISO 8601 UTC.
TEST_F(HistoryTest, AppendRefusesADateThatIsNotAnIso8601UtcDate) {
  const auto append_on = [this](const char* date) {
    std::vector<std::string> arguments = append_arguments(1, "abc123");
    arguments.back() = date;  // the value of --date
    return bench_test::run_bench(arguments, directory_);
  };
  for (const char* date : {"yesterday", "2026-13-45T99:99:99Z", "2026-02-30", "2026-11-25T24:00:00Z", "2026-11-25 02:17",
                           "2026-11-25T02:17:00"}) {
    const Ending ending = append_on(date);
    EXPECT_EQ(ending.exit_code, 2) << date << ": " << ending.err;
    EXPECT_EQ(std::ranges::count(ending.err, '\n'), 1) << ending.err;
    EXPECT_NE(ending.err.find(std::string("--date: expected an ISO 8601 UTC date, YYYY-MM-DD or YYYY-MM-DDTHH:MM:SSZ, got '") +
                              date + "'"),
              std::string::npos)
        << ending.err;
  }
  EXPECT_FALSE(fs::exists(history()));
  for (const char* date : {"2024-02-29", "2026-11-25T02:17:00Z"}) {
    const Ending ending = append_on(date);
    ASSERT_EQ(ending.exit_code, 0) << date << ": " << ending.err;
    EXPECT_EQ(read_history_h5(history()).back().date_utc, date);
  }
}

// Each misuse of `history` is one line naming what is wrong, exit code 2 (never 4).
TEST_F(HistoryTest, EveryMisuseIsOneLineAndExitCodeTwo) {
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/pile.json";
  const std::string compare = compare_file(1);
  const std::vector<std::pair<std::vector<std::string>, std::string>> misuses = {
      {{"history", "append", history(), "--compare", scene, "--candidate", "c", "--baseline", "b"},
       scene + ": expected a fx2d-bench.compare/1 object"},  // wrong file type
      {{"history", "append", history(), "--compare", compare, "--baseline", "b"}, "--candidate is required"},
      {{"history", "append", history(), "--compare", compare, "--candidate", "c", "--baseline", "b",
        "--policy", scene},
       scene + ":11:3: /bounds: unknown key"},  // a scene as the policy
      {{"history", "show", compare}, compare},  // JSON as the history
      {{"history", "show", history(), "--last", "0"}, "--last"},
      {{"history"}, "A subcommand is required"},  // missing argument
  };
  for (const auto& [arguments, expected] : misuses) {
    const Ending ending = bench_test::run_bench(arguments, directory_);
    EXPECT_EQ(ending.exit_code, 2) << ending.err;
    EXPECT_EQ(std::ranges::count(ending.err, '\n'), 1) << ending.err;
    EXPECT_NE(ending.err.find(expected), std::string::npos) << ending.err;
  }
}

TEST_F(HistoryTest, ShowRefusesAResultFileInOneLine) {
  std::ofstream(directory_ / "junk.h5") << "junk";
  const Ending ending = bench_test::run_bench({"history", "show", (directory_ / "junk.h5").string()}, directory_);
  EXPECT_EQ(ending.exit_code, 2);
  EXPECT_EQ(std::ranges::count(ending.err, '\n'), 1) << ending.err;
}

// --- crash safety ---------------------------------------------------------------------------------

// Starts `arguments` (an append) with the hook that makes it stop itself at `stage`.
BenchProcess start_stopped_at(const std::vector<std::string>& arguments, const char* stage, const fs::path& directory) {
  setenv("FX2D_HISTORY_TEST_STOP_AT", stage, 1);
  BenchProcess child(arguments, directory);
  unsetenv("FX2D_HISTORY_TEST_STOP_AT");
  return child;
}

TEST_F(HistoryTest, SigkillAtEveryStageLeavesTheOldOrTheNewHistory) {
  ASSERT_EQ(append(3, "night0").exit_code, 0);
  std::size_t rows = read_history_h5(history()).size();
  ASSERT_EQ(rows, 6u);
  for (const char* stage : {"read", "written", "synced", "renamed"}) {
    const BenchProcess child = start_stopped_at(append_arguments(3, stage), stage, directory_);
    ASSERT_TRUE(wait_until_stopped(child.pid())) << stage << ": the append did not stop there";
    child.send(SIGKILL);
    EXPECT_EQ(child.finish().signal, SIGKILL);
    const std::size_t after = read_history_h5(history()).size();  // throws, failing the test, if broken
    const std::size_t expected = std::string(stage) == "renamed" ? rows + 6 : rows;
    EXPECT_EQ(after, expected) << "killed at " << stage;
    rows = after;
    for (const std::string& name : leftovers()) EXPECT_TRUE(name.starts_with("history.h5.tmp.")) << name;
  }
}

TEST_F(HistoryTest, SigkillAtRandomMomentsNeverBreaksTheHistory) {
  // A history big enough that writing it takes a while: the kills land inside the HDF5 write too.
  constexpr int pairs = 1500;
  ASSERT_EQ(append(pairs, "seed").exit_code, 0);
  const auto started = std::chrono::steady_clock::now();
  ASSERT_EQ(append(pairs, "timed").exit_code, 0);
  const double append_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  std::size_t rows = read_history_h5(history()).size();
  ASSERT_EQ(rows, 4u * pairs);

  std::mt19937 random(20240501);
  std::uniform_real_distribution<double> moment(0.0, 1.2 * append_ms);
  int killed_before_done = 0;
  for (int attempt = 0; attempt < 12; ++attempt) {
    const BenchProcess child(append_arguments(pairs, "kill" + std::to_string(attempt)), directory_);
    std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long>(1000 * moment(random))));
    child.send(SIGKILL);
    if (child.finish().signal == SIGKILL) ++killed_before_done;
    const std::size_t after = read_history_h5(history()).size();
    EXPECT_TRUE(after == rows || after == rows + 2 * pairs) << "attempt " << attempt << ": " << after << " rows";
    rows = after;
  }
  EXPECT_GT(killed_before_done, 0) << "no kill landed before an append finished (" << append_ms << " ms each)";
}

// Runs the append `arguments`, interrupted (SIGINT) where it stopped itself at `stage`.
Ending interrupted_at(const std::vector<std::string>& arguments, const char* stage, const fs::path& directory) {
  const BenchProcess child = start_stopped_at(arguments, stage, directory);
  EXPECT_TRUE(wait_until_stopped(child.pid())) << "the append did not stop at " << stage;
  child.send(SIGINT);
  child.send(SIGCONT);
  return child.finish();
}

TEST_F(HistoryTest, SigintBeforeTheRenameLeavesTheOldHistoryAndExits130) {
  ASSERT_EQ(append(3, "night0").exit_code, 0);
  const Ending ending = interrupted_at(append_arguments(3, "interrupted"), "written", directory_);
  EXPECT_EQ(ending.exit_code, 130) << ending.err;
  EXPECT_NE(ending.err.find("is unchanged"), std::string::npos) << ending.err;
  EXPECT_EQ(read_history_h5(history()).size(), 6u);
  EXPECT_TRUE(leftovers().empty()) << "the interrupted append removes its temporary file";
}

TEST_F(HistoryTest, SigintAfterTheRenameKeepsTheCompletedAppend) {
  ASSERT_EQ(append(3, "night0").exit_code, 0);
  const Ending ending = interrupted_at(append_arguments(3, "late"), "renamed", directory_);
  EXPECT_EQ(ending.exit_code, 0) << ending.err;
  EXPECT_EQ(read_history_h5(history()).size(), 12u);
}

}  // namespace
}  // namespace fxbench

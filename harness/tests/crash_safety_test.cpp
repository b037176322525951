// Crash safety of `fx2d-bench run --out X`, tested on the real binary in a child process that is
// killed or interrupted at chosen moments: during the measurement, and during the final write
// (aimed at by watching for the writer's temporary file, `X.tmp.<pid>`, results_h5.h).
//
// What must hold whenever the child is stopped:
// - X is absent or a complete result file that reads back; it is never half-written;
// - an X that existed before a `--force` run is intact until the new one replaces it whole;
// - after SIGINT, exit code 130 and what was measured so far in X.partial.h5, marked partial,
//   holding whole repeats only; a SIGINT that arrives once measuring is over changes nothing;
// - a second SIGINT ends the process at once, without finishing any write;
// - the only thing a SIGKILL can leave behind is the clearly named X.tmp.<pid> of a write it
//   cut short, which later runs ignore (each writes its own X.tmp.<its pid>).
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bench_process.h"
#include "results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

using bench_test::BenchProcess;
using bench_test::Ending;

// Measuring takes about 2 s (fx2d about 350 ms a repeat, then Box2D about 100 ms), so that the
// kill points below land at different stages: start-up, first repeat, later repeats, Box2D.
const std::vector<std::string> long_measurement{"run", "pile", "--engine", "fx2d,box2d", "--steps", "200",
                                                "--repeats", "4", "--warmup", "0"};
constexpr int long_measurement_repeats = 4;
constexpr int long_measurement_steps = 200;

// A cheap scene stepped 50,000 times with every sample kept: measuring takes about 1 s and writing
// the 9 MB file about 100 ms, a window a poll every 0.2 ms cannot miss.
std::vector<std::string> long_write() {
  const std::string scene = (fs::path(FX2D_SOURCE_DIR) / "scenes" / "tests" / "single_box_on_ground.json").string();
  return {"run", scene, "--engine", "fx2d", "--steps", "50000", "--repeats", "1", "--warmup", "0",
          "--hash-every", "1", "--accuracy-every", "1"};
}

class CrashSafetyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("fx2d_crash_safety_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  fs::path out() const { return directory_ / "result.h5"; }
  fs::path partial_out() const { return directory_ / "result.h5.partial.h5"; }

  BenchProcess start(std::vector<std::string> arguments, bool force = false) const {
    arguments.insert(arguments.end(), {"--out", out().string()});
    if (force) arguments.emplace_back("--force");
    return BenchProcess(std::move(arguments), directory_);
  }

  // Runs `arguments --out X [--force]` and sends `signal` after `delay`.
  Ending run_and_signal(std::vector<std::string> arguments, int signal, milliseconds delay, bool force = false) const {
    const BenchProcess child = start(std::move(arguments), force);
    std::this_thread::sleep_for(delay);
    child.send(signal);
    return child.finish();
  }

  // Runs `arguments --out X [--force]` and sends each of `signals`, `gap` apart, as soon as the
  // writer's temporary file appears. False in `caught_writing` if the child ended before it did.
  Ending signal_during_write(std::vector<std::string> arguments, const std::vector<int>& signals, bool force,
                             bool& caught_writing, milliseconds gap = milliseconds(0)) const {
    const BenchProcess child = start(std::move(arguments), force);
    const fs::path temporary = directory_ / ("result.h5.tmp." + std::to_string(child.pid()));
    caught_writing = false;
    const auto give_up = Clock::now() + std::chrono::seconds(60);
    while (!caught_writing && Clock::now() < give_up && child.running()) {
      caught_writing = fs::exists(temporary);
      if (!caught_writing) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    for (const int signal : signals) {
      child.send(signal);
      std::this_thread::sleep_for(gap);
    }
    return child.finish();
  }

  // Names in the directory other than X, X.partial.h5 and the child's captured output.
  std::vector<std::string> leftovers() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(directory_)) {
      const std::string name = entry.path().filename().string();
      if (entry.path() != out() && entry.path() != partial_out() && name != "stdout.txt" && name != "stderr.txt")
        names.push_back(name);
    }
    return names;
  }

  fs::path directory_;
};

// A complete file of the long measurement: both engines, every repeat, every sample.
void expect_complete_long_measurement(const ResultSet& results) {
  EXPECT_FALSE(results.partial);
  ASSERT_EQ(results.runs.size(), 2u);
  for (const RunRecord& run : results.runs) {
    EXPECT_EQ(run.repeats, long_measurement_repeats) << run.engine;
    EXPECT_EQ(run.wall_ms.size(), std::size_t{long_measurement_repeats * long_measurement_steps}) << run.engine;
  }
}

// A partial file: marked so, every run whole but possibly the last, which has whole repeats only.
void expect_valid_partial_long_measurement(const ResultSet& results) {
  EXPECT_TRUE(results.partial);
  ASSERT_LE(results.runs.size(), 2u);
  for (std::size_t k = 0; k < results.runs.size(); ++k) {
    const RunRecord& run = results.runs[k];
    EXPECT_GE(run.repeats, 1) << run.engine;
    if (k + 1 < results.runs.size()) {
      EXPECT_EQ(run.repeats, long_measurement_repeats) << run.engine;
    }
    const auto samples = static_cast<std::size_t>(run.repeats) * long_measurement_steps;
    EXPECT_EQ(run.wall_ms.size(), samples) << run.engine;
    EXPECT_EQ(run.cycles.size(), samples) << run.engine;
    EXPECT_EQ(run.contacts.size(), samples) << run.engine;
    EXPECT_EQ(run.phase_ms.size(), samples * run.phase_names.size()) << run.engine;
    EXPECT_EQ(run.final_state_hash.size(), 16u) << "the first repeat, which sets it, is always whole";
  }
}

TEST_F(CrashSafetyTest, SigkillDuringMeasurementLeavesNoResultAndNothingButATemporaryFile) {
  for (const int ms : {50, 200, 500, 1000, 1700}) {
    const Ending ending = run_and_signal(long_measurement, SIGKILL, milliseconds(ms));
    if (ending.signal == 0) {  // the machine was quick enough to finish first
      EXPECT_EQ(ending.exit_code, 0) << ms << " ms: " << ending.err;
      expect_complete_long_measurement(read_results_h5(out().string()));
      fs::remove(out());
      continue;
    }
    EXPECT_EQ(ending.signal, SIGKILL);
    EXPECT_FALSE(fs::exists(out())) << "killed after " << ms << " ms";
    EXPECT_FALSE(fs::exists(partial_out())) << "a SIGKILL saves nothing";
    // The one thing allowed: a kill that happened to land in the few milliseconds of the write.
    for (const std::string& name : leftovers()) {
      EXPECT_TRUE(name.starts_with("result.h5.tmp.")) << "killed after " << ms << " ms, left " << name;
      fs::remove(directory_ / name);
    }
  }
}

TEST_F(CrashSafetyTest, SigkillDuringTheFinalWriteLeavesNoResultOnlyAClearlyNamedTemporaryFile) {
  bool caught_writing = false;
  const Ending killed = signal_during_write(long_write(), {SIGKILL}, false, caught_writing);
  ASSERT_TRUE(caught_writing) << "the write was not seen: " << killed.err;
  EXPECT_EQ(killed.signal, SIGKILL);
  if (fs::exists(out())) {
    // The kill landed between the rename and the exit: then the file is whole.
    EXPECT_EQ(read_results_h5(out().string()).runs.size(), 1u);
  } else {
    ASSERT_EQ(leftovers().size(), 1u);
    EXPECT_TRUE(leftovers().front().starts_with("result.h5.tmp.")) << leftovers().front();
  }

  // The leftover does not stand in a later run's way, which writes and renames its own.
  const Ending later = start({"run", "stacks", "--engine", "box2d", "--steps", "5", "--repeats", "1"}, true).finish();
  ASSERT_EQ(later.exit_code, 0) << later.err;
  EXPECT_EQ(read_results_h5(out().string()).runs.front().engine, "box2d");
  EXPECT_LE(leftovers().size(), 1u) << "the later run left no temporary file of its own";
}

TEST_F(CrashSafetyTest, SigintSavesWholeRepeatsUnderAPartialNameAndExits130) {
  int partial_saves = 0;
  for (const int ms : {50, 200, 500, 1000, 1700}) {
    const Ending ending = run_and_signal(long_measurement, SIGINT, milliseconds(ms));
    EXPECT_TRUE(leftovers().empty()) << leftovers().front();
    if (ending.signal == SIGINT || ending.exit_code == 0) {
      // Before the handler was installed, during start-up, the default action: nothing written.
      // After the process had finished: the complete result.
      EXPECT_FALSE(fs::exists(partial_out()));
      EXPECT_EQ(fs::exists(out()), ending.exit_code == 0) << "SIGINT after " << ms << " ms";
      if (ending.exit_code == 0) expect_complete_long_measurement(read_results_h5(out().string()));
      fs::remove(out());
      continue;
    }
    ASSERT_EQ(ending.exit_code, 130) << "SIGINT after " << ms << " ms: " << ending.err;
    EXPECT_FALSE(fs::exists(out())) << "a partial result never takes the final name";
    EXPECT_EQ(std::count(ending.err.begin(), ending.err.end(), '\n'), 1) << ending.err;
    EXPECT_NE(ending.err.find(partial_out().string()), std::string::npos) << ending.err;
    const ResultSet partial = read_results_h5(partial_out().string());
    expect_valid_partial_long_measurement(partial);
    if (!partial.runs.empty()) ++partial_saves;
    fs::remove(partial_out());
  }
  EXPECT_GE(partial_saves, 1) << "no SIGINT landed after a whole repeat; the machine is far slower than assumed";
}

TEST_F(CrashSafetyTest, SigintOnceMeasuringIsOverStillWritesTheFullResult) {
  bool caught_writing = false;
  const Ending ending = signal_during_write(long_write(), {SIGINT}, false, caught_writing);
  ASSERT_TRUE(caught_writing) << ending.err;
  EXPECT_EQ(ending.exit_code, 0) << ending.err;
  const ResultSet results = read_results_h5(out().string());
  EXPECT_FALSE(results.partial);
  ASSERT_EQ(results.runs.size(), 1u);
  EXPECT_EQ(results.runs.front().wall_ms.size(), 50'000u);
  EXPECT_FALSE(fs::exists(partial_out()));
  EXPECT_TRUE(leftovers().empty()) << leftovers().front();
}

TEST_F(CrashSafetyTest, SecondSigintEndsTheProcessAtOnceWithoutFinishingTheWrite) {
  bool caught_writing = false;
  // 10 ms apart, so the first has been handled (two pending SIGINTs would merge into one), and
  // well inside the ~100 ms write, which the first alone would let finish (the test above).
  const Ending ending = signal_during_write(long_write(), {SIGINT, SIGINT}, false, caught_writing, milliseconds(10));
  ASSERT_TRUE(caught_writing) << ending.err;
  EXPECT_EQ(ending.exit_code, 130) << ending.err;
  EXPECT_TRUE(ending.err.empty()) << "_exit at once, nothing printed: " << ending.err;
  EXPECT_FALSE(fs::exists(out())) << "the write was not finished";
  EXPECT_FALSE(fs::exists(partial_out()));
}

class ExistingResultTest : public CrashSafetyTest {
 protected:
  void SetUp() override {
    CrashSafetyTest::SetUp();
    const Ending first = start({"run", "stacks", "--engine", "box2d", "--steps", "5", "--repeats", "1"}).finish();
    ASSERT_EQ(first.exit_code, 0) << first.err;
    existing_ = read_results_h5(out().string());
  }

  // X is the old file, bit for bit in what it says, or (only if the rename happened) a whole new one.
  void expect_old_or_whole_new(const std::string& when, bool new_allowed) const {
    ASSERT_TRUE(fs::exists(out())) << when << ": the existing result was lost";
    const ResultSet now = read_results_h5(out().string());
    if (now == existing_) return;
    EXPECT_TRUE(new_allowed) << when << ": the existing result was replaced by an unfinished run";
    expect_complete_long_measurement(now);
  }

  ResultSet existing_;
};

TEST_F(ExistingResultTest, SigkillOfAForcedRunNeverLosesTheExistingResult) {
  for (const int ms : {50, 200, 500, 1000, 1700}) {
    const Ending ending = run_and_signal(long_measurement, SIGKILL, milliseconds(ms), true);
    expect_old_or_whole_new("SIGKILL after " + std::to_string(ms) + " ms", ending.signal == 0);
  }
  const ResultSet before = read_results_h5(out().string());  // a run above may have finished
  bool caught_writing = false;
  const Ending killed = signal_during_write(long_write(), {SIGKILL}, true, caught_writing);
  ASSERT_TRUE(caught_writing) << killed.err;
  ASSERT_TRUE(fs::exists(out()));
  const ResultSet now = read_results_h5(out().string());
  if (now != before) {
    EXPECT_EQ(now.runs.front().wall_ms.size(), 50'000u) << "replaced, so whole";
  }
}

TEST_F(ExistingResultTest, SigintOfAForcedRunKeepsTheExistingResultAndSavesBesideIt) {
  const Ending ending = run_and_signal(long_measurement, SIGINT, milliseconds(500), true);
  ASSERT_EQ(ending.exit_code, 130) << ending.err;
  expect_old_or_whole_new("SIGINT after 500 ms", false);
  expect_valid_partial_long_measurement(read_results_h5(partial_out().string()));
}

}  // namespace
}  // namespace fxbench

// Crash safety of `fx2d-bench run --out X`, tested on the real binary in a child process that is
// killed or interrupted at chosen moments: during the measurement (at later and later moments, from
// the start to past the end, whatever the machine's speed), and during the final write (aimed at by
// watching for the writer's temporary file, `X.tmp.<pid>`, results_h5.h).
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
#include <string.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/bench_process.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

using bench_test::BenchProcess;
using bench_test::Ending;

// Measuring takes about 0.3 s in Release (start-up about 0.1 s, then 4 fx2d repeats, then Box2D) and
// several times that under the sanitizers or on a loaded machine; the sweeps below (sweep_signal)
// follow its pace to signal in each stage. Short, because each sweep runs it about ten times.
const std::vector<std::string> long_measurement{"run", "pile", "--engine", "fx2d,box2d", "--steps", "100",
                                                "--repeats", "4", "--warmup", "0"};
constexpr int long_measurement_repeats = 4;
constexpr int long_measurement_steps = 100;

// A cheap scene stepped 50,000 times with every sample kept: measuring takes about 1 s and writing
// the 9 MB file about 100 ms, a window a poll every 0.2 ms does not miss, but which a loaded machine
// may not let the test act in; see write_pause.
std::vector<std::string> long_write() {
  const std::string scene = (fs::path(FX2D_SOURCE_DIR) / "scenes" / "tests" / "single_box_on_ground.json").string();
  return {"run", scene, "--engine", "fx2d", "--steps", "50000", "--repeats", "1", "--warmup", "0",
          "--hash-every", "1", "--accuracy-every", "1"};
}

// A complete file of the long measurement: both engines, every repeat, every sample.
void expect_complete_long_measurement(const ResultSet& results) {
  EXPECT_FALSE(results.partial);
  ASSERT_EQ(results.runs.size(), 2u);
  for (const RunRecord& run : results.runs) {
    EXPECT_EQ(run.repeats, long_measurement_repeats) << run.engine;
    EXPECT_EQ(run.wall_ms.size(), std::size_t{long_measurement_repeats * long_measurement_steps}) << run.engine;
  }
}

// A partial file: marked so, every run with whole repeats only. The two engines take their repeats
// in rounds (fx2d box2d, box2d fx2d, ...), so neither is more than one repeat ahead of the other.
void expect_valid_partial_long_measurement(const ResultSet& results) {
  EXPECT_TRUE(results.partial);
  ASSERT_LE(results.runs.size(), 2u);
  if (results.runs.size() == 2) {
    EXPECT_LE(std::abs(results.runs[0].repeats - results.runs[1].repeats), 1);
  }
  for (const RunRecord& run : results.runs) {
    EXPECT_GE(run.repeats, 1) << run.engine;
    EXPECT_LE(run.repeats, long_measurement_repeats) << run.engine;
    const auto samples = static_cast<std::size_t>(run.repeats) * long_measurement_steps;
    EXPECT_EQ(run.wall_ms.size(), samples) << run.engine;
    EXPECT_EQ(run.cycles.size(), samples) << run.engine;
    EXPECT_EQ(run.contacts.size(), samples) << run.engine;
    EXPECT_EQ(run.phase_ms.size(), samples * run.phase_names.size()) << run.engine;
    EXPECT_EQ(run.final_state_hash.size(), 16u) << "the first repeat, which sets it, is always whole";
  }
}

// The test-only pause the atomic writer makes between a complete, synced temporary file and the
// rename (atomic_file.cpp), set for the runs signalled during their write: the signals then land
// before the rename even when the test is scheduled late, and a second SIGINT 200 ms after the
// first is still in the write. Most land earlier, in the write proper, when the machine is idle.
const std::string write_pause = "FX2D_ATOMIC_FILE_TEST_PAUSE_MS=2000";

// How a sweep (CrashSafetyTest::sweep_signal) reports one run: how it ended, when it was signalled
// (for messages), and whether it ended by itself before the signal was due.
struct SignalledRun {
  Ending ending;
  std::string when;
  bool ended_first = false;
};

class CrashSafetyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("fx2d_crash_safety_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  fs::path out() const { return directory_ / "result.h5"; }
  fs::path partial_out() const { return directory_ / "result.h5.partial.h5"; }

  BenchProcess start(std::vector<std::string> arguments, bool force = false,
                     std::vector<std::string> environment = {}) const {
    arguments.insert(arguments.end(), {"--out", out().string()});
    if (force) arguments.emplace_back("--force");
    return BenchProcess(std::move(arguments), directory_, std::move(environment));
  }

  // Runs `arguments --out X [--force]` again and again, sending `signal` at a later moment each
  // time, and hands each run to `check`, until `check` says it has seen enough. Fixed delays would
  // assume one machine's speed (a sanitizer build on a loaded machine is several times slower than
  // Release), so the moments follow the run's own pace: 50 ms after the start, then twice as late
  // each time (one signal lands in every stage that ends over twice as late as it begins), up to a
  // run that ends before its signal is due. If `check` wants more after that one, the sweep goes on
  // at 0.6 of that run's length, where whole repeats are done and measuring is not (start-up and
  // the first repeat take about 40% of a whole run, in Release and under the sanitizers alike).
  void sweep_signal(const std::vector<std::string>& arguments, int signal, bool force,
                    const std::function<bool(const SignalledRun&)>& check) const {
    constexpr int max_runs = 20;
    auto delay = milliseconds(50);
    for (int k = 0; k < max_runs; ++k) {
      const BenchProcess child = start(arguments, force);
      const bool ended_first = !runs_for(child, delay);
      if (!ended_first) child.send(signal);
      const std::string when = std::string(strsignal(signal)) + " after " + std::to_string(delay.count()) + " ms";
      const SignalledRun run{child.finish(), when, ended_first};
      if (check(run)) return;
      delay = ended_first ? milliseconds(static_cast<long>(600 * run.ending.seconds)) : 2 * delay;
    }
    ADD_FAILURE() << "after " << max_runs << " runs signalled at growing moments, the sweep did not see what it needs";
  }

  // Waits `duration` or until `child` ends, whichever comes first (then within a millisecond, so
  // that its Ending's seconds say how long a whole run takes); true if it is still running.
  static bool runs_for(const BenchProcess& child, milliseconds duration) {
    const auto deadline = Clock::now() + duration;
    while (child.running()) {
      if (Clock::now() >= deadline) return true;
      std::this_thread::sleep_for(milliseconds(1));
    }
    return false;
  }

  // Runs `arguments --out X [--force]` and sends each of `signals`, `gap` apart, as soon as the
  // writer's temporary file appears. False in `caught_writing` if the child ended before it did.
  Ending signal_during_write(std::vector<std::string> arguments, const std::vector<int>& signals, bool force,
                             bool& caught_writing, milliseconds gap = milliseconds(0)) const {
    const BenchProcess child = start(std::move(arguments), force, {write_pause});
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

  // X after a SIGKILL: absent, or (the kill landed between the rename and the exit) whole.
  void expect_no_result_or_a_complete_one(const std::string& when) const {
    if (fs::exists(out())) expect_complete_long_measurement(read_results_h5(out().string()));
    EXPECT_FALSE(fs::exists(partial_out())) << when << ": a SIGKILL saves nothing";
    // The one thing allowed besides: a kill that landed in the write leaves its temporary file.
    for (const std::string& name : leftovers()) {
      EXPECT_TRUE(name.starts_with("result.h5.tmp.")) << when << ", left " << name;
      fs::remove(directory_ / name);
    }
  }

  // A SIGINT outside the handler's lifetime takes the default action: before it was installed, in
  // start-up, nothing is written yet; after it was removed, at the very end, X is already whole. A
  // SIGINT that came once the process had finished changed nothing either.
  static bool ended_untouched_by_sigint(const Ending& ending) {
    return ending.signal == SIGINT || ending.exit_code == 0;
  }

  // What a SIGINT at any moment leaves beside X (the callers check X itself). Returns whether it
  // saved whole repeats under X.partial.h5.
  bool expect_sigint_outcome(const SignalledRun& run) const {
    const Ending& ending = run.ending;
    EXPECT_TRUE(leftovers().empty()) << run.when << ": " << leftovers().front();
    if (ended_untouched_by_sigint(ending)) {
      EXPECT_FALSE(fs::exists(partial_out())) << run.when;
      return false;
    }
    if (ending.exit_code != 130) {
      ADD_FAILURE() << run.when << ": exit code " << ending.exit_code << ", signal " << ending.signal << ": "
                    << ending.err;
      return false;
    }
    EXPECT_EQ(std::count(ending.err.begin(), ending.err.end(), '\n'), 1) << ending.err;
    EXPECT_NE(ending.err.find(partial_out().string()), std::string::npos) << ending.err;
    const ResultSet partial = read_results_h5(partial_out().string());
    expect_valid_partial_long_measurement(partial);
    fs::remove(partial_out());
    return !partial.runs.empty();
  }

  fs::path directory_;
};

TEST_F(CrashSafetyTest, SigkillDuringMeasurementLeavesNoResultAndNothingButATemporaryFile) {
  sweep_signal(long_measurement, SIGKILL, false, [&](const SignalledRun& run) {
    if (run.ending.signal == 0) {  // the run ended before the kill
      EXPECT_EQ(run.ending.exit_code, 0) << run.when << ": " << run.ending.err;
      expect_complete_long_measurement(read_results_h5(out().string()));
    } else {
      EXPECT_EQ(run.ending.signal, SIGKILL) << run.when;
      expect_no_result_or_a_complete_one(run.when);
    }
    fs::remove(out());
    return run.ended_first;
  });
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
  sweep_signal(long_measurement, SIGINT, false, [&](const SignalledRun& run) {
    if (expect_sigint_outcome(run)) ++partial_saves;
    if (run.ending.exit_code == 0 || fs::exists(out())) {
      EXPECT_TRUE(ended_untouched_by_sigint(run.ending)) << run.when << ": a partial result never takes the final name";
      expect_complete_long_measurement(read_results_h5(out().string()));
    }
    fs::remove(out());
    return run.ended_first && partial_saves >= 1;
  });
  EXPECT_GE(partial_saves, 1) << "no SIGINT landed after a whole repeat";
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
  // 200 ms apart, so the first has been handled (two pending SIGINTs would merge into one) even on a
  // loaded machine, and well inside the write and its test pause, which the first alone would let
  // finish (the test above).
  const Ending ending = signal_during_write(long_write(), {SIGINT, SIGINT}, false, caught_writing, milliseconds(200));
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

  // X is the old file, bit for bit in what it says, or (only if the rename happened) a whole new
  // one, which is then the existing result the next run must keep.
  void expect_old_or_whole_new(const std::string& when, bool new_allowed) {
    ASSERT_TRUE(fs::exists(out())) << when << ": the existing result was lost";
    const ResultSet now = read_results_h5(out().string());
    if (now == existing_) return;
    EXPECT_TRUE(new_allowed) << when << ": the existing result was replaced by an unfinished run";
    expect_complete_long_measurement(now);
    existing_ = now;
  }

  ResultSet existing_;
};

TEST_F(ExistingResultTest, SigkillOfAForcedRunNeverLosesTheExistingResult) {
  sweep_signal(long_measurement, SIGKILL, true, [&](const SignalledRun& run) {
    // A kill between the rename and the exit may leave the new file: then it is whole.
    expect_old_or_whole_new(run.when, true);
    return run.ended_first;
  });
  const ResultSet before = read_results_h5(out().string());  // the sweep's last run finished
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
  bool interrupted_measuring = false;
  sweep_signal(long_measurement, SIGINT, true, [&](const SignalledRun& run) {
    expect_sigint_outcome(run);
    expect_old_or_whole_new(run.when, ended_untouched_by_sigint(run.ending));
    interrupted_measuring = run.ending.exit_code == 130;
    return interrupted_measuring;
  });
  EXPECT_TRUE(interrupted_measuring) << "no SIGINT landed once the handler was installed";
}

}  // namespace
}  // namespace fxbench

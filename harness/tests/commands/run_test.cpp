// Tests of `fx2d-bench run`: the order statistics and aggregation rules of the summary, the
// measurement loop's sampling and determinism check, the JSON summary of a tiny deterministic run
// against a golden file, and the built binary end to end (output, exit codes, the HDF5 file).
//
// The summary golden is goldens/summary_small.json; its timing figures are masked, everything
// else (accuracy figures, hashes, contact counts, schema) is compared exactly. Regenerate it,
// after a deliberate change to the summary or to an engine's physics, only with:
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/run_test --gtest_filter='*Golden*'
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "analysis/summary.h"
#include "format/summary_format.h"
#include "measure/interleave.h"
#include "measure/runner.h"
#include "stats/statistics.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

TEST(Spread, OddSampleHasTheMiddleValueAsMedian) {
  const std::vector<double> sample{3.0, 9.0, 1.0, 2.0, 5.0};
  const Spread spread = spread_of(sample);
  EXPECT_EQ(spread.median, 3.0);
  EXPECT_EQ(spread.min, 1.0);
  EXPECT_EQ(spread.max, 9.0);
}

TEST(Spread, EvenSampleAveragesTheMiddlePair) {
  const std::vector<double> sample{4.0, 1.0, 10.0, 2.0};
  EXPECT_EQ(spread_of(sample).median, 3.0);
}

TEST(Spread, EmptySampleIsAllZero) {
  const Spread spread = spread_of({});
  EXPECT_EQ(spread.median, 0.0);
  EXPECT_EQ(spread.min, 0.0);
  EXPECT_EQ(spread.max, 0.0);
  EXPECT_EQ(mean_of({}), 0.0);
}

TEST(Spread, MeanOfSampleIsItsSumOverCount) {
  const std::vector<double> sample{1.0, 2.0, 6.0};
  EXPECT_EQ(mean_of(sample), 3.0);
}

// Three repeats of two steps whose per-repeat means are 2, 6 and 4: aggregates are taken across
// repeats, so the median is 4 and min-max 2-6, although single steps range from 1 to 7.
RunRecord three_repeat_record() {
  RunRecord run;
  run.steps = 2;
  run.repeats = 3;
  run.wall_ms = {1.0, 3.0, 5.0, 7.0, 4.0, 4.0};
  run.cpu_ms = {1.0, 1.0, 3.0, 3.0, 2.0, 2.0};
  run.cycles = {10, 30, 50, 70, 40, 40};
  run.contacts = {0, 2, 0, 2, 0, 2};
  run.phase_names = {"collide", "solve"};
  run.phase_ms = {0.5, 1.5, 0.5, 1.5, 1.0, 3.0, 1.0, 3.0, 2.0, 2.0, 2.0, 2.0};
  AccuracySample early;
  early.step = 1;
  early.max_penetration = 0.02;
  early.mean_penetration = 0.01;
  early.kinetic_energy = 50.0;
  early.nan = 1;
  AccuracySample late;
  late.step = 2;
  late.max_penetration = 0.01;
  late.mean_penetration = 0.005;
  late.max_displacement = 3.0;
  late.max_lateral_drift = 0.5;
  late.kinetic_energy = 2.0;
  late.escaped = 4;
  run.accuracy = {early, late};
  return run;
}

TEST(Summary, TimingsAreAggregatedAcrossRepeatMeans) {
  const RunSummary summary = summarise(three_repeat_record());
  EXPECT_EQ(summary.ms_per_step.median, 4.0);
  EXPECT_EQ(summary.ms_per_step.min, 2.0);
  EXPECT_EQ(summary.ms_per_step.max, 6.0);
  EXPECT_EQ(summary.cpu_ms_per_step.median, 2.0);
  EXPECT_EQ(summary.cycles_per_step.median, 40.0);
  EXPECT_EQ(summary.contacts_mean, 1.0);
  ASSERT_EQ(summary.phases_ms.size(), 2u);
  EXPECT_EQ(summary.phases_ms[0].first, "collide");
  EXPECT_EQ(summary.phases_ms[0].second, 1.0);  // repeat means 0.5, 1, 2
  EXPECT_EQ(summary.phases_ms[1].first, "solve");
  EXPECT_EQ(summary.phases_ms[1].second, 2.0);  // repeat means 1.5, 3, 2
}

TEST(Summary, AccuracyIsTheWorstSampleButKineticEnergyIsTheLast) {
  const AccuracySample worst = summarise(three_repeat_record()).worst;
  EXPECT_EQ(worst.max_penetration, 0.02);
  EXPECT_EQ(worst.mean_penetration, 0.01);
  EXPECT_EQ(worst.max_displacement, 3.0);
  EXPECT_EQ(worst.max_lateral_drift, 0.5);
  EXPECT_EQ(worst.escaped, 4);
  EXPECT_EQ(worst.nan, 1);
  EXPECT_EQ(worst.kinetic_energy, 2.0);
}

// Two boxes and two circles dropped onto a ground box: contacts, tumbling and settling within
// 30 steps, small enough to run on every engine in milliseconds.
SceneSpec small_scene() {
  SceneSpec scene;
  scene.name = "summary_small";
  scene.hash = "5a5a5a5a5a5a5a5a";
  scene.size = 4;
  scene.steps = 30;
  BodySpec ground;
  ground.type = BodyType::static_body;
  ground.half_extents = {10.0, 0.5};
  ground.position = {0.0, -0.5};
  scene.bodies.push_back(ground);
  for (int i = 0; i < 4; ++i) {
    BodySpec body;
    body.shape = i % 2 == 0 ? ShapeKind::box : ShapeKind::circle;
    body.position = {-1.5 + 1.0 * i, 0.6 + 0.3 * i};
    body.angle = 0.1 * i;
    scene.bodies.push_back(body);
  }
  return scene;
}

ResultSet small_results(const RunPlan& plan) {
  const SceneSpec scene = small_scene();
  ResultSet results;
  results.scenes.push_back({scene.name, scene.hash, scene.resolved_json, scene.source_path, "penetration"});
  for (const EngineInfo& engine : engine_registry()) results.runs.push_back(measure_engine(scene, engine, plan));
  return results;
}

TEST(MeasureEngine, SamplesEveryNthStepAndTheLast) {
  RunPlan plan;
  plan.repeats = 2;
  plan.accuracy_every = 7;
  plan.hash_every = 10;
  const RunRecord run = measure_engine(small_scene(), engine_registry().front(), plan);
  // 30 steps: accuracy after 7, 14, 21, 28 and 30; hashes after 10, 20 and 30.
  ASSERT_EQ(run.accuracy.size(), 5u);
  EXPECT_EQ(run.accuracy.front().step, 7);
  EXPECT_EQ(run.accuracy[3].step, 28);
  EXPECT_EQ(run.accuracy.back().step, 30);
  ASSERT_EQ(run.state_hashes.size(), 3u);
  EXPECT_EQ(run.final_state_hash, run.state_hashes.back());
  EXPECT_EQ(run.wall_ms.size(), 60u);
  EXPECT_EQ(run.cycles.size(), 60u);
  EXPECT_EQ(run.contacts.size(), 60u);
  EXPECT_EQ(run.phase_ms.size(), 60u * run.phase_names.size());
  EXPECT_EQ(run.body_count, 5);
  EXPECT_EQ(run.bodies, 4);
}

TEST(MeasureEngine, EveryEngineRepeatsItsTrajectoryExactly) {
  RunPlan plan;
  plan.repeats = 3;
  plan.warmup_steps = 5;
  for (const RunRecord& run : small_results(plan).runs) EXPECT_TRUE(run.deterministic) << run.engine;
}

TEST(MeasureEngine, ProgressIsReportedForWarmupEachRepeatAndTheEnd) {
  RunPlan plan;
  plan.repeats = 2;
  plan.warmup_steps = 5;
  std::vector<RunProgress> reports;
  measure_engine(small_scene(), engine_registry().front(), plan, [&](const RunProgress& p) { reports.push_back(p); });
  ASSERT_EQ(reports.size(), 4u);
  EXPECT_EQ(reports[0].repeat, 0);
  EXPECT_EQ(reports[1].repeat, 1);
  EXPECT_EQ(reports[1].steps_done, 5);
  EXPECT_EQ(reports[2].repeat, 2);
  EXPECT_EQ(reports[3].steps_done, planned_steps(small_scene(), plan));
}

TEST(EngineRounds, VisitTheEnginesForwardThenBackward) {
  std::string order;
  for (int turn = 0; turn < 9; ++turn) order += static_cast<char>('A' + cell_of_turn(turn, 3));
  EXPECT_EQ(order, "ABCCBAABC");
  std::string alone;
  for (int turn = 0; turn < 3; ++turn) alone += static_cast<char>('A' + cell_of_turn(turn, 1));
  EXPECT_EQ(alone, "AAA");
}

// Several engines timed in rounds: each gets the record measure_engine gives it alone (samples,
// accuracy, hashes: every repeat is the same trajectory), and each new instance is built in the
// order of the rounds, so no engine's repeats all fall before another's.
TEST(EngineRounds, EachEngineGetsTheRecordItWouldGetAloneInTurnOrder) {
  const SceneSpec scene = small_scene();
  RunPlan plan;
  plan.repeats = 3;
  plan.warmup_steps = 4;
  std::string built;
  std::vector<EngineInfo> logged;
  for (const EngineInfo& engine : engine_registry()) {
    if (!engine.unavailable.empty() || logged.size() == 2) continue;
    EngineInfo copy = engine;
    copy.make = [&built, make = engine.make, tag = static_cast<char>('A' + logged.size())] {
      built += tag;
      return make();
    };
    logged.push_back(copy);
  }
  ASSERT_EQ(logged.size(), 2u);
  const TimedCell cells[] = {{&scene, &logged[0]}, {&scene, &logged[1]}};
  const InterleavePlan rounds{plan.repeats, 0.0, plan.warmup_steps, plan.hash_every, plan.accuracy_every};
  const RoundRobinRuns runs = measure_round_robin(cells, rounds);
  // A warm-up instance, then a timed one, in each engine's first round.
  EXPECT_EQ(built, "AABBBAAB");
  ASSERT_EQ(runs.runs.size(), 2u);
  EXPECT_FALSE(runs.interrupted);
  for (std::size_t e = 0; e < 2; ++e) {
    const RunRecord alone = measure_engine(scene, logged[e], plan);
    const RunRecord& interleaved = runs.runs[e];
    EXPECT_EQ(interleaved.engine, alone.engine);
    EXPECT_EQ(interleaved.repeats, 3);
    EXPECT_EQ(interleaved.wall_ms.size(), alone.wall_ms.size());
    EXPECT_EQ(interleaved.phase_ms.size(), alone.phase_ms.size());
    EXPECT_EQ(interleaved.contacts, alone.contacts);
    EXPECT_EQ(interleaved.state_hashes, alone.state_hashes);
    EXPECT_EQ(interleaved.final_state_hash, alone.final_state_hash);
    EXPECT_EQ(interleaved.accuracy.size(), alone.accuracy.size());
    EXPECT_TRUE(interleaved.deterministic);
  }
}

// Replaces every timing figure by a placeholder: they differ from run to run, the rest must not.
void mask_timings(nlohmann::ordered_json& summary) {
  for (auto& run : summary["runs"])
    for (const char* key : {"ms_per_step", "cpu_ms_per_step", "cycles_per_step", "phases_ms"})
      for (auto& [name, value] : run[key].items()) value = "<timing>";
  for (auto& figure : summary["machine"]) figure = "<timing>";
}

TEST(SummaryJson, SmallRunMatchesGoldenApartFromTimings) {
  RunPlan plan;
  plan.repeats = 2;
  // Ordered, so the golden keeps the summary's key order and a reordering shows as a change.
  nlohmann::ordered_json summary = summary_json(small_results(plan));
  mask_timings(summary);
  const fs::path golden = fs::path(FX2D_SOURCE_DIR) / "goldens" / "summary_small.json";
  if (std::getenv("FX2D_UPDATE_GOLDENS") != nullptr) {
    std::ofstream(golden) << summary.dump(2) << '\n';
    GTEST_SKIP() << "rewrote " << golden;
  }
  std::ifstream file(golden);
  ASSERT_TRUE(file) << golden << " is missing; regenerate it as the comment at the top of this file says";
  const auto expected = nlohmann::ordered_json::parse(file);
  EXPECT_EQ(summary, expected) << "differences (JSON patch from golden to actual): "
                               << nlohmann::ordered_json::diff(expected, summary).dump(2);
}

// ---------------------------------------------------------------------------------------------
// The built binary, end to end.

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

class BinaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("fx2d_run_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  Outcome bench(const std::string& arguments) const {
    const fs::path err = directory_ / "stderr.txt";
    const std::string command = std::string(FX2D_BENCH_EXE) + " " + arguments + " 2>" + err.string();
    Outcome outcome;
    FILE* pipe = popen(command.c_str(), "r");
    if (pipe == nullptr) return outcome;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) outcome.out.append(buffer, n);
    const int status = pclose(pipe);
    outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream err_file(err);
    outcome.err.assign(std::istreambuf_iterator<char>(err_file), {});
    return outcome;
  }

  // Exit code 2 and exactly one line on stderr, prefixed with the program's name.
  static void expect_one_line_input_error(const Outcome& outcome, const std::string& mentions) {
    EXPECT_EQ(outcome.exit_code, 2);
    EXPECT_TRUE(outcome.err.starts_with("fx2d-bench: ")) << outcome.err;
    EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1) << outcome.err;
    EXPECT_NE(outcome.err.find(mentions), std::string::npos) << outcome.err;
    EXPECT_TRUE(outcome.out.empty()) << outcome.out;
  }

  static std::string test_scene(const std::string& name) {
    return (fs::path(FX2D_SOURCE_DIR) / "scenes" / "tests" / (name + ".json")).string();
  }

  fs::path directory_;
};

TEST_F(BinaryTest, JsonSummaryCoversAllFourEnginesWithFiniteFigures) {
  const Outcome outcome = bench("run pile --bodies 20 --steps 20 --repeats 1 --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_TRUE(outcome.err.empty()) << "stderr is not a terminal, so no progress bar: " << outcome.err;
  const Json summary = Json::parse(outcome.out);
  EXPECT_EQ(summary["schema"], "fx2d-bench.summary/1");
  ASSERT_EQ(summary["runs"].size(), 4u);
  const std::vector<std::string> engines{"fx2d", "box2d", "ode", "chipmunk"};
  for (std::size_t i = 0; i < engines.size(); ++i) {
    const Json& run = summary["runs"][i];
    EXPECT_EQ(run["engine"], engines[i]);
    EXPECT_EQ(run["scene"], "pile");
    EXPECT_EQ(run["bodies"], 20);
    EXPECT_EQ(run["steps"], 20);
    EXPECT_EQ(run["repeats"], 1);
    EXPECT_EQ(run["accuracy"]["nan"], 0) << engines[i];
    EXPECT_EQ(run["primary_metric"], "penetration");
    EXPECT_EQ(run["state_hash"].get<std::string>().size(), 16u);
    for (const char* key : {"median", "min", "max"}) {
      const double ms = run["ms_per_step"][key];
      EXPECT_TRUE(std::isfinite(ms) && ms > 0.0) << engines[i] << " " << key << " " << ms;
    }
    EXPECT_TRUE(std::isfinite(run["cycles_per_step"]["median"].get<double>()));
  }
}

TEST_F(BinaryTest, TableHasAHeaderAndOneRowPerEngine) {
  const Outcome outcome = bench("run " + test_scene("single_box_on_ground") + " --engine box2d,fx2d --steps 5 --repeats 1");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_EQ(std::count(outcome.out.begin(), outcome.out.end(), '\n'), 3) << outcome.out;
  // Registry order, whatever order --engine named them in.
  EXPECT_LT(outcome.out.find("\nfx2d "), outcome.out.find("\nbox2d ")) << outcome.out;
}

// A scene file that lists its bodies has no size parameter: its results count its dynamic bodies
// (the box, not the ground it rests on), never 0.
TEST_F(BinaryTest, SceneWithoutASizeCountsItsDynamicBodies) {
  const Outcome outcome = bench("run " + test_scene("single_box_on_ground") + " --engine fx2d --steps 5 --repeats 1 --json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_EQ(Json::parse(outcome.out)["runs"][0]["bodies"], 1) << outcome.out;
}

TEST_F(BinaryTest, MissingSceneFileIsAnInputError) {
  expect_one_line_input_error(bench("run " + (directory_ / "nosuch.json").string()), "nosuch.json");
}

TEST_F(BinaryTest, UnknownEngineIsAnInputError) {
  expect_one_line_input_error(bench("run --engine nosuch"), "nosuch");
}

TEST_F(BinaryTest, ZeroRepeatsIsAnInputError) { expect_one_line_input_error(bench("run --repeats 0"), "--repeats"); }

TEST_F(BinaryTest, ExistingOutFileWithoutForceIsRefusedBeforeMeasuring) {
  const fs::path out = directory_ / "existing.h5";
  std::ofstream(out) << "keep me";
  expect_one_line_input_error(bench("run --out " + out.string()), "--force");
  std::ifstream kept(out);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "keep me");
}

TEST_F(BinaryTest, OutFileReadsBackWithEveryRunAndSample) {
  const fs::path out = directory_ / "small.h5";
  const Outcome outcome = bench("run " + test_scene("single_box_on_ground") +
                                " --steps 20 --repeats 2 --warmup 0 --accuracy-every 5 --json --out " + out.string());
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const ResultSet results = read_results_h5(out.string());
  ASSERT_EQ(results.runs.size(), 4u);
  ASSERT_EQ(results.scenes.size(), 1u);
  EXPECT_EQ(results.scenes.front().primary_metric, "displacement");
  EXPECT_FALSE(results.provenance.cpu_model.empty());
  EXPECT_GT(results.provenance.tsc_ghz, 0.0);
  for (const RunRecord& run : results.runs) {
    EXPECT_EQ(run.wall_ms.size(), 40u) << run.engine;
    EXPECT_EQ(run.cycles.size(), 40u) << run.engine;
    EXPECT_EQ(run.accuracy.size(), 4u) << run.engine;  // after steps 5, 10, 15, 20
    EXPECT_EQ(run.warmup_steps, 0);
    EXPECT_TRUE(run.deterministic) << run.engine;
  }
  // The same run printed as JSON names the same final states as the file holds, and the same
  // machine: how long a cache line took between two cores and back, where there are two.
  const Json summary = Json::parse(outcome.out);
  for (std::size_t i = 0; i < results.runs.size(); ++i)
    EXPECT_EQ(summary["runs"][i]["state_hash"], results.runs[i].final_state_hash);
  EXPECT_EQ(summary["machine"]["core_round_trip_ns_start"].get<double>(),
            results.provenance.core_round_trip_ns_start);
  EXPECT_EQ(summary["machine"]["core_round_trip_ns_end"].get<double>(),
            results.provenance.core_round_trip_ns_end);
  EXPECT_EQ(results.provenance.core_round_trip_ns_start > 0.0, std::thread::hardware_concurrency() >= 2);
  EXPECT_EQ(results.provenance.core_round_trip_ns_end > 0.0, std::thread::hardware_concurrency() >= 2);
}

TEST_F(BinaryTest, EnginesListsEveryEngineOnePerLine) {
  const Outcome outcome = bench("engines");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_EQ(std::count(outcome.out.begin(), outcome.out.end(), '\n'), 4) << outcome.out;
  const Json listing = Json::parse(bench("engines --json").out);
  ASSERT_EQ(listing["engines"].size(), 4u);
  EXPECT_EQ(listing["engines"][0]["name"], "fx2d");
}

}  // namespace
}  // namespace fxbench

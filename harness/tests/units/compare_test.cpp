// Tests of `fx2d-bench compare` on result files built in memory with known differences and
// written with write_results_h5: the verdict of each row, the exit codes 0/1/2/3, the refusal of
// different scenes, the provenance warnings, accuracy regressions ("faster, less accurate"),
// same/changed physics, the cross-engine view, the command-line wiring, and the JSON, Markdown
// and terminal outputs against golden files.
//
// The goldens are goldens/compare_*.{json,md,txt}. They are deterministic (the bootstrap has a
// fixed seed). Regenerate them, after a deliberate change of method or format, only with:
//   FX2D_UPDATE_GOLDENS=1 <build>/harness/tests/compare_test --gtest_filter='*Golden*'
#include "analysis/compare.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <utility>

#include "commands/commands.h"
#include "commands/compare.h"
#include "format/compare_format.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* pile_hash = "1111111111111111";
constexpr const char* stacks_hash = "2222222222222222";
constexpr int steps = 40;

// Step s of repeat r costs scale * (0.5 + 0.01 s) ms, the growth of a settling scene, times a
// +-0.6% factor per repeat (the machine's state) and a +-0.3% factor per step, patterns that
// `noise_phase` shifts so that two runs never share their noise. A repeat's median step (the
// figure compare judges) is thus within +-0.9% of its noiseless value, and the ratio of two
// runs' medians within 1.009 / 0.991 = 1.8% of the true ratio. Phases split the step 40/60, cycles count at
// 2.2 GHz, and accuracy is one sample at the last step.
RunRecord synthetic_run(const std::string& engine, const std::string& scene, double scale, int noise_phase,
                        int repeats = 8) {
  RunRecord run;
  run.engine = engine;
  run.engine_version = "1.0";
  run.scene = scene;
  run.scene_hash = scene == "pile" ? pile_hash : stacks_hash;
  run.bodies = scene == "pile" ? 300 : 50;
  run.body_count = run.bodies + 1;
  run.steps = steps;
  run.repeats = repeats;
  run.hash_every = 20;
  run.phase_names = {"collide", "solve"};
  for (int r = 0; r < repeats; ++r) {
    for (int s = 0; s < steps; ++s) {
      const double repeat_noise = 0.006 * (((r * 5 + noise_phase) % 7) - 3) / 3.0;
      const double step_noise = 0.003 * (((r * 7 + s * 3 + noise_phase) % 11) - 5) / 5.0;
      const double ms = scale * (0.5 + 0.01 * s) * (1.0 + repeat_noise) * (1.0 + step_noise);
      run.wall_ms.push_back(ms);
      run.cpu_ms.push_back(ms);
      run.cycles.push_back(static_cast<std::uint64_t>(std::llround(ms * 2.2e6)));
      run.contacts.push_back(run.bodies);
      run.phase_ms.push_back(0.4 * ms);
      run.phase_ms.push_back(0.6 * ms);
    }
  }
  AccuracySample last;
  last.step = steps;
  last.max_penetration = 0.002;
  last.max_displacement = scene == "pile" ? 3.0 : 0.001;
  run.accuracy = {last};
  run.state_hashes = {engine + "-" + scene + "-h20", engine + "-" + scene + "-h40"};
  run.final_state_hash = run.state_hashes.back();
  return run;
}

// `run` as if measured with --counter instructions: `instructions` over its `steps` steps.
RunRecord counted(RunRecord run, std::uint64_t instructions) {
  run.instruction_count = InstructionCount{instructions, run.steps, "callgrind", "valgrind-3.19.0"};
  return run;
}

ResultSet results_of(std::vector<RunRecord> runs) {
  ResultSet results;
  results.provenance.cpu_model = "Test CPU @ 2.2GHz";
  results.provenance.hostname = "bench-01";
  results.provenance.compiler = "GNU 12.2.0";
  results.provenance.build_flags = "-O2 -ffp-contract=off";
  results.scenes = {{"pile", pile_hash, "{}", "", "penetration"}, {"stacks", stacks_hash, "{}", "", "displacement"}};
  results.runs = std::move(runs);
  return results;
}

class CompareFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("fx2d_compare_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::string write(const ResultSet& results, const std::string& name) const {
    const std::string path = (directory_ / name).string();
    write_results_h5(results, path, true);
    return path;
  }

  CompareReport compare(const ResultSet& a, const ResultSet& b, const CompareSettings& settings = {}) const {
    return compare_files(write(a, "a.h5"), write(b, "b.h5"), "", settings);
  }

  // One of each A/B outcome: fx2d pile 10% slower in time and in instructions (two
  // regressions), fx2d stacks 10% faster but drifting (faster, less accurate), box2d pile
  // untouched in time and instructions (unchanged), ode pile 10% faster (improvement; counted in
  // A only, so no instructions row), ode stacks with two repeats (inconclusive).
  CompareReport mixed_report() const {
    RunRecord drifting = synthetic_run("fx2d", "stacks", 0.9, 5);
    drifting.accuracy[0].max_displacement = 0.01;
    const ResultSet a =
        results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), 40'000'000), synthetic_run("fx2d", "stacks", 1.0, 0),
                    counted(synthetic_run("box2d", "pile", 2.0, 0), 80'000'000),
                    counted(synthetic_run("ode", "pile", 0.5, 0), 20'000'000), synthetic_run("ode", "stacks", 0.5, 0, 2)});
    const ResultSet b = results_of({counted(synthetic_run("fx2d", "pile", 1.1, 5), 44'000'000), drifting,
                                    counted(synthetic_run("box2d", "pile", 2.0, 0), 80'000'000),
                                    synthetic_run("ode", "pile", 0.45, 5), synthetic_run("ode", "stacks", 0.5, 5, 2)});
    return compare(a, b);
  }

  fs::path directory_;
};

const CompareRow& row_of(const CompareReport& report, const std::string& engine, const std::string& scene,
                         const std::string& metric) {
  for (const CompareRow& row : report.rows)
    if (row.engine == engine && row.scene == scene && row.metric == metric) return row;
  throw std::logic_error("no row " + engine + " " + scene + " " + metric);
}

TEST_F(CompareFiles, IdenticalFilesAreNoChangeWithSamePhysicsAndExitZero) {
  const ResultSet results = results_of({synthetic_run("fx2d", "pile", 1.0, 0)});
  const CompareReport report = compare(results, results);
  ASSERT_EQ(report.rows.size(), 5u);  // ms_per_step, mean_cpu_ms_per_step, cycles_per_step, two phases
  for (const CompareRow& row : report.rows) {
    EXPECT_EQ(row.estimate.ratio, 1.0) << row.metric;
    EXPECT_EQ(row.speed.speed, Speed::no_change) << row.metric;
    EXPECT_EQ(row.same_physics, true);
    // Step against step where steps correspond; the mean of a repeat against the others'.
    EXPECT_EQ(row.test_name,
              row.metric == "mean_cpu_ms_per_step" ? "mann-whitney-u" : "wilcoxon-signed-rank-paired");
    EXPECT_EQ(row.test->p_value, 1.0);
  }
  EXPECT_EQ(row_of(report, "fx2d", "pile", "ms_per_step").verdict(), "no change");
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_EQ(report.exit_code(), exit_ok);
}

// `run` with its step split into the named phases in the given shares.
RunRecord with_phases(RunRecord run, const std::vector<std::pair<std::string, double>>& shares) {
  run.phase_names.clear();
  for (const auto& share : shares) run.phase_names.push_back(share.first);
  run.phase_ms.clear();
  for (const double ms : run.wall_ms) {
    for (const auto& share : shares) run.phase_ms.push_back(share.second * ms);
  }
  return run;
}

// Fx2D's phases before each stage function had a timer (RESULTS_FORMAT.md, "Fx2D's phase names"),
// and the same steps split into today's stages so that each old phase is the sum of its stages.
const std::vector<std::pair<std::string, double>> old_fx2d_phases = {
    {"integration", 0.10},    {"broad_phase", 0.05}, {"narrow_phase", 0.15}, {"velocity_passes", 0.50},
    {"position_solve", 0.05}, {"constraints", 0.05}, {"bookkeeping", 0.10}};
const std::vector<std::pair<std::string, double>> new_fx2d_phases = {
    {"broad_phase", 0.05}, {"collide", 0.15},     {"prepare", 0.05},        {"colour_and_pack", 0.05},
    {"integrate", 0.10},   {"warm_start", 0.05},  {"solve", 0.20},          {"relax", 0.10},
    {"restitution", 0.05}, {"position_solve", 0.05}, {"constraints", 0.05}, {"store", 0.04},
    {"sleep", 0.06}};

TEST_F(CompareFiles, OldPhaseNamesCompareWithTheSumsOfTheStagesTheyCovered) {
  const ResultSet old_file = results_of({with_phases(synthetic_run("fx2d", "pile", 1.0, 0), old_fx2d_phases)});
  const ResultSet new_file = results_of({with_phases(synthetic_run("fx2d", "pile", 1.0, 0), new_fx2d_phases)});
  for (const CompareReport& report : {compare(old_file, new_file), compare(new_file, old_file)}) {
    ASSERT_EQ(report.rows.size(), 3u + old_fx2d_phases.size());  // ms, mean CPU, cycles, then every old phase
    for (const auto& [name, share] : old_fx2d_phases) {
      const CompareRow& row = row_of(report, "fx2d", "pile", "phase:" + name);
      EXPECT_NEAR(row.estimate.ratio, 1.0, 1e-9) << name;
      EXPECT_EQ(row.speed.speed, Speed::no_change) << name;
    }
  }
}

TEST_F(CompareFiles, TenPercentSlowerStepsAreARegressionInEveryMetricAndExitOne) {
  const CompareReport report = compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}),
                                       results_of({synthetic_run("fx2d", "pile", 1.1, 5)}));
  for (const CompareRow& row : report.rows) {
    EXPECT_EQ(row.speed.speed, Speed::slower) << row.metric;
    EXPECT_NEAR(row.estimate.ratio, 1.1, 1.1 * 0.018) << row.metric;
    EXPECT_GE(row.estimate.ci.low, 1.1 * 0.991 / 1.009) << row.metric;
  }
  EXPECT_EQ(report.count_regressions(), 1);  // one gating row: ms_per_step
  EXPECT_EQ(report.exit_code(), exit_regression);
}

TEST_F(CompareFiles, FasterButLessAccurateIsFlaggedAndIsARegression) {
  RunRecord candidate = synthetic_run("fx2d", "pile", 0.9, 5);
  candidate.accuracy[0].max_penetration *= 2.0;
  const CompareReport report = compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}), results_of({candidate}));
  const CompareRow& row = row_of(report, "fx2d", "pile", "ms_per_step");
  EXPECT_EQ(row.speed.speed, Speed::faster);
  EXPECT_EQ(row.verdict(), "faster, less accurate");
  EXPECT_EQ(report.exit_code(), exit_regression);
}

TEST_F(CompareFiles, AccuracyWithinToleranceIsTheSameAndBeyondItIsWorse) {
  // Tolerance 5% of 2 mm plus the 0.1 mm floor: 0.2 mm.
  RunRecord within = synthetic_run("fx2d", "pile", 1.0, 5);
  within.accuracy[0].max_penetration = 0.002 + 0.00019;
  const CompareReport same = compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}), results_of({within}));
  EXPECT_EQ(row_of(same, "fx2d", "pile", "ms_per_step").verdict(), "no change");
  EXPECT_EQ(same.exit_code(), exit_ok);

  RunRecord beyond = synthetic_run("fx2d", "pile", 1.0, 5);
  beyond.accuracy[0].max_penetration = 0.002 + 0.00021;
  const CompareReport worse = compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}), results_of({beyond}));
  EXPECT_EQ(row_of(worse, "fx2d", "pile", "ms_per_step").verdict(), "no change, less accurate");
  EXPECT_EQ(worse.exit_code(), exit_regression);
}

TEST_F(CompareFiles, DisplacementJudgesOnlyWhereItIsThePrimaryMetric) {
  // A pile that falls 10% further is a different trajectory, not an error; a stack that drifts
  // 10 mm instead of 1 mm is an error.
  RunRecord pile = synthetic_run("fx2d", "pile", 1.0, 5);
  pile.accuracy[0].max_displacement *= 1.1;
  RunRecord stacks = synthetic_run("fx2d", "stacks", 1.0, 5);
  stacks.accuracy[0].max_displacement = 0.01;
  const CompareReport report =
      compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0), synthetic_run("fx2d", "stacks", 1.0, 0)}),
              results_of({pile, stacks}));
  const CompareRow& pile_row = row_of(report, "fx2d", "pile", "ms_per_step");
  EXPECT_EQ(pile_row.accuracy[1].change, AccuracyChange::changed);
  EXPECT_EQ(pile_row.accuracy_change(), AccuracyChange::same);
  EXPECT_EQ(row_of(report, "fx2d", "stacks", "ms_per_step").accuracy_change(), AccuracyChange::worse);
  EXPECT_EQ(report.count_regressions(), 1);
}

TEST_F(CompareFiles, TwoRepeatsAreInconclusiveAndExitThree) {
  const CompareReport report = compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0, 2)}),
                                       results_of({synthetic_run("fx2d", "pile", 1.1, 5, 2)}));
  const CompareRow& row = row_of(report, "fx2d", "pile", "ms_per_step");
  EXPECT_EQ(row.speed.speed, Speed::inconclusive);
  EXPECT_GE(row.speed.repeats_needed.value_or(0), VerdictRules{}.min_repeats);
  EXPECT_EQ(report.exit_code(), exit_inconclusive);
}

TEST_F(CompareFiles, DifferentSceneHashIsRefusedUnlessForced) {
  ResultSet other_scene = results_of({synthetic_run("fx2d", "pile", 1.0, 5)});
  other_scene.runs[0].scene_hash = "3333333333333333";
  other_scene.scenes[0].hash = "3333333333333333";
  const ResultSet reference = results_of({synthetic_run("fx2d", "pile", 1.0, 0)});
  try {
    compare(reference, other_scene);
    FAIL() << "different scenes were compared";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("different scene"), std::string::npos) << message;
    EXPECT_NE(message.find("--force"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  CompareSettings forced;
  forced.force = true;
  const CompareReport report = compare(reference, other_scene, forced);
  EXPECT_FALSE(report.rows.empty());
}

TEST_F(CompareFiles, ChangedStateHashIsChangedPhysicsAndUnpaired) {
  RunRecord candidate = synthetic_run("fx2d", "pile", 1.0, 5);
  candidate.state_hashes.back() = candidate.final_state_hash = "other";
  const CompareReport report = compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}), results_of({candidate}));
  const CompareRow& row = row_of(report, "fx2d", "pile", "ms_per_step");
  EXPECT_EQ(row.same_physics, false);
  EXPECT_EQ(row.test_name, "mann-whitney-u");
}

// The two builds of one `ab` as its file holds them (fx2d@A, fx2d@B), `rounds` rounds each, B's
// steps `b_scale` times A's, both on one trajectory.
struct AbRounds {
  RunRecord a;
  RunRecord b;
};

AbRounds ab_rounds(double b_scale, int rounds) {
  AbRounds ab{synthetic_run("fx2d@A", "pile", 1.0, 0, rounds), synthetic_run("fx2d@B", "pile", b_scale, 0, rounds)};
  ab.b.state_hashes = ab.a.state_hashes;
  ab.b.final_state_hash = ab.a.final_state_hash;
  return ab;
}

// Every step of round `round` of `run` takes `factor` times as long.
void scale_round(RunRecord& run, int round, double factor) {
  for (int s = 0; s < steps; ++s) run.wall_ms[static_cast<std::size_t>(round * steps + s)] *= factor;
}

// The rounds of one `ab`: round r of both builds ran at
// the machine's speed of the moment, a factor spread over +-15% across 30 rounds, and B costs 5%
// more. Pairs of rounds cancel that drift; two independent files could not, so the same figures
// judged as two `run`s are inconclusive.
TEST_F(CompareFiles, AnAbFileResamplesItsRoundsAsPairsAndFindsAShiftTheDriftHides) {
  constexpr int rounds = 30;
  auto [a, b] = ab_rounds(1.05, rounds);
  for (int r = 0; r < rounds; ++r) {
    const double drift = 1.0 + 0.15 * ((r * 7) % rounds - 14.5) / 14.5;
    scale_round(a, r, drift);
    scale_round(b, r, drift);
  }
  const CompareReport paired = compare_files(write(results_of({a, b}), "ab.h5"), std::nullopt, "", {});
  const CompareRow& row = paired.rows.at(0);
  ASSERT_EQ(row.metric, "ms_per_step");
  EXPECT_TRUE(row.rounds_paired);
  EXPECT_NEAR(row.estimate.ratio, 1.05, 1e-9);  // every pair's ratio is exactly 1.05
  EXPECT_NEAR(row.estimate.ci.low, 1.05, 1e-9);
  EXPECT_NEAR(row.estimate.ci.high, 1.05, 1e-9);
  EXPECT_EQ(row.speed.speed, Speed::slower);
  EXPECT_NE(compare_table(paired).find("resampling those pairs of rounds"), std::string::npos);

  const std::optional<VariantResults> split = split_variants(results_of({a, b}));
  ASSERT_TRUE(split.has_value());
  const CompareReport unpaired = compare_results(split->a, "a.h5", split->b, "b.h5", {});
  EXPECT_FALSE(unpaired.rows.at(0).rounds_paired);
  EXPECT_LT(unpaired.rows.at(0).estimate.ci.low, 1.02);
  EXPECT_EQ(unpaired.rows.at(0).speed.speed, Speed::inconclusive);
  EXPECT_NE(compare_table(unpaired).find("resampling A's and B's repeats independently"), std::string::npos);
}

// A neighbour whose activity is locked to the rounds (it slows the last 15 of the 40 steps of
// every A round by 25%) while B costs 5% more throughout. Those steps cost more than the median
// step already, so no round's median moves and the rounds show B 5% slower; but tested step by
// step, the 15 slowed steps say A is slower and the other 25 say B is, and the per-step test
// finds nothing (p = 0.26). The test of an `ab` file is therefore taken over its rounds, the
// same unit its interval resamples.
TEST_F(CompareFiles, AnAbFileIsTestedOverItsRoundsSoANeighbourLockedToTheRoundsHidesNoShift) {
  constexpr int rounds = 30;
  constexpr int first_slowed_step = 25;
  auto [a, b] = ab_rounds(1.05, rounds);
  for (int r = 0; r < rounds; ++r)
    for (int s = first_slowed_step; s < steps; ++s) a.wall_ms[static_cast<std::size_t>(r * steps + s)] *= 1.25;
  const CompareReport report = compare_files(write(results_of({a, b}), "ab.h5"), std::nullopt, "", {});
  const CompareRow& row = report.rows.at(0);
  ASSERT_EQ(row.metric, "ms_per_step");
  EXPECT_EQ(row.test_name, "sign-test-rounds");
  EXPECT_GT(row.estimate.ci.low, 1.03);
  EXPECT_LT(row.test->p_value, 1e-4);
  EXPECT_EQ(row.speed.speed, Speed::slower);
}

// B costs 5% more, and 8 of 30 A rounds ran 30% slower (a neighbour busy in those only), so
// those rounds say B/A = 0.81. The median round is unmoved. In a signed-rank test those 8 rounds'
// large differences outweigh the 22 small ones (p = 0.67); counted by sign, 22 against 8 is
// significant (p = 0.018). The test over rounds counts signs, as their median does.
TEST_F(CompareFiles, AnAbFileIsTestedBySignsSoAFewBadlyDisturbedRoundsDoNotOutweighTheRest) {
  constexpr int rounds = 30;
  auto [a, b] = ab_rounds(1.05, rounds);
  for (int r = 0; r < 8; ++r) scale_round(a, r * 3 + 1, 1.3);
  const CompareReport report = compare_files(write(results_of({a, b}), "ab.h5"), std::nullopt, "", {});
  const CompareRow& row = report.rows.at(0);
  ASSERT_EQ(row.metric, "ms_per_step");
  EXPECT_EQ(row.test_name, "sign-test-rounds");
  EXPECT_GT(row.estimate.ci.low, 1.03);
  EXPECT_NEAR(row.test->p_value, 0.018, 0.001);
  EXPECT_EQ(row.speed.speed, Speed::slower);
}

// The rounds of an `ab` alternate between two machine states: in one B is 15% faster, in the
// other both builds run 20% slower and alike. The verdict stands, with a warning that says so.
TEST_F(CompareFiles, AnAbFileWhoseRoundsSplitByMachineStateIsJudgedWithAWarning) {
  constexpr int rounds = 30;
  auto [a, b] = ab_rounds(1.0, rounds);
  for (int r = 0; r < rounds; r += 2) scale_round(b, r, 0.85);
  for (int r = 1; r < rounds; r += 2) {
    scale_round(a, r, 1.2);
    scale_round(b, r, 1.2);
  }
  const CompareReport split = compare_files(write(results_of({a, b}), "ab.h5"), std::nullopt, "", {});
  ASSERT_EQ(split.warnings.size(), 1u);
  EXPECT_NE(split.warnings[0].find("fx2d pile 300: B/A is 0.850 over the half of the rounds that ran fastest and "
                                   "1.000 over the slowest half"),
            std::string::npos)
      << split.warnings[0];

  // The same rounds with the state moving both builds alike: no warning.
  b.wall_ms = a.wall_ms;
  for (int r = 0; r < rounds; ++r) scale_round(b, r, 0.9);
  EXPECT_TRUE(compare_files(write(results_of({a, b}), "ab2.h5"), std::nullopt, "", {}).warnings.empty());
}

TEST_F(CompareFiles, DifferentMachineOrCompilerWarnsUnlessForced) {
  ResultSet candidate = results_of({synthetic_run("fx2d", "pile", 1.0, 5)});
  candidate.provenance.cpu_model = "Other CPU";
  candidate.provenance.compiler = "Clang 14.0.6";
  const ResultSet reference = results_of({synthetic_run("fx2d", "pile", 1.0, 0)});
  const CompareReport warned = compare(reference, candidate);
  ASSERT_EQ(warned.warnings.size(), 2u);
  EXPECT_NE(warned.warnings[0].find("cpu_model"), std::string::npos);
  EXPECT_NE(warned.warnings[1].find("compiler"), std::string::npos);
  CompareSettings forced;
  forced.force = true;
  EXPECT_TRUE(compare(reference, candidate, forced).warnings.empty());
}

TEST_F(CompareFiles, NothingInCommonIsBadInput) {
  EXPECT_THROW(compare(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}),
                       results_of({synthetic_run("box2d", "pile", 1.0, 0)})),
               InputError);
}

TEST_F(CompareFiles, CorruptFileIsBadInput) {
  const std::string good = write(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}), "good.h5");
  const std::string corrupt = (directory_ / "corrupt.h5").string();
  std::ofstream(corrupt) << "not an HDF5 file";
  EXPECT_THROW(compare_files(good, corrupt, "", {}), InputError);
  EXPECT_THROW(compare_files(corrupt, std::nullopt, "", {}), InputError);
}

// --- instruction counts ---------------------------------------------------------------------------

// 40 steps of 1e6 instructions each.
constexpr std::uint64_t reference_count = 40'000'000;

TEST_F(CompareFiles, InstructionRowIsTheExactRatioWithNoTest) {
  const CompareReport report = compare(results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count)}),
                                       results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), 44'000'000)}));
  ASSERT_EQ(report.rows.size(), 6u);  // ms, mean CPU, cycles, two phases, then instructions
  const CompareRow& row = report.rows.back();
  EXPECT_EQ(row.metric, "instructions_per_step");
  EXPECT_EQ(row.a, 1e6);
  EXPECT_EQ(row.b, 1.1e6);
  EXPECT_EQ(row.estimate.ratio, 1.1);
  EXPECT_EQ(row.estimate.ci.low, 1.1);
  EXPECT_EQ(row.estimate.ci.high, 1.1);
  EXPECT_FALSE(row.test.has_value());
  EXPECT_EQ(row.test_name, "exact");
  EXPECT_EQ(row.speed.speed, Speed::slower);
  EXPECT_FALSE(row.speed.repeats_needed.has_value());
  EXPECT_EQ(row_of(report, "fx2d", "pile", "ms_per_step").speed.speed, Speed::no_change);
  // The time did not move, the instructions did: the count alone gates.
  EXPECT_EQ(report.count_regressions(), 1);
  EXPECT_EQ(report.exit_code(), exit_regression);
  const auto json = compare_json(report);
  EXPECT_TRUE(json["rows"][5]["p_value"].is_null());
  EXPECT_EQ(json["rows"][5]["ci_low"], 1.1);
  EXPECT_EQ(json["rows"][5]["regression"], true);
}

TEST_F(CompareFiles, InstructionVerdictsAtTheToleranceEdges) {
  // 0.5% of 1e6 instructions per step is 5000 per step, 200000 over 40 steps; 40 more over
  // 40 steps is one instruction per step beyond the edge.
  const auto speed = [&](std::uint64_t b_count) {
    const CompareReport report = compare(results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count)}),
                                         results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), b_count)}));
    return std::pair{row_of(report, "fx2d", "pile", "instructions_per_step").speed.speed, report.exit_code()};
  };
  EXPECT_EQ(speed(reference_count), std::pair(Speed::no_change, exit_ok));
  EXPECT_EQ(speed(reference_count + 200'000), std::pair(Speed::no_change, exit_ok));
  EXPECT_EQ(speed(reference_count + 200'040), std::pair(Speed::slower, exit_regression));
  EXPECT_EQ(speed(reference_count - 200'000), std::pair(Speed::no_change, exit_ok));
  EXPECT_EQ(speed(reference_count - 200'040), std::pair(Speed::faster, exit_ok));
}

TEST_F(CompareFiles, InstructionToleranceIsSettable) {
  const ResultSet a = results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count)});
  const ResultSet b = results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count + 200'040)});
  CompareSettings wider;
  wider.instructions_tolerance = 0.01;
  EXPECT_EQ(compare(a, b, wider).exit_code(), exit_ok);
  CompareSettings exact;
  exact.instructions_tolerance = 0.0;
  const ResultSet one_more = results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count + 1)});
  EXPECT_EQ(compare(a, one_more, exact).exit_code(), exit_regression);
}

TEST_F(CompareFiles, AFasterStepOnTheSameInstructionsIsFlaggedAsLikelyPlacement) {
  const ResultSet a = results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count)});
  const CompareReport same_count =
      compare(a, results_of({counted(synthetic_run("fx2d", "pile", 0.9, 0), reference_count + 1000)}));
  ASSERT_EQ(row_of(same_count, "fx2d", "pile", "ms_per_step").speed.speed, Speed::faster);
  ASSERT_EQ(same_count.warnings.size(), 1u);
  EXPECT_NE(same_count.warnings[0].find(
                "fx2d pile 300: the step is faster (B/A 0.900) on 1.000 of A's instructions"),
            std::string::npos)
      << same_count.warnings[0];
  EXPECT_NE(same_count.warnings[0].find("code placement"), std::string::npos) << same_count.warnings[0];
  // The count moved with the time: the change did the work, and nothing is said.
  const CompareReport fewer =
      compare(a, results_of({counted(synthetic_run("fx2d", "pile", 0.9, 0), 36'000'000)}));
  EXPECT_EQ(row_of(fewer, "fx2d", "pile", "instructions_per_step").speed.speed, Speed::faster);
  EXPECT_TRUE(fewer.warnings.empty());
}

// `run` as if its costliest quarter of steps (the last, in a synthetic run) took `factor` times
// as long in CPU and wall time alike: steps above the median already, which leave it in place.
RunRecord with_costlier_tail(RunRecord run, double factor) {
  const auto per_repeat = static_cast<std::size_t>(run.steps);
  for (std::size_t i = 0; i < run.wall_ms.size(); ++i) {
    if (i % per_repeat < per_repeat - per_repeat / 4) continue;
    run.wall_ms[i] *= factor;
    run.cpu_ms[i] *= factor;
  }
  return run;
}

// A change confined to a quarter of the steps leaves every repeat's median step where it was;
// the mean CPU time per step, the figure `run` and the speed table report, sees it.
TEST_F(CompareFiles, ACostInAQuarterOfTheStepsShowsInTheMeanRowNotInTheStepRow) {
  const ResultSet a = results_of({synthetic_run("fx2d", "pile", 1.0, 0)});
  const CompareReport report =
      compare(a, results_of({with_costlier_tail(synthetic_run("fx2d", "pile", 1.0, 5), 1.8)}));
  EXPECT_EQ(row_of(report, "fx2d", "pile", "ms_per_step").speed.speed, Speed::no_change);
  const CompareRow& mean = row_of(report, "fx2d", "pile", "mean_cpu_ms_per_step");
  EXPECT_EQ(mean.speed.speed, Speed::slower);
  // The last 10 of 40 steps cost 0.845 ms on average, the whole run 0.695: 1 + 0.8 x 10 x 0.845 / (40 x
  // 0.695).
  EXPECT_NEAR(mean.estimate.ratio, 1.243, 0.02);
  EXPECT_EQ(report.exit_code(), exit_ok);  // information: only the step and the instructions gate
  // And the other way: a change that cuts those steps back is faster by the mean alone.
  const CompareReport cut =
      compare(results_of({with_costlier_tail(synthetic_run("fx2d", "pile", 1.0, 0), 1.8)}),
              results_of({synthetic_run("fx2d", "pile", 1.0, 5)}));
  EXPECT_EQ(row_of(cut, "fx2d", "pile", "mean_cpu_ms_per_step").speed.speed, Speed::faster);
  EXPECT_EQ(row_of(cut, "fx2d", "pile", "ms_per_step").speed.speed, Speed::no_change);
}

TEST_F(CompareFiles, CountsOnOneSideGiveNoInstructionRowAndOneWarning) {
  const ResultSet a = results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count),
                                  counted(synthetic_run("fx2d", "stacks", 1.0, 0), reference_count)});
  const ResultSet b = results_of({synthetic_run("fx2d", "pile", 1.0, 5), synthetic_run("fx2d", "stacks", 1.0, 5)});
  const CompareReport report = compare(a, b);
  EXPECT_EQ(report.rows.size(), 10u);  // ms, mean CPU, cycles and two phases for each scene; no instructions
  EXPECT_TRUE(std::ranges::none_of(report.rows, [](const CompareRow& row) { return row.metric == "instructions_per_step"; }));
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("2 pairs of runs with instruction counts on one side only"), std::string::npos)
      << report.warnings[0];
  EXPECT_NE(report.warnings[0].find("--counter instructions"), std::string::npos) << report.warnings[0];
  EXPECT_EQ(report.exit_code(), exit_ok);
}

ResultSet three_engines() {
  return results_of({synthetic_run("fx2d", "pile", 1.0, 0), synthetic_run("box2d", "pile", 2.0, 3),
                     synthetic_run("ode", "pile", 0.5, 6)});
}

TEST_F(CompareFiles, OneFileComparesFx2dAgainstTheOtherEnginesWithoutGating) {
  const CompareReport report = compare_files(write(three_engines(), "engines.h5"), std::nullopt, "", {});
  EXPECT_TRUE(report.cross_engine);
  const CompareRow& against_box2d = report.rows.at(0);
  EXPECT_EQ(against_box2d.engine, "fx2d");
  EXPECT_EQ(against_box2d.against, "box2d");
  EXPECT_NEAR(against_box2d.estimate.ratio, 0.5, 0.5 * 0.018);
  EXPECT_EQ(against_box2d.speed.speed, Speed::faster);
  EXPECT_FALSE(against_box2d.same_physics.has_value());
  EXPECT_EQ(report.rows.size(),
            6u);  // ms, mean CPU and cycles against each of two engines: no phases across engines
  EXPECT_EQ(report.rows.at(3).against, "ode");
  EXPECT_EQ(report.rows.at(3).speed.speed, Speed::slower);
  EXPECT_EQ(report.exit_code(), exit_ok);  // fx2d slower than ode: a report, not a gate
}

TEST_F(CompareFiles, BaselineComparesEveryOtherEngineAgainstIt) {
  const CompareReport report = compare_files(write(three_engines(), "engines.h5"), std::nullopt, "box2d", {});
  ASSERT_EQ(report.rows.size(), 6u);
  EXPECT_EQ(report.rows[0].engine, "fx2d");
  EXPECT_EQ(report.rows[0].against, "box2d");
  EXPECT_EQ(report.rows[3].engine, "ode");
  EXPECT_EQ(report.rows[3].against, "box2d");
  EXPECT_NEAR(report.rows[3].estimate.ratio, 0.25, 0.25 * 0.018);
}

TEST_F(CompareFiles, CrossEngineViewShowsInstructionRowsWithoutGating) {
  const ResultSet results = results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count),
                                        counted(synthetic_run("box2d", "pile", 2.0, 3), reference_count / 2)});
  const CompareReport report = compare_files(write(results, "engines.h5"), std::nullopt, "", {});
  const CompareRow& row = row_of(report, "fx2d", "pile", "instructions_per_step");
  EXPECT_EQ(row.against, "box2d");
  EXPECT_EQ(row.estimate.ratio, 2.0);
  EXPECT_EQ(row.speed.speed, Speed::slower);
  EXPECT_EQ(report.exit_code(), exit_ok);  // a report, not a gate
}

// --- the command line ---------------------------------------------------------------------------

class CapturedStdout {
 public:
  CapturedStdout() : previous_(std::cout.rdbuf(text_.rdbuf())) {}
  ~CapturedStdout() { std::cout.rdbuf(previous_); }
  CapturedStdout(const CapturedStdout&) = delete;
  CapturedStdout& operator=(const CapturedStdout&) = delete;
  std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::streambuf* previous_;
};

// Parses `arguments` after "fx2d-bench compare"; returns the exit status the command set.
int run_compare(std::vector<std::string> arguments) {
  CLI::App app;
  int status = -1;
  register_compare(app, status);
  arguments.insert(arguments.begin(), "compare");
  std::reverse(arguments.begin(), arguments.end());  // CLI11 takes a vector in reverse order
  app.parse(arguments);
  return status;
}

TEST_F(CompareFiles, CommandPrintsJsonAndSetsTheExitStatus) {
  const std::string a = write(results_of({synthetic_run("fx2d", "pile", 1.0, 0)}), "a.h5");
  const std::string b = write(results_of({synthetic_run("fx2d", "pile", 1.1, 5)}), "b.h5");
  CapturedStdout captured;
  EXPECT_EQ(run_compare({a, b, "--json"}), exit_regression);
  const auto json = nlohmann::json::parse(captured.text());
  EXPECT_EQ(json["schema"], "fx2d-bench.compare/1");
  EXPECT_EQ(json["regressions"], 1);
  EXPECT_EQ(json["rows"][0]["verdict"], "slower");
  EXPECT_EQ(json["rows"][0]["physics"], "same");
}

TEST_F(CompareFiles, CommandRejectsBaselineWithTwoFilesAndJsonWithMarkdown) {
  const std::string a = write(three_engines(), "a.h5");
  EXPECT_THROW(run_compare({a, a, "--baseline", "box2d"}), CLI::ParseError);
  EXPECT_THROW(run_compare({a, a, "--json", "--markdown"}), CLI::ParseError);
  // A baseline the file lacks is its contents' refusal (plugin_commands_test), not the parser's.
  EXPECT_THROW(run_compare({a, "--baseline", "bullet"}), InputError);
  EXPECT_THROW(run_compare({a, a, "--noise", "-0.1"}), CLI::ParseError);
}

TEST_F(CompareFiles, CommandTakesInstructionsToleranceAndRejectsOneOutOfRange) {
  const std::string a = write(results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count)}), "a.h5");
  const std::string b =
      write(results_of({counted(synthetic_run("fx2d", "pile", 1.0, 0), reference_count + 400'000)}), "b.h5");
  CapturedStdout captured;
  EXPECT_EQ(run_compare({a, b}), exit_regression);
  EXPECT_EQ(run_compare({a, b, "--instructions-tolerance", "0.02"}), exit_ok);
  EXPECT_THROW(run_compare({a, b, "--instructions-tolerance", "-0.01"}), CLI::ParseError);
}

// --- outputs against goldens ----------------------------------------------------------------------

std::string file_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void expect_matches_golden(const std::string& text, const std::string& name) {
  const fs::path golden = fs::path(FX2D_SOURCE_DIR) / "goldens" / name;
  if (std::getenv("FX2D_UPDATE_GOLDENS") != nullptr) {
    std::ofstream(golden, std::ios::binary) << text;
    GTEST_SKIP() << "regenerated " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; regenerate it as this file's header says";
  std::istringstream actual_lines(text);
  std::istringstream golden_lines(file_text(golden));
  std::string actual;
  std::string expected;
  for (int line = 1; std::getline(golden_lines, expected); ++line) {
    if (!std::getline(actual_lines, actual)) actual = "<end of output>";
    ASSERT_EQ(actual, expected) << golden << ":" << line << " differs; if deliberately, regenerate it as this file's header says";
  }
  EXPECT_FALSE(std::getline(actual_lines, actual)) << "output goes on past the end of " << golden << ": " << actual;
}

TEST_F(CompareFiles, MixedOutcomesHeadlineAndExitCode) {
  const CompareReport report = mixed_report();
  EXPECT_EQ(report.headline(), "3 regressions, 1 improvement, 2 unchanged, 1 inconclusive");
  ASSERT_EQ(report.warnings.size(), 1u);  // ode pile counted in A only
  EXPECT_NE(report.warnings[0].find("1 pair of runs with instruction counts on one side only"), std::string::npos)
      << report.warnings[0];
  EXPECT_EQ(report.exit_code(), exit_regression);
}

TEST_F(CompareFiles, JsonMatchesGolden) {
  const CompareReport report = mixed_report();
  expect_matches_golden(compare_json(report).dump(2) + "\n", "compare_ab.json");
}

TEST_F(CompareFiles, MarkdownMatchesGolden) {
  const CompareReport report = mixed_report();
  expect_matches_golden(compare_markdown(report), "compare_ab.md");
}

TEST_F(CompareFiles, TerminalTableMatchesGolden) {
  const CompareReport report = mixed_report();
  expect_matches_golden(compare_table(report), "compare_ab.txt");
}

TEST_F(CompareFiles, CrossEngineMarkdownMatchesGolden) {
  const CompareReport report = compare_files(write(three_engines(), "engines.h5"), std::nullopt, "", {});
  expect_matches_golden(compare_markdown(report), "compare_engines.md");
}

}  // namespace
}  // namespace fxbench

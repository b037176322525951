// Tests of the nightly gate (gate_policy.h, `fx2d-bench gate`): the committed policy is valid and
// names the gating suite; each rule at its boundary with per-scene thresholds (the two-stage time
// rule, the exact rule of instruction counts, the accuracy tolerance); a quarantined row is
// dropped with its reason printed; a control that moved makes the night's time verdicts
// inconclusive but leaves exact counts gating; a bad policy is refused in one line, exit 2.
//
// Boundary values are chosen exactly representable in binary (1 + 2^-5 = 1.03125), so "at the
// band edge" means exactly at it, not a rounding away from it.
#include "analysis/gate_policy.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/bench_process.h"
#include "stats/statistics.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double edge = 0.03125;  // 2^-5: the test policy's noise band and instructions tolerance for pile

// Pile gates at +-2^-5 for time and counts; stacks is looser for time (0.25) and for accuracy
// (50%); one ODE row is quarantined; Box2D and ODE are controls.
const char* const test_policy = R"policy({
  "schema": "fx2d-bench.gating/1",
  "suite": {"engines": ["fx2d", "box2d", "ode"], "scenes": [{"scene": "pile", "bodies": 600}], "rounds": 8, "steps": 50},
  "smoke": {"engines": ["fx2d"], "scenes": [{"scene": "pile", "bodies": 60}], "rounds": 6, "steps": 20},
  "controls": ["box2d", "ode"],
  "defaults": {"noise": 0.03125, "alpha": 0.05, "accuracy_tolerance": 0.05, "instructions_tolerance": 0.03125},
  "scenes": {"stacks": {"noise": 0.25, "accuracy_tolerance": 0.5, "reason": "test: a looser scene"}},
  "quarantine": [{"engine": "ode", "scene": "pile", "bodies": 600, "metric": "ms_per_step",
                  "reason": "ODE's QuickStep timing swings 5% between boots (test)"}]
})policy";

json time_row(const std::string& engine, const std::string& scene, double ratio, double low, double high, double p) {
  return {{"engine", engine}, {"against", engine}, {"scene", scene}, {"bodies", scene == "pile" ? 600 : 200},
          {"metric", "ms_per_step"}, {"a", 1.0}, {"b", ratio}, {"ratio", ratio}, {"ci_low", low},
          {"ci_high", high}, {"p_value", p}, {"repeats_a", 10}, {"repeats_b", 10}, {"verdict", "(compare's)"}};
}

json exact_row(const std::string& engine, double ratio) {
  return {{"engine", engine}, {"against", engine}, {"scene", "pile"}, {"bodies", 600},
          {"metric", "instructions_per_step"}, {"a", 1e6}, {"b", 1e6 * ratio}, {"ratio", ratio},
          {"ci_low", ratio}, {"ci_high", ratio}, {"p_value", nullptr}, {"verdict", "(compare's)"}};
}

json comparison(std::vector<json> rows) {
  return {{"schema", "fx2d-bench.compare/1"}, {"mode", "ab"}, {"rows", rows}, {"regressions", 0}};
}

GateReport judged(std::vector<json> rows) {
  return judge(comparison(std::move(rows)), "test.json", parse_policy(test_policy, "policy.json"));
}

std::string only_verdict(std::vector<json> rows) {
  const GateReport report = judged(std::move(rows));
  EXPECT_EQ(report.rows.size(), 1u);
  return report.rows.at(0).verdict;
}

// --- the committed policy -------------------------------------------------------------------------

// ... and the jointed scenes as they stand: the pins' batches and the joint schedule are guarded
// nightly like the contacts.
TEST(GatePolicy, CommittedPolicyNamesTheCanonicalScenesAtTheirMiddleSizesOnAllEngines) {
  const Policy policy = read_policy(std::string(FX2D_SOURCE_DIR) + "/ci/gating.json");
  ASSERT_EQ(policy.suite.scenes.size(), 6u);
  EXPECT_EQ(policy.suite.scenes[0].scene, "pile");
  EXPECT_EQ(policy.suite.scenes[0].bodies, 600);
  EXPECT_EQ(policy.suite.scenes[1].scene, "stacks");
  EXPECT_EQ(policy.suite.scenes[1].bodies, 200);
  EXPECT_EQ(policy.suite.scenes[2].scene, "settling_boxes");
  EXPECT_EQ(policy.suite.scenes[2].bodies, 800);
  EXPECT_EQ(policy.suite.scenes[3].scene, "scenes/joints/chain.json");
  EXPECT_EQ(policy.suite.scenes[4].scene, "scenes/joints/joint_grid.json");
  EXPECT_EQ(policy.suite.scenes[5].scene, "scenes/joints/rope.json");
  EXPECT_EQ(policy.suite.scenes[3].bodies + policy.suite.scenes[4].bodies + policy.suite.scenes[5].bodies, 0);
  EXPECT_EQ(policy.suite.engines, (std::vector<std::string>{"fx2d", "box2d", "ode"}));
  EXPECT_EQ(policy.controls, (std::vector<std::string>{"box2d", "ode"}));
  for (const Quarantine& entry : policy.quarantine) EXPECT_FALSE(entry.reason.empty());
}

// --- the time rule --------------------------------------------------------------------------------

TEST(GateTimeRule, SignificantAndWholeIntervalAboveTheBandIsSlower) {
  EXPECT_EQ(only_verdict({time_row("fx2d", "pile", 1.05, 1.04, 1.06, 0.001)}), "slower");
}

TEST(GateTimeRule, IntervalTouchingTheBandEdgeIsInconclusiveNotSlower) {
  EXPECT_EQ(only_verdict({time_row("fx2d", "pile", 1.05, 1.0 + edge, 1.06, 0.001)}), "inconclusive");
}

TEST(GateTimeRule, IntervalEndingExactlyAtTheBandEdgeIsNoChange) {
  EXPECT_EQ(only_verdict({time_row("fx2d", "pile", 1.0, 1.0 - edge, 1.0 + edge, 0.5)}), "no change");
}

TEST(GateTimeRule, OutsideTheBandButNotSignificantIsInconclusive) {
  EXPECT_EQ(only_verdict({time_row("fx2d", "pile", 1.05, 1.04, 1.06, 0.05)}), "inconclusive");
  EXPECT_EQ(only_verdict({time_row("fx2d", "pile", 1.05, 1.04, 1.06, 0.0499)}), "slower");
}

TEST(GateTimeRule, TheSceneOwnNoiseBandApplies) {
  // The same 5% slowdown is a regression on pile (band 3.125%) and no change on stacks (band 25%).
  const GateReport report = judged({time_row("fx2d", "pile", 1.05, 1.04, 1.06, 0.001),
                                    time_row("fx2d", "stacks", 1.05, 1.04, 1.06, 0.001)});
  EXPECT_EQ(report.rows[0].verdict, "slower");
  EXPECT_TRUE(report.rows[0].regression);
  EXPECT_DOUBLE_EQ(report.rows[0].band, edge);
  EXPECT_EQ(report.rows[1].verdict, "no change");
  EXPECT_FALSE(report.rows[1].regression);
  EXPECT_DOUBLE_EQ(report.rows[1].band, 0.25);
  EXPECT_EQ(report.exit_code(), exit_regression);
}

TEST(GateTimeRule, FasterIsAStepButNotARegression) {
  const GateReport report = judged({time_row("fx2d@B", "pile", 0.9, 0.88, 0.92, 0.001)});
  EXPECT_EQ(report.rows[0].verdict, "faster");
  EXPECT_TRUE(report.rows[0].step_detected);
  EXPECT_EQ(report.exit_code(), exit_ok);
}

// --- the exact rule -------------------------------------------------------------------------------

TEST(GateExactRule, RatioAtTheToleranceIsNoChangeAndJustBeyondIsSlowerOrFaster) {
  EXPECT_EQ(only_verdict({exact_row("fx2d", 1.0 + edge)}), "no change");
  EXPECT_EQ(only_verdict({exact_row("fx2d", 1.0 + edge + 1e-9)}), "slower");
  EXPECT_EQ(only_verdict({exact_row("fx2d", 1.0 - edge)}), "no change");
  EXPECT_EQ(only_verdict({exact_row("fx2d", 1.0 - edge - 1e-9)}), "faster");
}

TEST(GateExactRule, ExactRegressionGatesEvenOnANoisyMachine) {
  const GateReport report = judged({time_row("box2d", "pile", 1.1, 1.08, 1.12, 0.001),
                                    time_row("fx2d", "pile", 1.1, 1.08, 1.12, 0.001), exact_row("fx2d", 1.1)});
  ASSERT_EQ(report.noisy_controls.size(), 1u);
  EXPECT_EQ(report.rows[1].verdict, "inconclusive (noisy machine)");
  EXPECT_FALSE(report.rows[1].regression);
  EXPECT_EQ(report.rows[2].verdict, "slower");
  EXPECT_EQ(report.exit_code(), exit_regression);
}

// --- controls -------------------------------------------------------------------------------------

TEST(GateControls, ControlThatMovedMakesTheNightInconclusive) {
  const GateReport report = judged({time_row("box2d", "pile", 1.1, 1.08, 1.12, 0.001),
                                    time_row("fx2d", "pile", 1.1, 1.08, 1.12, 0.001)});
  EXPECT_EQ(report.rows[0].verdict, "control changed: slower");
  EXPECT_FALSE(report.rows[0].regression);
  EXPECT_FALSE(report.rows[0].step_detected);
  EXPECT_EQ(report.rows[1].verdict, "inconclusive (noisy machine)");
  EXPECT_EQ(report.exit_code(), exit_inconclusive);
  EXPECT_NE(report.headline().find("noisy machine"), std::string::npos);
}

TEST(GateControls, AnUndecidedControlIsNotCountedSteady) {
  const GateReport report = judged({time_row("box2d", "pile", 1.03, 1.01, 1.05, 0.2),
                                    time_row("fx2d", "pile", 1.0, 0.99, 1.01, 0.6)});
  EXPECT_EQ(report.rows[0].verdict, "control: inconclusive");
  EXPECT_NE(report.headline().find("0 controls steady, 1 controls inconclusive, 0 controls changed"), std::string::npos)
      << report.headline();
}

TEST(GateControls, SteadyControlsLeaveTheVerdictAlone) {
  const GateReport report = judged({time_row("box2d", "pile", 1.0, 0.99, 1.01, 0.6),
                                    time_row("fx2d", "pile", 1.1, 1.08, 1.12, 0.001)});
  EXPECT_EQ(report.rows[0].verdict, "control: no change");
  EXPECT_TRUE(report.noisy_controls.empty());
  EXPECT_EQ(report.rows[1].verdict, "slower");
  EXPECT_EQ(report.exit_code(), exit_regression);
}

// --- accuracy -------------------------------------------------------------------------------------

json with_penetration(json row, double a, double b) {
  row["accuracy"] = {{"primary_metric", "penetration"},
                     {"figures", {{"max_penetration", {{"a", a}, {"b", b}}}, {"max_displacement", {{"a", 3.0}, {"b", 9.0}}}}}};
  return row;
}

TEST(GateAccuracy, PenetrationBeyondTheSceneToleranceIsARegressionAndDisplacementOfAPileIsNot) {
  // pile: 5% of 10 mm + 0.1 mm = 0.6 mm allowed; 0.8 mm worse is a regression. The displacement
  // tripled, but a pile must fall: displacement judges only where it is the primary metric.
  const GateReport report = judged({with_penetration(time_row("fx2d", "pile", 1.0, 0.99, 1.01, 0.5), 0.010, 0.0108)});
  EXPECT_EQ(report.rows[0].verdict, "no change, less accurate");
  EXPECT_TRUE(report.rows[0].regression);
  // stacks: 50% of 10 mm + 0.1 mm allowed, so the same change is within tolerance.
  const GateReport looser = judged({with_penetration(time_row("fx2d", "stacks", 1.0, 0.99, 1.01, 0.5), 0.010, 0.0108)});
  EXPECT_EQ(looser.rows[0].verdict, "no change");
  EXPECT_FALSE(looser.rows[0].regression);
}

// --- quarantine -----------------------------------------------------------------------------------

TEST(GateQuarantine, QuarantinedRowNeverGatesAndKeepsItsReason) {
  const GateReport report = judged({time_row("ode@B", "pile", 1.5, 1.4, 1.6, 0.001)});
  ASSERT_EQ(report.rows.size(), 1u);
  EXPECT_TRUE(report.rows[0].quarantined);
  EXPECT_FALSE(report.rows[0].regression);
  EXPECT_EQ(report.rows[0].verdict, "quarantined");
  EXPECT_EQ(report.rows[0].reason, "ODE's QuickStep timing swings 5% between boots (test)");
  EXPECT_EQ(report.exit_code(), exit_ok);
}

TEST(GateQuarantine, QuarantineMatchesOnlyItsEngineSceneSizeAndMetric) {
  json other_size = time_row("ode", "pile", 1.5, 1.4, 1.6, 0.001);
  other_size["bodies"] = 300;
  const GateReport report = judged({other_size, time_row("fx2d", "pile", 1.0, 0.99, 1.01, 0.5)});
  EXPECT_FALSE(report.rows[0].quarantined);
  EXPECT_EQ(report.rows[0].verdict, "control changed: slower");
}

// --- refusals -------------------------------------------------------------------------------------

void expect_policy_error(const std::string& policy, const std::string& mentions) {
  try {
    parse_policy(policy, "bad.json");
    ADD_FAILURE() << "accepted: " << policy;
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(mentions), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(GatePolicyRefusals, EachBadPolicyIsNamedByItsJsonPointer) {
  const std::string good = test_policy;
  expect_policy_error(replaced(good, "\"noise\": 0.03125", "\"nosie\": 0.03125"),
                      "bad.json:6:16: /defaults/nosie: unknown key");
  expect_policy_error(replaced(good, "\"noise\": 0.25", "\"noise\": 2"),
                      "bad.json:7:34: /scenes/stacks/noise: expected a number in [0, 0.5]");
  expect_policy_error(replaced(good, ",\n                  \"reason\": \"ODE's QuickStep timing swings 5% between boots (test)\"", ""),
                      "/quarantine/0: missing 'reason'");
  expect_policy_error(replaced(good, "\"rounds\": 6", "\"rounds\": 5"), "/smoke/rounds: expected at least 6 rounds, got 5");
  expect_policy_error(replaced(good, "\"rounds\": 8", "\"rounds\": 0"), "/suite/rounds: expected an integer in [6,");
  expect_policy_error(replaced(good, "gating/1", "gating/9"), "/schema: expected \"fx2d-bench.gating/1\"");
  expect_policy_error("{ not json", "bad.json:1:4: syntax error: invalid literal");
  // A key as the file spells it, escaped as JSON pointers escape '/' and '~'.
  expect_policy_error(replaced(good, "\"stacks\": {\"noise\"", "\"a/b~c\": {\"nose\""),
                      "bad.json:7:24: /scenes/a~1b~0c/nose: unknown key");
}

// The rounds are judged by a sign test: a policy must ask for at least as many as it can decide on
// at the policy's strictest alpha (sign_test_min_pairs: 6 at 0.05, 13 at 0.001).
TEST(GatePolicyRefusals, RoundsTooFewForTheSignTestToDecideAreRefused) {
  const std::string strict = replaced(test_policy, "\"accuracy_tolerance\": 0.5,", "\"accuracy_tolerance\": 0.5, \"alpha\": 0.001,");
  EXPECT_EQ(sign_test_min_pairs(0.001), 13);
  expect_policy_error(strict, "/suite/rounds: expected at least 13 rounds, got 8");
  EXPECT_EQ(parse_policy(replaced(replaced(strict, "\"rounds\": 8", "\"rounds\": 13"), "\"rounds\": 6", "\"rounds\": 13"),
                         "strict.json")
                .suite.rounds,
            13);
}

TEST(GatePolicyRefusals, CrossEngineComparisonDoesNotGate) {
  json report = comparison({time_row("fx2d", "pile", 1.0, 0.99, 1.01, 0.5)});
  report["mode"] = "cross-engine";
  EXPECT_THROW(judge(report, "x.json", parse_policy(test_policy, "p.json")), InputError);
}

// --- the command line -----------------------------------------------------------------------------

class GateCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("fx2d_gate_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
    write("policy.json", test_policy);
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(directory_ / name) << text;
    return (directory_ / name).string();
  }
  bench_test::Ending gate(std::vector<std::string> arguments) const {
    arguments.insert(arguments.begin(), "gate");
    return bench_test::run_bench(std::move(arguments), directory_);
  }

  fs::path directory_;
};

TEST_F(GateCommand, PrintsTheQuarantineReasonAndExitsOnTheVerdict) {
  const std::string compare = write("compare.json", comparison({time_row("ode", "pile", 1.5, 1.4, 1.6, 0.001),
                                                                time_row("fx2d", "pile", 1.1, 1.08, 1.12, 0.001)})
                                                        .dump());
  const bench_test::Ending ending = gate({compare, "--policy", (directory_ / "policy.json").string()});
  EXPECT_EQ(ending.exit_code, 1) << ending.err;
  EXPECT_NE(ending.out.find("ode pile 600 ms_per_step: ODE's QuickStep timing swings 5% between boots (test)"),
            std::string::npos)
      << ending.out;
  EXPECT_NE(ending.out.find("slower (REGRESSION)"), std::string::npos) << ending.out;

  const bench_test::Ending as_json = gate({compare, "--policy", (directory_ / "policy.json").string(), "--json"});
  const json parsed = json::parse(as_json.out);
  EXPECT_EQ(parsed["schema"], "fx2d-bench.gate/1");
  EXPECT_EQ(parsed["regressions"], 1);
  EXPECT_EQ(parsed["rows"][0]["reason"], "ODE's QuickStep timing swings 5% between boots (test)");
}

TEST_F(GateCommand, TheQuarantineNamesThePolicyFileUsed) {
  fs::copy_file(directory_ / "policy.json", directory_ / "mypolicy.json");
  const std::string compare = write("compare.json", comparison({time_row("ode", "pile", 1.5, 1.4, 1.6, 0.001)}).dump());
  const bench_test::Ending ending = gate({compare, "--policy", (directory_ / "mypolicy.json").string()});
  EXPECT_EQ(ending.exit_code, 0) << ending.err;
  EXPECT_NE(ending.out.find("quarantined, not gating (" + (directory_ / "mypolicy.json").string() + "):"), std::string::npos)
      << ending.out;
}

// Each misuse of `gate` is one line naming what is wrong, exit code 2 (never 4).
TEST_F(GateCommand, EveryMisuseIsOneLineAndExitCodeTwo) {
  const std::string policy = (directory_ / "policy.json").string();
  const std::string compare = write("compare.json", comparison({time_row("fx2d", "pile", 1.0, 0.99, 1.01, 0.5)}).dump());
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/pile.json";
  const std::vector<std::pair<std::vector<std::string>, std::string>> misuses = {
      {{scene, "--policy", policy}, scene + ": expected a fx2d-bench.compare/1 object"},  // wrong file type
      {{compare, "--policy", scene}, ": unknown key; expected one of schema"},            // a scene as the policy
      {{compare}, "--policy is required"},                                                // missing argument
      {{compare, "--policy", policy, "--print-suite", "full"}, "excludes"},               // conflicting options
      {{"--policy", policy, "--print-suite", "nightly"}, "--print-suite"},
      {{"--policy", policy}, "gate: give COMPARE.json to judge"},
      {{compare, "--policy", policy, "--shard", "1/2"}, "--shard requires --print-suite"},
      {{"--policy", policy, "--print-suite", "full", "--shard", "3/2"}, "--shard"},
  };
  for (const auto& [arguments, expected] : misuses) {
    const bench_test::Ending ending = gate(arguments);
    EXPECT_EQ(ending.exit_code, 2) << ending.err;
    EXPECT_EQ(std::ranges::count(ending.err, '\n'), 1) << ending.err;
    EXPECT_NE(ending.err.find(expected), std::string::npos) << ending.err;
  }
}

TEST_F(GateCommand, BadPolicyIsOneLineAndExitCodeTwo) {
  const std::string compare = write("compare.json", comparison({time_row("fx2d", "pile", 1.0, 0.99, 1.01, 0.5)}).dump());
  const std::string policy = write("bad.json", replaced(test_policy, "\"alpha\": 0.05", "\"alpha\": \"5%\""));
  const bench_test::Ending ending = gate({compare, "--policy", policy});
  EXPECT_EQ(ending.exit_code, 2);
  EXPECT_EQ(std::ranges::count(ending.err, '\n'), 1) << ending.err;
  EXPECT_NE(ending.err.find("bad.json:6:43: /defaults/alpha: expected a number"), std::string::npos)
      << ending.err;
  EXPECT_TRUE(ending.out.empty()) << ending.out;
}

TEST_F(GateCommand, PrintsTheSuiteForTheNightlyScript) {
  const bench_test::Ending ending = gate({"--policy", (directory_ / "policy.json").string(), "--print-suite", "full"});
  EXPECT_EQ(ending.exit_code, 0) << ending.err;
  const std::string settings = "engines fx2d,box2d,ode\nrounds 8\nsteps 50\nshard 1/1\nwork_items 1\nwork_list ";
  EXPECT_EQ(ending.out.substr(0, settings.size()), settings) << ending.out;
  EXPECT_TRUE(ending.out.ends_with("\nscene pile 600 pile_600\n")) << ending.out;
}

// The lines of `out` that start with `prefix`, the prefix dropped.
std::vector<std::string> lines_of(const std::string& out, const std::string& prefix) {
  std::vector<std::string> lines;
  std::istringstream stream(out);
  for (std::string line; std::getline(stream, line);)
    if (line.starts_with(prefix)) lines.push_back(line.substr(prefix.size()));
  return lines;
}

// Two shards of the committed suite hold every scene once, balanced by bodies: settling_boxes 800
// and pile 600 against stacks 200 and the jointed scenes as they stand (200, 894 and 200 bodies),
// under one identity of the whole suite. Its scene files are paths from the source tree's root.
TEST_F(GateCommand, PrintsOneShardOfTheSuiteBalancedByBodies) {
  const std::string policy = std::string(FX2D_SOURCE_DIR) + "/ci/gating.json";
  const auto shard = [&](const std::string& suite, const std::string& part) {
    return bench_test::run_bench_from(
        FX2D_SOURCE_DIR, {"gate", "--policy", policy, "--print-suite", suite, "--shard", part}, directory_);
  };
  const bench_test::Ending first = shard("full", "1/2");
  const bench_test::Ending second = shard("full", "2/2");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(lines_of(first.out, "scene "),
            (std::vector<std::string>{"stacks 200 stacks_200", "scenes/joints/chain.json - chain",
                                      "scenes/joints/joint_grid.json - joint_grid",
                                      "scenes/joints/rope.json - rope"}));
  EXPECT_EQ(lines_of(second.out, "scene "),
            (std::vector<std::string>{"pile 600 pile_600", "settling_boxes 800 settling_boxes_800"}));
  EXPECT_EQ(lines_of(first.out, "shard "), std::vector<std::string>{"1/2"});
  EXPECT_EQ(lines_of(first.out, "work_items "), std::vector<std::string>{"6"});
  EXPECT_EQ(lines_of(first.out, "work_list "), lines_of(second.out, "work_list "));
  const bench_test::Ending smoke = shard("smoke", "1/2");
  EXPECT_NE(lines_of(first.out, "work_list "), lines_of(smoke.out, "work_list "));
}

// The night names a scene's files after its file's stem and size: two suite scenes of one name
// would write over each other's, and the policy is refused; one scene at two sizes is two names.
TEST(GatePolicy, TwoSuiteScenesOfOneNameAreRefused) {
  const std::string pile = R"({"scene": "pile", "bodies": 600})";
  expect_policy_error(replaced(test_policy, pile, R"({"scene": "a/rope.json"}, {"scene": "b/rope.json"})"),
                      "/suite/scenes/1/scene: expected a scene a night can name apart from the others, got a "
                      "second 'rope' (its file's stem, and _N at a size)");
  expect_policy_error(
      replaced(test_policy, pile,
               R"({"scene": "pile", "bodies": 600}, {"scene": "scenes/pile.json", "bodies": 600})"),
      "got a second 'pile_600'");
  const Policy sizes = parse_policy(
      replaced(test_policy, pile, R"({"scene": "pile", "bodies": 600}, {"scene": "pile", "bodies": 300})"),
      "policy.json");
  EXPECT_EQ(sizes.suite.scenes[1].name, "pile_300");
}

// A suite's scene without bodies runs as it stands (`-`); one that cannot be read is refused with
// the policy's name, before any night is measured.
TEST_F(GateCommand, ASuiteSceneWithoutBodiesRunsAsItStands) {
  const std::string listed =
      write("listed.json", R"({"schema": "fx2d.scene/1", "bodies": [{"shape": {"circle": 1}}]})");
  const std::string policy = write("files.json", replaced(test_policy, R"({"scene": "pile", "bodies": 600})",
                                                          R"({"scene": "listed.json"})"));
  const auto print_suite = [&] {
    return bench_test::run_bench_from(directory_, {"gate", "--policy", policy, "--print-suite", "full"},
                                      directory_);
  };
  const bench_test::Ending ending = print_suite();
  EXPECT_EQ(ending.exit_code, 0) << ending.err;
  EXPECT_EQ(lines_of(ending.out, "scene "), std::vector<std::string>{"listed.json - listed"});
  fs::remove(listed);
  const bench_test::Ending missing = print_suite();
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(missing.err,
            "fx2d-bench: " + policy +
                ": the full suite's scene: listed.json: no such scene file, nor the name of an embedded "
                "scene (a suite's scene files are read from the working directory)\n");
}

}  // namespace
}  // namespace fxbench

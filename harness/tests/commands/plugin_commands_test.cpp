// Every measuring and reading subcommand with a plugin engine beside the built-in one: run,
// compare, gate, ab, sweep, stability and report, each driven through the fx2d-bench binary as a
// user types it. The plugin is this tree's Fx2D, so each command must give its rows the plugin's
// label and the very figures of the built-in engine; none can break unseen for plugins again.
// Then what a plugin declares (ABI version 4), through Chipmunk2D's plugin: its knobs checked,
// swept and listed, its capabilities refusing a scene before anything is measured.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/bench_process.h"
#include "tests/support/plugin_copies.h"

namespace fxbench {
namespace {

using bench_test::Ending;
using bench_test::run_bench;
using nlohmann::json;

const std::string labelled_plugin = std::string("plugin:") + FX2D_BENCH_PLUGIN + "|label";
const std::string both_engines = "fx2d," + labelled_plugin;
// Small enough that the whole file runs in seconds; stacks has contacts from its first step.
const std::vector<std::string> small_stacks{"stacks", "--bodies", "10", "--steps", "20"};

class PluginCommands : public test::PluginCopies {
 public:
  Ending bench(std::vector<std::string> arguments) const { return run_bench(std::move(arguments), directory_); }

  Ending bench_on_small_stacks(const std::string& command, std::vector<std::string> options) const {
    std::vector<std::string> arguments{command};
    arguments.insert(arguments.end(), small_stacks.begin(), small_stacks.end());
    arguments.insert(arguments.end(), options.begin(), options.end());
    return bench(arguments);
  }

  std::string path(const std::string& name) const { return (directory_ / name).string(); }

  // A run file of Fx2D, Box2D and the plugin on small stacks.
  std::string run_file() const {
    const Ending ended =
        bench_on_small_stacks("run", {"--repeats", "2", "--engine", "box2d," + both_engines, "--out", path("run.h5")});
    EXPECT_EQ(ended.exit_code, 0) << ended.err;
    return path("run.h5");
  }

  // The worst penetration, m, of pile 300 after 120 steps on an engine's `threads` (its sleeping
  // switched off by the knob SLEEP_OFF), once the run is checked to have no NaN and none escaped.
  double pile_penetration(const std::string& engine, const std::string& sleep_off,
                          const std::string& threads) const {
    const std::string solver = "/solver/" + engine + "/";
    const Ending ended =
        bench({"run", "pile", "--bodies", "300", "--steps", "120", "--engine", engine, "--json", "--set",
               solver + sleep_off + "=false", "--set", solver + "threads=" + threads});
    EXPECT_EQ(ended.exit_code, 0) << ended.err;
    const json accuracy = json::parse(ended.out).at("runs").at(0).at("accuracy");
    EXPECT_EQ(accuracy.at("nan"), 0);
    EXPECT_EQ(accuracy.at("escaped"), 0);
    return accuracy.at("max_penetration").get<double>();
  }
};

const json& run_of(const json& summary, const std::string& engine) {
  for (const json& run : summary.at("runs"))
    if (run.at("engine") == engine) return run;
  throw std::runtime_error("no run of " + engine);
}

TEST_F(PluginCommands, RunGivesThePluginsRowTheBuiltInEnginesState) {
  const Ending ended = bench_on_small_stacks("run", {"--repeats", "2", "--engine", both_engines, "--json"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json summary = json::parse(ended.out);
  EXPECT_EQ(run_of(summary, "label").at("state_hash"), run_of(summary, "fx2d").at("state_hash"));
  EXPECT_EQ(run_of(summary, "label").at("accuracy"), run_of(summary, "fx2d").at("accuracy"));
}

TEST_F(PluginCommands, CompareTakesThePluginAsBaseline) {
  const std::string file = run_file();
  const Ending ended = bench({"compare", file, "--baseline", "label", "--json"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json report = json::parse(ended.out);
  std::vector<std::string> judged;
  for (const json& row : report.at("rows")) {
    EXPECT_EQ(row.at("against"), "label") << row.dump();
    if (row.at("metric") == "ms_per_step") judged.push_back(row.at("engine"));
  }
  EXPECT_EQ(judged, (std::vector<std::string>{"fx2d", "box2d"}));
}

TEST_F(PluginCommands, CompareRefusesABaselineTheFileDoesNotHoldInOneLine) {
  const Ending ended = bench({"compare", run_file(), "--baseline", "nobody"});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_EQ(ended.err, "fx2d-bench: " + path("run.h5") + ": no scene has a nobody run and a run of another engine; nothing to compare\n");
}

// An A/B of a plugin against a copy of itself on small stacks.
Ending ab_of_plugin_copies(const PluginCommands& test, const std::string& other) {
  return test.bench_on_small_stacks("ab", {"--a", FX2D_BENCH_PLUGIN, "--b", other, "--rounds", "6", "--json"});
}

TEST_F(PluginCommands, AbOfAPluginAgainstACopyOfItselfFindsTheSamePhysics) {
  const Ending ended = ab_of_plugin_copies(*this, copy_of(FX2D_BENCH_PLUGIN, "other.so"));
  ASSERT_NE(ended.exit_code, 2) << ended.err;
  const json report = json::parse(ended.out);
  int step_rows = 0;
  for (const json& row : report.at("rows")) {
    if (row.at("metric") != "ms_per_step") continue;
    ++step_rows;
    EXPECT_EQ(row.at("physics"), "same");
    EXPECT_EQ(row.at("accuracy").at("change"), "same");
  }
  EXPECT_EQ(step_rows, 1);
}

// The gate's rows for an `ab` of `plugin` against `copy`, another build of it: one, of stacks,
// named after the engine.
void expect_gate_judges_ab_of(const PluginCommands& test, const std::string& plugin, const std::string& copy,
                              const std::string& engine) {
  const Ending ab = test.bench_on_small_stacks("ab", {"--a", plugin, "--b", copy, "--rounds", "6", "--json"});
  ASSERT_NE(ab.exit_code, 2) << ab.err;
  { std::ofstream(test.path("ab.json")) << ab.out; }
  const Ending gate =
      test.bench({"gate", "--policy", std::string(FX2D_SOURCE_DIR) + "/ci/gating.json", test.path("ab.json"), "--json"});
  ASSERT_NE(gate.exit_code, 2) << gate.err;
  const json rows = json::parse(gate.out).at("rows");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("scene"), "stacks");
  EXPECT_EQ(rows[0].at("engine"), engine);
}

TEST_F(PluginCommands, GateJudgesTheAbOfAPlugin) {
  expect_gate_judges_ab_of(*this, FX2D_BENCH_PLUGIN, copy_of(FX2D_BENCH_PLUGIN, "other.so"), "fx2d");
}

TEST_F(PluginCommands, GateJudgesTheAbOfAnotherEnginesPlugin) {
  expect_gate_judges_ab_of(*this, FX2D_BENCH_CHIPMUNK_PLUGIN, copy_of(FX2D_BENCH_CHIPMUNK_PLUGIN, "other.so"),
                           "chipmunk");
}

TEST_F(PluginCommands, SweepMeasuresThePluginsOwnGridAndFront) {
  const Ending ended = bench_on_small_stacks(
      "sweep", {"--repeats", "1", "--fx2d-substeps", "1,2", "--engine", both_engines, "--json", "--out", path("sweep.h5")});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json sweep = json::parse(ended.out);
  std::vector<json> built_in;
  std::vector<json> plugged_in;
  for (const json& point : sweep.at("points"))
    (point.at("engine") == "label" ? plugged_in : built_in).push_back(point);
  ASSERT_EQ(plugged_in.size(), built_in.size());
  ASSERT_GE(plugged_in.size(), 3u);  // two swept substep counts and the scene's own
  for (std::size_t i = 0; i < plugged_in.size(); ++i) {
    EXPECT_EQ(plugged_in[i].at("settings"), built_in[i].at("settings"));
    EXPECT_EQ(plugged_in[i].at("primary_error"), built_in[i].at("primary_error"));
  }
  int plugin_fronts = 0;
  for (const json& front : sweep.at("fronts")) plugin_fronts += front.at("engine") == "label" ? 1 : 0;
  EXPECT_EQ(plugin_fronts, 1);
  EXPECT_TRUE(std::filesystem::exists(path("sweep.h5")));
}

TEST_F(PluginCommands, StabilityFindsThePluginsBoundaryWhereTheBuiltInEnginesIs) {
  const Ending ended = bench({"stability", "--quick", "--test", "card_house", "--engine", both_engines, "--json"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json results = json::parse(ended.out).at("results");
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[1].at("engine"), "label");
  EXPECT_EQ(results[1].at("settings"), results[0].at("settings"));
  EXPECT_EQ(results[1].at("first_fail"), results[0].at("first_fail"));
  EXPECT_EQ(results[1].at("last_pass"), results[0].at("last_pass"));
}

TEST_F(PluginCommands, ReportDrawsThePluginsRuns) {
  const std::string file = run_file();
  const Ending ended = bench({"report", file, "-o", path("report")});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  std::ifstream page(path("report/index.html"));
  const std::string html{std::istreambuf_iterator<char>(page), {}};
  // The engine's chip in a row of the runs' table, not merely the word: the command line in the
  // provenance table names it too.
  EXPECT_NE(html.find(">label</span></td>"), std::string::npos);
}

// Chipmunk2D, a plugin of another engine than Fx2D, in compare, report and sweep as the issue asks:
// its rows judged against Fx2D, its chip in the report, its own front.
TEST_F(PluginCommands, ChipmunkIsJudgedByCompareAndDrawnByReport) {
  const Ending run = bench_on_small_stacks("run", {"--repeats", "2", "--engine", "fx2d,chipmunk", "--out", path("c.h5")});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Ending compared = bench({"compare", path("c.h5"), "--baseline", "fx2d", "--json"});
  ASSERT_EQ(compared.exit_code, 0) << compared.err;
  const json report = json::parse(compared.out);
  int chipmunk_step_rows = 0;
  for (const json& row : report.at("rows"))
    chipmunk_step_rows += row.at("engine") == "chipmunk" && row.at("metric") == "ms_per_step" ? 1 : 0;
  EXPECT_EQ(chipmunk_step_rows, 1) << compared.out;
  const Ending drawn = bench({"report", path("c.h5"), "-o", path("report")});
  ASSERT_EQ(drawn.exit_code, 0) << drawn.err;
  std::ifstream page(path("report/index.html"));
  const std::string html{std::istreambuf_iterator<char>(page), {}};
  // A chip in a row of the runs' table; the page's header names every registered engine, run or not.
  EXPECT_NE(html.find(">chipmunk</span></td>"), std::string::npos);
}

TEST_F(PluginCommands, SweepOfEveryEngineGivesChipmunkItsOwnFront) {
  const Ending ended = bench_on_small_stacks("sweep", {"--repeats", "1", "--engine", "all", "--json"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json sweep = json::parse(ended.out);
  std::vector<std::string> fronts;
  for (const json& front : sweep.at("fronts")) fronts.push_back(front.at("engine"));
  EXPECT_EQ(fronts, (std::vector<std::string>{"fx2d", "box2d", "ode", "chipmunk"}));
  int chipmunk_points = 0;
  for (const json& point : sweep.at("points")) chipmunk_points += point.at("engine") == "chipmunk" ? 1 : 0;
  EXPECT_GE(chipmunk_points, 3) << "the iterations axis and the scene's own point";
}

TEST_F(PluginCommands, AKnobOutOfItsRangeIsRefusedInOneLineBeforeMeasuring) {
  const Ending ended =
      bench({"run", "stacks", "--engine", "chipmunk", "--set", "/solver/chipmunk/iterations=0"});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_EQ(ended.err,
            "fx2d-bench: --set /solver/chipmunk/iterations=0: /solver/chipmunk/iterations: expected an "
            "integer from 1 "
            "to 1000, got 0\n");
  EXPECT_EQ(ended.out, "");
}

TEST_F(PluginCommands, AKeyThatIsNoKnobIsRefusedWithTheKnobsItCouldBe) {
  const Ending ended =
      bench({"run", "stacks", "--engine", "chipmunk", "--set", "/solver/chipmunk/iteration=5"});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_EQ(
      ended.err,
      "fx2d-bench: --set /solver/chipmunk/iteration=5: /solver/chipmunk/iteration: not a knob of chipmunk; "
      "expected one of "
      "iterations, sleeping, sleep_time, collision_slop, threads\n");
}

// chipmunk.threads 2 steps a hasty space (cpHastySpace.h) with two solver threads: the pile stays
// whole and overlaps as much as on one thread. Not bit for bit: repeats on two threads may end in
// different states (harness/README.md), so only the physics is compared, within a margin that
// rests on runs: eleven on an idle machine ended 98.8 to 102.3 mm deep against one thread's 101.4,
// and one in CI, with both cores busy, 96.0 (5 mm, the margin before, failed it).
TEST_F(PluginCommands, ChipmunkOnTwoThreadsKeepsThePileAsOnOne) {
  const double one = pile_penetration("chipmunk", "sleeping", "1");
  EXPECT_NEAR(pile_penetration("chipmunk", "sleeping", "2"), one, 0.15 * one)
      << "worst penetration, m; one thread: " << one;
}

TEST_F(PluginCommands, ChipmunkThreadsBeyondTheTwoItRunsAreRefusedInOneLine) {
  const Ending ended =
      bench({"run", "stacks", "--engine", "chipmunk", "--set", "/solver/chipmunk/threads=3"});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_EQ(
      ended.err,
      "fx2d-bench: --set /solver/chipmunk/threads=3: /solver/chipmunk/threads: expected an integer from 1 to "
      "2, got 3\n");
}

// Fx2D's, Box2D's and ODE's blocks are checked once, by the engine's knobs, as any engine's: one line
// naming the scene's file, the value's line and column, the JSON pointer and what the knob takes,
// exit code 2, nothing measured.
TEST_F(PluginCommands, BuiltInEnginesBlocksAreCheckedByTheirKnobsInOneLineNamingTheFile) {
  const std::string file = path("t.json");
  std::string text;
  const auto error_of = [&](const std::string& engine, const std::string& block) {
    text = R"({"schema": "fx2d.scene/1", "bodies": [{"shape": {"circle": 1}}], "solver": {")" + engine +
           R"(": )" + block + "}}";
    std::ofstream(file) << text;
    const Ending ended = bench({"run", file, "--engine", engine});
    EXPECT_EQ(ended.exit_code, 2) << block;
    EXPECT_EQ(ended.out, "") << block;
    return ended.err;
  };
  struct Case {
    std::string engine, block, error;  // the error after "/solver/<engine>/"
  };
  const std::vector<Case> cases{
      {"fx2d", R"({"sleeping": 1})", "sleeping: expected true or false, got 1"},
      {"fx2d", R"({"relax_passes": 0})", "relax_passes: expected an integer from 1 to 1000, got 0"},
      {"fx2d", R"({"joint_relax_passes": 0})",
       "joint_relax_passes: expected an integer from 1 to 1000, got 0"},
      {"fx2d", R"({"max_push_speed": 0})", "max_push_speed: expected a number from 0.001 to 1e+06, got 0"},
      {"fx2d", R"({"workers": 65})", "workers: expected an integer from 1 to 64, got 65"},
      {"fx2d", R"({"substep": 3})",
       "substep: not a knob of fx2d; expected one of substeps, velocity_passes, sleeping, relax_passes, "
       "max_push_speed, workers, rest_schedule, shallow_schedule, impact_velocity_passes, "
       "joint_relax_passes"},
      {"box2d", R"({"velocity_iterations": 0})",
       "velocity_iterations: expected an integer from 1 to 1000, got 0"},
      {"box2d", R"({"position_iterations": 2.5})",
       "position_iterations: expected an integer from 0 to 1000, got 2.5"},
      {"box2d", R"({"sleeping": 0})", "sleeping: expected true or false, got 0"},
      {"box2d", R"({"velocity": 3})",
       "velocity: not a knob of box2d; expected one of velocity_iterations, position_iterations, sleeping"},
      {"ode", R"({"iterations": -1})", "iterations: expected an integer from 1 to 1000, got -1"},
      {"ode", R"({"erp": 1.5})", "erp: expected a number from 0 to 1, got 1.5"},
      {"ode", R"({"cfm": 2})", "cfm: expected a number from 0 to 1, got 2.0"},
      {"ode", R"({"auto_disable": 1})", "auto_disable: expected true or false, got 1"},
      {"ode", R"({"iteration": 5})",
       "iteration: not a knob of ode; expected one of iterations, erp, cfm, auto_disable, threads"},
  };
  for (const Case& bad : cases) {
    const std::string error = error_of(bad.engine, bad.block);
    // The block's one value, on the file's one line.
    const std::size_t column = text.find(bad.block) + bad.block.find(": ") + 3;
    EXPECT_EQ(error, "fx2d-bench: " + file + ":1:" + std::to_string(column) + ": /solver/" + bad.engine +
                         "/" + bad.error + "\n");
  }
}

TEST_F(PluginCommands, SweepAxisSweepsAPluginsKnobBesideTheScenesOwnValue) {
  const Ending ended = bench_on_small_stacks(
      "sweep", {"--repeats", "1", "--engine", "chipmunk", "--axis", "chipmunk.iterations=3,7", "--json"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json sweep = json::parse(ended.out);
  std::vector<int> iterations;
  for (const json& point : sweep.at("points")) iterations.push_back(point.at("settings").at("iterations"));
  EXPECT_EQ(iterations, (std::vector<int>{3, 7, 10}));  // 10: the knob's default, the scene's own point
}

TEST_F(PluginCommands, SweepAxisSetsTheShortFormsOfBuiltInEngines) {
  const Ending ended = bench_on_small_stacks(
      "sweep", {"--repeats", "1", "--engine", "box2d", "--axis", "box2d.velocity_iterations=2,3", "--box2d-position",
                "3", "--json"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json sweep = json::parse(ended.out);
  std::vector<int> iterations;
  for (const json& point : sweep.at("points"))
    iterations.push_back(point.at("settings").at("velocity_iterations"));
  EXPECT_EQ(iterations, (std::vector<int>{2, 3, 8}));  // 8: the scene's own
}

TEST_F(PluginCommands, SweepAxisRefusesAKnobTheEngineLacks) {
  const Ending ended =
      bench_on_small_stacks("sweep", {"--engine", "chipmunk", "--axis", "chipmunk.substeps=1,2"});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_EQ(ended.err,
            "fx2d-bench: --axis chipmunk.substeps=1,2: chipmunk has no knob substeps (fx2d-bench engines "
            "lists them)\n");
}

TEST_F(PluginCommands, EnginesListsEachEnginesKnobs) {
  const Ending ended = bench({"engines"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  EXPECT_NE(
      ended.out.find("chipmunk.iterations, chipmunk.sleeping, chipmunk.sleep_time, chipmunk.collision_slop, "
                     "chipmunk.threads"),
      std::string::npos)
      << ended.out;
  EXPECT_NE(ended.out.find("fx2d.substeps, fx2d.velocity_passes"), std::string::npos) << ended.out;
  EXPECT_NE(ended.out.find("box2d.velocity_iterations, box2d.position_iterations, box2d.sleeping"),
            std::string::npos)
      << ended.out;
  EXPECT_NE(ended.out.find("ode.iterations, ode.erp, ode.cfm, ode.auto_disable, ode.threads"),
            std::string::npos)
      << ended.out;
}

TEST_F(PluginCommands, EnginesKnobsGivesEachKnobsRangeDefaultAndDescription) {
  const Ending ended = bench({"engines", "--knobs", "--engine", "chipmunk"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  // iterations, sleeping, sleep_time, collision_slop, threads
  EXPECT_EQ(std::count(ended.out.begin(), ended.out.end(), '\n'), 5) << ended.out;
  EXPECT_NE(ended.out.find("chipmunk.iterations      an integer from 1 to 1000  default 10     solver iterations per "
                           "step (cpSpaceSetIterations)\n"),
            std::string::npos)
      << ended.out;
  EXPECT_NE(ended.out.find("chipmunk.collision_slop  a number from 0 to 1       default 0.005  overlap allowed"),
            std::string::npos)
      << ended.out;
}

TEST_F(PluginCommands, EnginesKnobsGivesOdesThreadsAndTheirRange) {
  const Ending ended = bench({"engines", "--knobs", "--engine", "ode"});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  EXPECT_NE(ended.out.find(
                "ode.threads       an integer from 1 to 8     default 1      threads stepping the world"),
            std::string::npos)
      << ended.out;
}

// A plugin named on the command line is listed as any engine: its label, its file, its knobs.
TEST_F(PluginCommands, EnginesListsAPluginGivenByPathWithItsKnobs) {
  const Ending ended = bench({"engines", "--json", "--engine", labelled_plugin});
  ASSERT_EQ(ended.exit_code, 0) << ended.err;
  const json engines = json::parse(ended.out).at("engines");
  ASSERT_EQ(engines.size(), 1u);
  EXPECT_EQ(engines[0].at("name"), "label");
  EXPECT_EQ(engines[0].at("plugin"), std::filesystem::absolute(FX2D_BENCH_PLUGIN).lexically_normal().string());
  const json& substeps = engines[0].at("knobs").at(0);
  EXPECT_EQ(substeps.at("name"), "substeps");
  EXPECT_EQ(substeps.at("type"), "integer");
  EXPECT_EQ(substeps.at("default"), 8);
  EXPECT_FALSE(substeps.at("description").get<std::string>().empty());
}

// The same refusal from the command line, as the issue asks of every built-in engine's knobs.
TEST_F(PluginCommands, AnOdeKnobOutOfRangeFromSetIsRefusedInOneLine) {
  for (const auto& [set, error] : std::vector<std::pair<std::string, std::string>>{
           {"/solver/ode/iterations=-1", "iterations: expected an integer from 1 to 1000, got -1"},
           {"/solver/ode/cfm=1.5", "cfm: expected a number from 0 to 1, got 1.5"},
           {"/solver/ode/threads=9", "threads: expected an integer from 1 to 8, got 9"}}) {
    const Ending ended = bench({"run", "stacks", "--engine", "ode", "--set", set});
    EXPECT_EQ(ended.exit_code, 2) << set;
    EXPECT_EQ(ended.err, "fx2d-bench: --set " + set + ": /solver/ode/" + error + "\n");
    EXPECT_EQ(ended.out, "") << set;
  }
}

// ode.threads 2 steps the world on ODE's own pool of two threads: the pile stays whole and
// overlaps about as much as on one thread. Not bit for bit: every run on two threads ends in a
// different state (scenes/README.md); eleven runs gave a worst penetration of 92 to 112 mm
// against one thread's 99, so a quarter of one thread's is the margin.
TEST_F(PluginCommands, OdeOnTwoThreadsKeepsThePileAsOnOne) {
  const double one = pile_penetration("ode", "auto_disable", "1");
  EXPECT_NEAR(pile_penetration("ode", "auto_disable", "2"), one, 0.25 * one)
      << "worst penetration, m; one thread: " << one;
}

TEST_F(PluginCommands, AnEngineWithoutBulletsRefusesASceneWithOneNamingIt) {
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/tests/joints_and_bounce.json";
  const Ending ended = bench({"run", scene, "--engine", "chipmunk", "--set", "/bodies/1/bullet=true"});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_NE(ended.err.find("engine chipmunk cannot build bullets"), std::string::npos) << ended.err;
}

// ODE, built in, declares no bullets either: it has no continuous collision.
TEST_F(PluginCommands, OdeRefusesASceneWithABulletNamingIt) {
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/tests/falling_circle.json";
  const Ending ended = bench({"run", scene, "--engine", "ode", "--set", "/bodies/0/bullet=true"});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_EQ(ended.err, "fx2d-bench: scene falling_circle: engine ode cannot build bullets\n");
}

TEST_F(PluginCommands, AbRefusesBuildsOfTwoDifferentEngines) {
  const Ending ended =
      bench_on_small_stacks("ab", {"--a", FX2D_BENCH_PLUGIN, "--b", FX2D_BENCH_CHIPMUNK_PLUGIN});
  EXPECT_EQ(ended.exit_code, 2);
  EXPECT_NE(ended.err.find("--a is fx2d and --b is chipmunk; ab judges two builds of one engine"),
            std::string::npos)
      << ended.err;
}

TEST_F(PluginCommands, AbTimesTwoBuildsOfChipmunk) {
  const Ending ended = bench_on_small_stacks(
      "ab", {"--a", FX2D_BENCH_CHIPMUNK_PLUGIN, "--b", copy_of(FX2D_BENCH_CHIPMUNK_PLUGIN, "other.so"),
             "--rounds", "6", "--json"});
  ASSERT_NE(ended.exit_code, 2) << ended.err;
  const json report = json::parse(ended.out);
  ASSERT_FALSE(report.at("rows").empty());
  EXPECT_EQ(report.at("rows")[0].at("physics"), "same");
}

}  // namespace
}  // namespace fxbench

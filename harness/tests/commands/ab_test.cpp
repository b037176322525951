// `fx2d-bench ab`: the ABBA order, the split of an A/B file back into two result sets, the
// command end to end on prebuilt plugins (its verdict is the one `compare` gives on its file), the
// counts of exactly the plugins it timed, the one-line refusals of every misuse, the name of the
// directory it builds a plugin in, a plugin built in this build tree against the same source built
// by ab (the same instructions), and the statistical proof of the method on this machine: the same
// build against itself is judged "no change" (also when one side is that build by ab), and a build
// 5% slower per step is judged "slower", each in at least 19 of 20 repetitions.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "analysis/compare.h"
#include "common/errors.h"
#include "tests/support/bench_process.h"
#include "engines/plugin_engine.h"
#include "measure/ab_builds.h"
#include "measure/interleave.h"
#include "tests/support/plugin_copies.h"
#include "scene/scene_loader.h"
#include "stats/statistics.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;
using bench_test::Ending;
using bench_test::run_bench;
using bench_test::run_bench_from;

using AbTest = test::PluginCopies;

bool one_line(const std::string& text) { return !text.empty() && text.find('\n') == text.size() - 1; }

// The row of `metric` in compare JSON.
nlohmann::json row_of(const nlohmann::json& verdict, const std::string& metric) {
  for (const nlohmann::json& row : verdict["rows"])
    if (row["metric"] == metric) return row;
  ADD_FAILURE() << "no " << metric << " row in " << verdict.dump();
  return {};
}

// Valgrind cannot run an AddressSanitizer build, and may not be installed.
bool valgrind_can_count() { return !FX2D_BENCH_SANITIZED && std::system("valgrind --version > /dev/null 2>&1") == 0; }

// `worktree` needs the sources to be a git checkout (a source archive is not).
bool sources_are_a_checkout() { return fs::exists(fs::path(FX2D_SOURCE_DIR) / ".git"); }

// The directory ab builds a plugin in is named by what the build is made from. Two plugin projects
// with the same files in two places (a git worktree of this checkout) get two directories: CMake
// will not configure one directory from two sources, and ab failed on the second.
TEST(AbBuildKey, ChangesWithTheArgumentsThePluginFilesAndWhereTheProjectIs) {
  const fs::path project = fs::path(FX2D_SOURCE_DIR) / "harness" / "plugin";
  const fs::path copy = fs::temp_directory_path() / ("fx2d_ab_build_key_" + std::to_string(getpid()));
  fs::remove_all(copy);
  fs::create_directories(copy);
  for (const fs::directory_entry& entry : fs::directory_iterator(project)) {
    if (entry.is_regular_file()) fs::copy_file(entry.path(), copy / entry.path().filename());
  }
  const std::string key = plugin_build_key({"-DFX2D_PROFILE=ON"}, project);
  EXPECT_EQ(key, plugin_build_key({"-DFX2D_PROFILE=ON"}, project));
  EXPECT_NE(key, plugin_build_key({"-DFX2D_PROFILE=OFF"}, project));
  const std::string copied = plugin_build_key({"-DFX2D_PROFILE=ON"}, copy);
  EXPECT_NE(key, copied);
  std::ofstream(copy / "fx2d_plugin.cpp", std::ios::app) << "\n";
  EXPECT_NE(copied, plugin_build_key({"-DFX2D_PROFILE=ON"}, copy));
  fs::remove_all(copy);
}

TEST(AbRounds, AlternateABBA) {
  std::string order;
  for (int round = 0; round < 12; ++round) order += variant_of_round(round) == Variant::a ? 'A' : 'B';
  EXPECT_EQ(order, "ABBAABBAABBA");
}

// --a-cmake and --b-cmake split as a shell would, so that one CMake argument may hold spaces.
TEST(AbCmakeWords, SplitAsAShellSoAQuotedArgumentKeepsItsSpaces) {
  using Words = std::vector<std::string>;
  EXPECT_EQ(cmake_words("--b", ""), Words{});
  EXPECT_EQ(cmake_words("--b", " -DFX2D_NATIVE=ON \t-DFX2D_PROFILE=OFF "),
            (Words{"-DFX2D_NATIVE=ON", "-DFX2D_PROFILE=OFF"}));
  EXPECT_EQ(cmake_words("--b", "-DCMAKE_CXX_FLAGS='-falign-functions=64 -falign-loops=64' -DX=1"),
            (Words{"-DCMAKE_CXX_FLAGS=-falign-functions=64 -falign-loops=64", "-DX=1"}));
  EXPECT_EQ(cmake_words("--b", "\"-DA=say \\\"hi\\\" \\\\ 'x'\" ''"), (Words{"-DA=say \"hi\" \\ 'x'", ""}));
  EXPECT_EQ(cmake_text(cmake_words("--b", "-DX=1  -DCMAKE_CXX_FLAGS='-O2 -g'")),
            "-DX=1 '-DCMAKE_CXX_FLAGS=-O2 -g'");
  EXPECT_EQ(cmake_text(cmake_words("--b", "-DX= ''")), "-DX= ''");
  try {
    cmake_words("--a", "-DX='a b");
    ADD_FAILURE() << "an unclosed quote was accepted";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "--a-cmake: the quote at character 5 of `-DX='a b` is never closed; expected a matching '");
  }
}

TEST(AbVariants, SplitOnlyAFileOfAAndBRunsIntoTwoResultSets) {
  ResultSet file;
  file.provenance.hostname = "machine";
  file.runs.resize(2);
  file.runs[0].engine = variant_engine_name("fx2d", Variant::a);
  file.runs[1].engine = variant_engine_name("fx2d", Variant::b);
  file.runs[1].repeats = 7;
  const auto split = split_variants(file);
  ASSERT_TRUE(split.has_value());
  ASSERT_EQ(split->a.runs.size(), 1u);
  ASSERT_EQ(split->b.runs.size(), 1u);
  EXPECT_EQ(split->a.runs[0].engine, "fx2d");
  EXPECT_EQ(split->b.runs[0].engine, "fx2d");
  EXPECT_EQ(split->b.runs[0].repeats, 7);
  EXPECT_EQ(split->b.provenance.hostname, "machine");

  file.runs.emplace_back().engine = "box2d";  // a run file, not an A/B file
  EXPECT_FALSE(split_variants(file).has_value());
  file.runs.resize(1);  // A alone
  EXPECT_FALSE(split_variants(file).has_value());
}

TEST_F(AbTest, PrebuiltPluginsGiveAFileThatCompareJudgesTheSameWay) {
  const std::string out = (directory_ / "ab.h5").string();
  const Ending ab = run_bench({"ab", "--a", copy_of(FX2D_BENCH_PLUGIN, "a.so"), "--b", copy_of(FX2D_BENCH_PLUGIN, "b.so"),
                               "stacks", "--bodies", "20", "--steps", "20", "--rounds", "6", "--out", out, "--json"},
                              directory_);
  ASSERT_TRUE(ab.exit_code == 0 || ab.exit_code == 1 || ab.exit_code == 3) << ab.exit_code << ": " << ab.err;
  const auto verdict = nlohmann::json::parse(ab.out);
  EXPECT_EQ(verdict["schema"], compare_schema);
  EXPECT_EQ(verdict["mode"], "ab");
  ASSERT_FALSE(verdict["rows"].empty());
  EXPECT_EQ(verdict["rows"][0]["engine"], "fx2d");
  EXPECT_EQ(verdict["rows"][0]["physics"], "same");
  EXPECT_EQ(verdict["rows"][0]["repeats_a"], 6);

  const ResultSet file = read_results_h5(out);
  ASSERT_EQ(file.runs.size(), 2u);
  EXPECT_EQ(file.runs[0].engine, "fx2d@A");
  EXPECT_EQ(file.runs[1].engine, "fx2d@B");
  EXPECT_NE(file.runs[0].engine_version.find("a.so"), std::string::npos) << file.runs[0].engine_version;
  EXPECT_NE(file.runs[1].engine_version.find("b.so"), std::string::npos) << file.runs[1].engine_version;
  EXPECT_EQ(file.runs[0].engine_settings,
            "relax_passes=3 sleeping=true substeps=8 velocity_passes=1");  // the scene's fx2d block

  const Ending compare = run_bench({"compare", out, "--json"}, directory_);
  EXPECT_EQ(compare.exit_code, ab.exit_code) << compare.err;
  EXPECT_EQ(nlohmann::json::parse(compare.out), verdict);
}

// The built-in engine against this build tree's plugin: the same code, called in the binary or in a
// loaded library, so the two step the same trajectories (physics "same") and what differs is the
// cost of the call (harness/README.md measures it).
TEST_F(AbTest, TheBuiltInEngineAgainstThisBuildsPluginIsTheSamePhysics) {
  const std::string out = (directory_ / "ab.h5").string();
  const Ending ab = run_bench({"ab", "--a", "built-in", "--b", FX2D_BENCH_PLUGIN, "stacks", "--bodies", "20", "--steps",
                               "20", "--rounds", "6", "--out", out, "--json"},
                              directory_);
  ASSERT_TRUE(ab.exit_code == 0 || ab.exit_code == 1 || ab.exit_code == 3) << ab.exit_code << ": " << ab.err;
  EXPECT_NE(ab.err.find("(linked into this fx2d-bench)\n"), std::string::npos) << ab.err;
  EXPECT_NE(ab.err.find(std::string("(plugin ") + FX2D_BENCH_PLUGIN + ")\n"), std::string::npos) << ab.err;
  EXPECT_EQ(row_of(nlohmann::json::parse(ab.out), "ms_per_step")["physics"], "same");
  const ResultSet file = read_results_h5(out);
  ASSERT_EQ(file.runs.size(), 2u);
  EXPECT_EQ(file.runs[0].engine, "fx2d@A");
  EXPECT_NE(file.runs[0].engine_version.find("built-in"), std::string::npos) << file.runs[0].engine_version;
}

// ci/nightly gates on these counts: they must be of the two plugins ab timed and named, whatever
// else its cache holds. B spins after each step (the slow test plugin), so its count is larger.
TEST_F(AbTest, CountsAreOfExactlyThePluginsTimedAndNamed) {
  if (!valgrind_can_count()) GTEST_SKIP() << "needs valgrind, outside a sanitizer build";
  setenv("FX2D_BENCH_TEST_SLOWDOWN", "0.5", 1);
  const std::string a = copy_of(FX2D_BENCH_PLUGIN, "a.so");
  const std::string b = copy_of(FX2D_BENCH_SLOW_PLUGIN, "b.so");
  const Ending ab = run_bench({"ab", "--a", a, "--b", b, "pile", "--bodies", "30", "--steps", "10", "--rounds", "6",
                               "--counter", "instructions", "--json"},
                              directory_);
  unsetenv("FX2D_BENCH_TEST_SLOWDOWN");
  ASSERT_TRUE(ab.exit_code == 0 || ab.exit_code == 1 || ab.exit_code == 3) << ab.exit_code << ": " << ab.err;
  EXPECT_NE(ab.err.find("A = "), std::string::npos) << ab.err;
  EXPECT_NE(ab.err.find("(plugin " + a + ")\n"), std::string::npos) << ab.err;
  EXPECT_NE(ab.err.find("(plugin " + b + ")\n"), std::string::npos) << ab.err;
  const nlohmann::json counted = row_of(nlohmann::json::parse(ab.out), "instructions_per_step");
  EXPECT_EQ(counted["verdict"], "slower") << counted.dump();
  EXPECT_GT(counted["ratio"].get<double>(), 1.1) << counted.dump();
}

// The same source built in this build tree and by ab's plugin project (ab_builds.h) is the same
// code: they once differed in visibility (ab's project compiled Fx2D with -fvisibility=hidden),
// which let GCC inline differently, 3.2% fewer instructions and 0.955 in time on pile 60. Run from
// the checkout, `worktree` is it, and its path is printed.
TEST_F(AbTest, APluginOfThisBuildTreeAndTheCheckoutBuiltByAbCountTheSameInstructions) {
  if (!valgrind_can_count() || !sources_are_a_checkout())
    GTEST_SKIP() << "needs valgrind and a git checkout, outside a sanitizer build";
  const Ending ab = run_bench_from(FX2D_SOURCE_DIR,
                                   {"ab", "--a", FX2D_BENCH_PLUGIN, "--b", "worktree", "pile", "--bodies", "60", "--steps",
                                    "20", "--rounds", "6", "--counter", "instructions", "--json"},
                                   directory_);
  ASSERT_TRUE(ab.exit_code == 0 || ab.exit_code == 1 || ab.exit_code == 3) << ab.exit_code << ": " << ab.err;
  EXPECT_NE(ab.err.find("B = 0.1.0 worktree " + fs::canonical(FX2D_SOURCE_DIR).string() + " (of "), std::string::npos)
      << ab.err;
  const nlohmann::json counted = row_of(nlohmann::json::parse(ab.out), "instructions_per_step");
  EXPECT_EQ(counted["a"], counted["b"]) << counted.dump();
  // The plugin's compiled-in description names today's HEAD, not the one of its cache entry's
  // first build: its build directory is configured again when the description changes.
  const std::string marker = "(plugin ";
  const std::size_t plugin_at = ab.err.rfind(marker);
  ASSERT_NE(plugin_at, std::string::npos) << ab.err;
  const fs::path plugin =
      ab.err.substr(plugin_at + marker.size(), ab.err.find(")\n", plugin_at) - plugin_at - marker.size());
  std::ifstream cache(plugin.parent_path() / "CMakeCache.txt");
  const std::string cached{std::istreambuf_iterator<char>(cache), {}};
  const std::size_t head_at = ab.err.find(" (of ", ab.err.find("B = 0.1.0 worktree")) + 5;
  const std::string head = ab.err.substr(head_at, ab.err.find(')', head_at) - head_at);
  EXPECT_NE(cached.find("FX2D_BENCH_PLUGIN_DESCRIPTION:STRING=worktree " +
                        fs::canonical(FX2D_SOURCE_DIR).string() + " (of " + head + ")"),
            std::string::npos)
      << head;
}

// `worktree` is the checkout of the current directory; outside one there is none to measure.
TEST_F(AbTest, WorktreeOutsideAGitCheckoutIsOneLineAndExitCodeTwo) {
  const Ending ending =
      run_bench_from(directory_, {"ab", "--a", FX2D_BENCH_PLUGIN, "--b", "worktree", "--rounds", "6"}, directory_);
  EXPECT_EQ(ending.exit_code, 2) << ending.err;
  EXPECT_TRUE(one_line(ending.err)) << ending.err;
  EXPECT_NE(ending.err.find("--b worktree: the current directory " + directory_.string() + " is not in a git checkout"),
            std::string::npos)
      << ending.err;
}

// Both builds are resolved before either is built: a typo in B costs nothing.
TEST_F(AbTest, AnUnknownRevisionIsRefusedBeforeTheOtherSideIsBuilt) {
  setenv("XDG_CACHE_HOME", (directory_ / "cache").c_str(), 1);
  const Ending ending = run_bench({"ab", "--a", "HEAD", "--b", "no-such-revision"}, directory_);
  unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(ending.exit_code, 2) << ending.err;
  EXPECT_TRUE(one_line(ending.err)) << ending.err;
  EXPECT_NE(ending.err.find("--b no-such-revision: not a plugin file"), std::string::npos) << ending.err;
  EXPECT_FALSE(fs::exists(directory_ / "cache" / "fx2d-bench" / "ab"));
}

TEST(AbRounds, TheFewestRoundsAcceptedAreTheFewestTheSignTestCanDecideOn) {
  const int fewest = sign_test_min_pairs(CompareSettings{}.rules.alpha);
  const auto p_all_slower = [](int rounds) {
    const std::vector<double> a(static_cast<std::size_t>(rounds), 1.0);
    const std::vector<double> b(static_cast<std::size_t>(rounds), 1.3);
    return paired_sign_test(a, b).p_value;
  };
  EXPECT_EQ(fewest, 6);  // the measurement: "slower" only from 6 rounds, p 0.074 at 5
  EXPECT_GE(p_all_slower(fewest - 1), 0.05);
  EXPECT_LT(p_all_slower(fewest), 0.05);
}

// A time budget may stop the rounds before they can decide: the output says so.
TEST_F(AbTest, RoundsCutShortByTheTimeBudgetAreSaidToBeTooFewToDecide) {
  const Ending ab = run_bench({"ab", "--a", copy_of(FX2D_BENCH_PLUGIN, "a.so"), "--b", copy_of(FX2D_BENCH_PLUGIN, "b.so"),
                               "pile", "--bodies", "300", "--steps", "50", "--rounds", "6", "--time-budget", "0.001"},
                              directory_);
  EXPECT_EQ(ab.exit_code, 3) << ab.err;  // inconclusive: fewer than 3 rounds
  EXPECT_NE(ab.err.find("fx2d-bench: pile 300: --time-budget allowed "), std::string::npos) << ab.err;
  EXPECT_NE(ab.err.find(" rounds: the sign test over fewer than 6 cannot reach p < 0.05, so no slowdown however large "
                        "can be judged\n"),
            std::string::npos)
      << ab.err;
}

// Each misuse of `ab` is one line naming what is wrong, exit code 2 (never 4), before any build.
TEST_F(AbTest, EveryMisuseIsOneLineAndExitCodeTwo) {
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/pile.json";
  const std::string plugin = FX2D_BENCH_PLUGIN;
  const std::vector<std::pair<std::vector<std::string>, std::string>> misuses = {
      {{"ab", "--a", scene, "--b", plugin}, "--a: "},                              // a scene is not a plugin
      {{"ab", "--a", plugin}, "--b is required"},                                  // missing argument
      {{"ab", "--a", plugin, "--b", plugin, "--json", "--markdown"}, "excludes"},  // conflicting options
      {{"ab", "--a", plugin, "--b", plugin, "--b-cmake", "-DFX2D_NATIVE=ON"}, "--b-cmake: applies to"},
      {{"ab", "--a", plugin, "--b", "worktree", "--b-cmake", "-DX=\"a b"},
       "--b-cmake: the quote at character 5"},
      {{"ab", "--a", "built-in", "--b", plugin, "--a-cmake", "-DFX2D_NATIVE=ON"},
       "--a-cmake: applies to a git revision or worktree, not to the built-in engine"},
      {{"ab", "--a", plugin, "--b", plugin, "--rounds", "3"},
       "--rounds: expected an integer in [6, 100000]; 3 rounds:"},
      {{"ab", "--a", plugin, "--b", plugin, "--rounds", "many"},
       "--rounds: expected an integer in [6, 100000], got many"},
      {{"ab", "--a", plugin, "--b", plugin, "--counter", "cycles"}, "--counter"},
      {{"ab", "--a", plugin, "--b", plugin, "--force"}, "--force requires --out"},
      {{"ab", "--a", plugin, "--b", plugin, "--rounds"}, "--rounds"},  // missing value
  };
  for (const auto& [arguments, expected] : misuses) {
    const Ending ending = run_bench(arguments, directory_);
    EXPECT_EQ(ending.exit_code, 2) << arguments.back() << ": " << ending.err;
    EXPECT_TRUE(one_line(ending.err)) << ending.err;
    EXPECT_NE(ending.err.find(expected), std::string::npos) << ending.err;
  }
}

// An installed fx2d-bench may outlive the tree it was built from, whose harness/plugin project builds
// revisions: --source, else FX2D_SOURCE, names another; with none, one line says what to pass.
TEST_F(AbTest, TheTreeThatBuildsRevisionsIsSourceElseFx2dSourceElseTheOneBuiltFrom) {
  unsetenv("FX2D_SOURCE");
  const std::string gone = (directory_ / "gone").string();
  EXPECT_EQ(plugin_source_tree("", FX2D_SOURCE_DIR), FX2D_SOURCE_DIR);
  EXPECT_EQ(plugin_source_tree(FX2D_SOURCE_DIR, gone), fs::path(FX2D_SOURCE_DIR).lexically_normal().string());
  try {
    plugin_source_tree("", gone);
    ADD_FAILURE() << "no tree, yet no refusal";
  } catch (const InputError& refusal) {
    EXPECT_EQ(std::string(refusal.what()),
              "building a revision or the worktree takes the harness/plugin project of an Fx2D source tree, and " +
                  gone + ", which this fx2d-bench was built from, has none; name one with --source DIR or FX2D_SOURCE");
  }
  setenv("FX2D_SOURCE", FX2D_SOURCE_DIR, 1);
  EXPECT_EQ(plugin_source_tree("", gone), fs::path(FX2D_SOURCE_DIR).lexically_normal().string());
  setenv("FX2D_SOURCE", gone.c_str(), 1);
  EXPECT_THROW(plugin_source_tree("", FX2D_SOURCE_DIR), InputError);
  unsetenv("FX2D_SOURCE");
}

TEST_F(AbTest, ASourceThatIsNoFx2dTreeIsOneLineAndExitCodeTwoBeforeAnyBuild) {
  setenv("XDG_CACHE_HOME", (directory_ / "cache").c_str(), 1);
  const Ending ending = run_bench({"ab", "--a", "HEAD", "--b", "HEAD", "--source", directory_.string()}, directory_);
  unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(ending.exit_code, 2) << ending.err;
  EXPECT_EQ(ending.err, "fx2d-bench: --a HEAD: --source " + directory_.string() +
                            ": not an Fx2D source tree (no harness/plugin/CMakeLists.txt)\n");
  EXPECT_FALSE(fs::exists(directory_ / "cache" / "fx2d-bench" / "ab"));
}

TEST_F(AbTest, ABuildThatCannotBeFoundIsOneLineAndExitCodeTwo) {
  const Ending ending = run_bench({"ab", "--a", "no-such-revision-or-file", "--b", FX2D_BENCH_PLUGIN}, directory_);
  EXPECT_EQ(ending.exit_code, 2);
  EXPECT_TRUE(one_line(ending.err)) << ending.err;
  EXPECT_NE(ending.err.find("--a no-such-revision-or-file: not a plugin file"), std::string::npos) << ending.err;
}

TEST_F(AbTest, ABuildThatFailsNamesTheRevisionAndItsLog) {
  setenv("XDG_CACHE_HOME", (directory_ / "cache").c_str(), 1);
  const Ending ending = run_bench({"ab", "--a", FX2D_BENCH_PLUGIN, "--b", "HEAD", "--b-cmake",
                                   "-DFX2D_ARCH_BASELINE=no-such-isa"},
                                  directory_);
  unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(ending.exit_code, 2);
  // Progress lines come first; the error is the last line.
  const std::string last = ending.err.substr(ending.err.rfind('\n', ending.err.size() - 2) + 1);
  EXPECT_NE(last.find("fx2d-bench: --b HEAD: configuring the plugin build failed; see "), std::string::npos) << ending.err;
  const std::string log = last.substr(last.find("see ") + 4, last.size() - last.find("see ") - 5);
  EXPECT_TRUE(fs::exists(log)) << log;
  EXPECT_TRUE(fs::path(log).string().starts_with((directory_ / "cache" / "fx2d-bench" / "ab").string())) << log;
}

// --- the statistical proof -----------------------------------------------------------------------

// One short `ab` (in process: the same functions the command runs) and compare's step-time row,
// its rounds paired as the command pairs them.
CompareRow judged(const EngineInfo& a, const EngineInfo& b, const SceneSpec& scene, int rounds) {
  InterleavePlan plan;
  plan.rounds = rounds;
  plan.warmup_steps = scene.steps;
  InterleavedRuns runs = measure_interleaved(scene, a, b, plan);
  VariantResults variants;
  runs.a.engine = runs.b.engine = "fx2d";
  variants.a.runs.push_back(std::move(runs.a));
  variants.b.runs.push_back(std::move(runs.b));
  const CompareReport report = compare_variants(variants, CompareSettings{});
  return report.rows.at(0);
}

// The proofs run alone (RUN_SERIAL in CMakeLists.txt) but share the machine with whatever else
// it runs, which is the point. The scene and length are chosen for that:
// - settling_boxes at its 200 boxes: its steps cost nearly the same (0.2-0.3 ms) once the boxes
//   have landed, so a step preempted in a round moves that round's median step (statistics.h)
//   one place among close values, where the 60 steps of a 300-body pile, ten times dearer at the
//   end than at the start, let each preempted step move the median by about 2%;
// - 100 steps a round, so that most of them are past the landing: at 50 steps, 0 of 12 A/A runs
//   were "no change" (load 3.6), at 100 steps 12 of 12;
// - 60 rounds per build: the interval's half-width falls as 1/sqrt(rounds). At a load of 3, 48
//   rounds and 60 rounds each gave A/A "no change" in 19 of 20 and 5% "slower" in 20 of 20 with
//   the rounds resampled independently, one of 20 A/A runs inconclusive both times. Resampled as
//   pairs (statistics.h), 60 rounds gave 20 of 20 and 20 of 20 at loads of 1 (twice) and 3; one
//   `ab` run takes 3 s at load 1 and 4.3 s at load 3, a proof 60 s and 90 s.
class AbProof : public AbTest {
 protected:
  void SetUp() override {
    if (FX2D_BENCH_SANITIZED) GTEST_SKIP() << "sanitizer build: instrumented timings say nothing about speed";
    AbTest::SetUp();
    SceneOverrides overrides;
    overrides.steps = 100;
    scene_ = load_scene_file(std::string(FX2D_SOURCE_DIR) + "/scenes/settling_boxes.json", overrides);
  }

  int count_of(Speed expected, const EngineInfo& a, const EngineInfo& b) const {
    int count = 0;
    for (int repetition = 0; repetition < repetitions; ++repetition) {
      const auto start = std::chrono::steady_clock::now();
      const CompareRow row = judged(a, b, scene_, rounds);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      count += row.speed.speed == expected ? 1 : 0;
      std::printf("repetition %d: %s, %.3f [%.3f, %.3f], p %.2g (%.1f s)\n", repetition + 1,
                  to_string(row.speed.speed).c_str(), row.estimate.ratio, row.estimate.ci.low, row.estimate.ci.high,
                  row.test ? row.test->p_value : 1.0, seconds);
    }
    std::printf("%d of %d judged %s\n", count, repetitions, to_string(expected).c_str());
    return count;
  }

  static constexpr int repetitions = 20;
  static constexpr int rounds = 60;
  SceneSpec scene_;
};

TEST_F(AbProof, TheSameBuildAgainstItselfIsNoChangeIn19Of20) {
  const EngineInfo a = plugin_engine_info(Plugin::load(copy_of(FX2D_BENCH_PLUGIN, "a.so")), "fx2d@A");
  const EngineInfo b = plugin_engine_info(Plugin::load(copy_of(FX2D_BENCH_PLUGIN, "b.so")), "fx2d@B");
  EXPECT_GE(count_of(Speed::no_change, a, b), 19);
}

// A plugin built in this build tree against the same checkout built by ab's plugin project: once
// 0.976 on pile 300 (issue 25), because the two compiled Fx2D differently.
TEST_F(AbProof, ThisBuildTreesPluginAgainstTheCheckoutBuiltByAbIsNoChangeIn19Of20) {
  if (!sources_are_a_checkout()) GTEST_SKIP() << "needs a git checkout of the sources";
  const fs::path before = fs::current_path();
  fs::current_path(FX2D_SOURCE_DIR);  // `worktree` is the checkout of the current directory
  const PluginBuild built = prepare_plugin_build(resolve_plugin_build("--b", "worktree", "", ""));
  fs::current_path(before);
  const EngineInfo a = plugin_engine_info(Plugin::load(FX2D_BENCH_PLUGIN), "fx2d@A");
  const EngineInfo b = plugin_engine_info(built.plugin, "fx2d@B");
  EXPECT_GE(count_of(Speed::no_change, a, b), 19);
}

TEST_F(AbProof, AFivePercentSlowerBuildIsSlowerIn19Of20) {
  setenv("FX2D_BENCH_TEST_SLOWDOWN", "0.05", 1);  // read by the slow plugin at each create()
  const EngineInfo a = plugin_engine_info(Plugin::load(FX2D_BENCH_PLUGIN), "fx2d@A");
  const EngineInfo b = plugin_engine_info(Plugin::load(FX2D_BENCH_SLOW_PLUGIN), "fx2d@B");
  const int slower = count_of(Speed::slower, a, b);
  unsetenv("FX2D_BENCH_TEST_SLOWDOWN");
  EXPECT_GE(slower, 19);
}

}  // namespace
}  // namespace fxbench

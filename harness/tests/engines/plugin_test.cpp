// Engine plugins: two builds of Fx2D loaded into one process at once, each stepping exactly the
// trajectory of the built-in engine; one exported symbol; refusals of what is not a plugin of this
// ABI; plugin engine names; and the test plugin's injected cost.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "common/errors.h"
#include "engines/engines.h"
#include "engines/plugin_engine.h"
#include "metrics/accuracy.h"
#include "tests/support/plugin_copies.h"
#include "scene/scene_loader.h"
#include "tests/support/spec_builders.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

SceneSpec scene_file(const std::string& path, int steps) {
  SceneOverrides overrides;
  overrides.steps = steps;
  return load_scene_file(std::string(FX2D_SOURCE_DIR) + "/" + path, overrides);
}

using test::PluginCopies;

std::string final_hash(const Engine& engine) {
  std::vector<BodyState> state;
  engine.read_state(state);
  return state_hash(state);
}

// Steps the engines in lockstep, so that both libraries' code runs interleaved in one process.
std::vector<std::string> hashes_after_lockstep(const std::vector<Engine*>& engines, const SceneSpec& scene) {
  for (Engine* engine : engines) engine->build(scene);
  for (int step = 0; step < scene.steps; ++step)
    for (Engine* engine : engines) engine->step();
  std::vector<std::string> hashes;
  for (Engine* engine : engines) hashes.push_back(final_hash(*engine));
  return hashes;
}

TEST_F(PluginCopies, TwoBuildsLoadedAtOnceStepTheBuiltInEnginesTrajectories) {
  const auto first = Plugin::load(copy_of(FX2D_BENCH_PLUGIN, "first.so"));
  const auto second = Plugin::load(copy_of(FX2D_BENCH_PLUGIN, "second.so"));
  // Two libraries, two tables, two copies of Fx2D: RTLD_LOCAL kept them apart.
  ASSERT_NE(&first->table(), &second->table());
  ASSERT_NE(&first->table(), fx2d_bench_plugin_table());
  // Boxes, circles, a polygon and both joint kinds cross the ABI.
  for (const char* path : {"scenes/stacks.json", "scenes/tests/polygon_and_joint.json", "scenes/tests/joints_and_bounce.json",
                           "scenes/stability/chain_load.json"}) {
    const SceneSpec scene = scene_file(path, 60);
    const auto built_in = make_fx2d_engine();
    const auto a = make_plugin_engine(first);
    const auto b = make_plugin_engine(second);
    const std::vector<std::string> hashes = hashes_after_lockstep({built_in.get(), a.get(), b.get()}, scene);
    EXPECT_EQ(hashes[1], hashes[0]) << path;
    EXPECT_EQ(hashes[2], hashes[0]) << path;
    EXPECT_EQ(a->phase_names(), built_in->phase_names());
    EXPECT_EQ(a->contact_count(), built_in->contact_count()) << path;
  }
}

// `nm -D --defined-only` of a library: the names of its exported symbols.
std::vector<std::string> exported_symbols(const std::string& library) {
  const std::string command = "nm -D --defined-only '" + library + "'";
  FILE* pipe = popen(command.c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  std::vector<std::string> names;
  char line[1024];
  while (pipe != nullptr && std::fgets(line, sizeof line, pipe) != nullptr) {
    std::string text(line);
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    names.push_back(text.substr(text.rfind(' ') + 1));
  }
  EXPECT_EQ(pipe != nullptr ? pclose(pipe) : -1, 0) << command;
  return names;
}

TEST(PluginLibrary, ExportsOnlyItsEntryPoint) {
  for (const char* library : {FX2D_BENCH_PLUGIN, FX2D_BENCH_SLOW_PLUGIN})
    EXPECT_EQ(exported_symbols(library), std::vector<std::string>{FX2D_BENCH_PLUGIN_ENTRY}) << library;
}

std::string load_error(const std::string& path) {
  try {
    Plugin::load(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "loaded";
}

TEST(PluginLoader, RefusesAnotherAbiVersionInOneLine) {
  const std::string error = load_error(FX2D_BENCH_WRONG_ABI_PLUGIN);
  const std::string expected = "plugin ABI version " + std::to_string(FX2D_BENCH_PLUGIN_ABI_VERSION + 1) +
                               ", this fx2d-bench reads version " + std::to_string(FX2D_BENCH_PLUGIN_ABI_VERSION);
  EXPECT_NE(error.find(expected), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
}

TEST_F(PluginCopies, RefusesAMissingFileAndAFileThatIsNoLibrary) {
  EXPECT_NE(load_error((directory_ / "absent.so").string()).find("no such file"), std::string::npos);
  const fs::path text = directory_ / "text.so";
  std::FILE* file = std::fopen(text.c_str(), "w");
  std::fputs("not a library\n", file);
  std::fclose(file);
  EXPECT_NE(load_error(text.string()).find("cannot load"), std::string::npos);
}

TEST(PluginEngineNames, FindEngineLoadsAPluginOnceUnderItsLabel) {
  const std::string name = std::string("plugin:") + FX2D_BENCH_PLUGIN + "|fx2d@X";
  const EngineInfo* engine = find_engine(name);
  ASSERT_NE(engine, nullptr);
  EXPECT_EQ(engine->name, "fx2d@X");
  EXPECT_EQ(engine->solver, "fx2d");
  EXPECT_EQ(engine->version.rfind(find_engine("fx2d")->version, 0), 0u) << engine->version;
  EXPECT_EQ(find_engine(name), engine);
  const EngineInfo* unlabelled = find_engine(std::string("plugin:") + FX2D_BENCH_PLUGIN);
  ASSERT_NE(unlabelled, nullptr);
  EXPECT_EQ(unlabelled->name, std::string("plugin:") + FX2D_BENCH_PLUGIN);
  EXPECT_THROW(find_engine("plugin:/no/such/plugin.so"), InputError);
}

TEST(PluginEngine, ReportsABuildFailureAsItsOneLineError) {
  SceneSpec scene = scene_file("scenes/tests/polygon_and_joint.json", 1);
  scene.joints.at(0).body_b = 999;
  try {
    make_fx2d_engine()->build(scene);
    FAIL() << "built a joint to a body that does not exist";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "fx2d plugin: joint body index 999 out of range");
  }
}

// The SDK's layer (fx2d_bench_plugin.hpp) refuses a body type, shape kind or joint kind outside
// the engine's capabilities before the adapter's World is built, so an adapter meets no other.
TEST(PluginSdk, RefusesAKindOutsideTheCapabilitiesBeforeBuilding) {
  const Fx2dBenchPlugin& table = *fx2d_bench_plugin_table();
  std::vector<double> settings;
  for (int32_t i = 0; i < table.knob_count; ++i) settings.push_back(table.knobs[i].default_value);
  Fx2dBenchBody box{};
  box.type = FX2D_BENCH_DYNAMIC_BODY;
  box.shape = FX2D_BENCH_BOX;
  box.half_extents = {0.5, 0.5};
  box.density = 1.0;
  std::vector<Fx2dBenchBody> bodies{box, box};
  bodies[1].position = {0.0, 2.0};
  Fx2dBenchJoint joint{FX2D_BENCH_REVOLUTE_JOINT, 0, 1, {}, {}, -1.0};
  const auto error_of = [&] {
    const Fx2dBenchScene scene{{0.0, -10.0}, 1.0 / 60.0, bodies.data(), 2, &joint, 1,
                               settings.data(), table.knob_count};
    char error[200] = "";
    Fx2dBenchInstance* built = table.create(&scene, error, sizeof error);
    if (built != nullptr) table.destroy(built);
    return std::string(built != nullptr ? "built" : error);
  };
  EXPECT_EQ(error_of(), "built");
  bodies[1].type = 3;
  EXPECT_EQ(error_of(), "fx2d plugin: body 1: unknown body type 3");
  bodies[1].type = FX2D_BENCH_STATIC_BODY;
  bodies[1].shape = 7;
  EXPECT_EQ(error_of(), "fx2d plugin: body 1: shape kind 7 is not one the engine builds");
  bodies[1].shape = FX2D_BENCH_CIRCLE;
  joint.kind = 2;
  EXPECT_EQ(error_of(), "fx2d plugin: joint 0: joint kind 2 is not one the engine builds");
}

// A circle at 390 m/s meets a 0.02 m box coming the other way at 100 m/s: marked a bullet in the
// scene, it stops at the box (the flag crossed the plugin table); unmarked, it passes through.
TEST(PluginEngine, TheScenesBulletFlagReachesFx2d) {
  const auto circle_ends_before_box = [](bool bullet) {
    SceneSpec scene;
    scene.name = "bullet";
    scene.gravity = {0.0, 0.0};
    BodySpec box = test::box_at({10.0, 0.0});
    box.half_extents = {0.01, 1.0};
    box.linear_velocity = {-100.0, 0.0};
    BodySpec circle = test::circle_at({-10.0, 0.0}, 0.05);
    circle.linear_velocity = {390.0, 0.0};
    circle.bullet = bullet;
    scene.bodies = {box, circle};
    const auto engine = make_fx2d_engine();
    engine->build(scene);
    for (int step = 0; step < 30; ++step) engine->step();
    std::vector<BodyState> state;
    engine->read_state(state);
    return state[1].position.x < state[0].position.x;
  };
  EXPECT_TRUE(circle_ends_before_box(true));
  EXPECT_FALSE(circle_ends_before_box(false));
}

// The injected cost spins until the step's own time times the fraction has passed again, so a
// step's wall time is at least (1 + fraction) times the time Fx2D's stage timers saw inside it.
TEST(SlowdownPlugin, EachStepTakesItsInjectedShareLonger) {
  const SceneSpec scene = scene_file("scenes/stacks.json", 30);
  const auto engine = make_plugin_engine(Plugin::load(FX2D_BENCH_SLOW_PLUGIN));
  setenv("FX2D_BENCH_TEST_SLOWDOWN", "1.0", 1);  // read when the scene is built
  engine->build(scene);
  unsetenv("FX2D_BENCH_TEST_SLOWDOWN");
  std::vector<double> phases(engine->phase_names().size());
  for (int step = 0; step < scene.steps; ++step) {
    const auto start = std::chrono::steady_clock::now();
    engine->step();
    const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    engine->read_phases(phases);
    const double staged_ms = std::accumulate(phases.begin(), phases.end(), 0.0);
    ASSERT_GT(staged_ms, 0.0);
    EXPECT_GE(wall_ms, 2.0 * staged_ms) << "step " << step;
  }
  // Same physics: the cost is added after the step, never inside it.
  EXPECT_EQ(final_hash(*engine), [&] {
    const auto reference = make_fx2d_engine();
    reference->build(scene);
    for (int step = 0; step < scene.steps; ++step) reference->step();
    return final_hash(*reference);
  }());
}

}  // namespace
}  // namespace fxbench

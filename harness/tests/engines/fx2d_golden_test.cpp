// Solver regression: Fx2D's final poses and velocities on four scenes, compared to the bit with
// tables under goldens/, and for the canonical scenes also hashed and compared with
// goldens/state_hashes.json. Any change to the solver's arithmetic or order fires this test; a
// change that is meant shows up as a reviewed diff of the regenerated tables. It needs no more of
// the harness than fx2d_bench_portable, so the aarch64 cross build (ci/cross-aarch64) runs it
// against the same files as every x86-64 build.
//
// Regenerate (never by hand):  FX2D_UPDATE_GOLDENS=1 ctest --test-dir build/release -R Golden
// Shown to fire: with velocity_passes 4 -> 5 in scenes' fx2d settings, every table differs
// (see the note of the engine issue for the output).
//
// Threads change no bit: each table is matched again at 2, 3 and 8 workers, and since those
// scenes are too small for the step to spread them over threads, the canonical scenes also run
// at sizes past every threshold, their state hashes compared with one worker's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "engines/engines.h"
#include "metrics/accuracy.h"
#include "scene/scene_loader.h"

namespace fxbench {
namespace {

std::string golden_path(const std::string& name) { return std::string(FX2D_SOURCE_DIR) + "/goldens/fx2d_" + name + ".txt"; }

SceneOverrides with_workers(SceneOverrides overrides, int workers) {
  overrides.sets.emplace_back("/solver/fx2d/workers", std::to_string(workers));
  return overrides;
}

std::vector<BodyState> final_state(const SceneSpec& scene, int steps) {
  auto engine = make_fx2d_engine();
  engine->build(scene);
  for (int i = 0; i < steps; ++i) engine->step();
  std::vector<BodyState> state;
  engine->read_state(state);
  return state;
}

// One line per body: x y angle vx vy w, printed with enough digits to round-trip exactly.
std::string pose_table(const SceneSpec& scene, int steps, const std::vector<BodyState>& state) {
  std::ostringstream out;
  out << "# fx2d final state: scene " << scene.name << ", " << scene.bodies.size() << " bodies, " << steps
      << " steps\n# x y angle vx vy w\n";
  char line[256];
  for (const BodyState& s : state) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %.17g\n", s.position.x, s.position.y, s.angle,
                  s.linear_velocity.x, s.linear_velocity.y, s.angular_velocity);
    out << line;
  }
  return out.str();
}

struct GoldenCase {
  const char* name;   // golden file suffix
  const char* scene;  // path below the source directory
  int bodies;         // 0: the scene's own size
  // The entry of goldens/state_hashes.json that holds this final state's hash, or nullptr. That
  // file is written by determinism_test from `fx2d-bench run` at each canonical scene's own size;
  // hashing the same state here checks it in builds that have no fx2d-bench.
  const char* state_hash_entry;
  // Substeps, velocity passes and relaxation passes when not the scene's own (0: the scene's).
  int substeps = 0, velocity_passes = 0, relax_passes = 0;
  friend void PrintTo(const GoldenCase& c, std::ostream* os) { *os << c.name; }
};

// The first line where two tables differ, for a failure message a reader can act on.
std::string first_difference(const std::string& expected, const std::string& actual) {
  std::istringstream e(expected), a(actual);
  std::string line_e, line_a;
  for (int line = 1;; ++line) {
    const bool more_e = static_cast<bool>(std::getline(e, line_e));
    const bool more_a = static_cast<bool>(std::getline(a, line_a));
    if (!more_e && !more_a) return "none";
    if (line_e != line_a || more_e != more_a) {
      return "line " + std::to_string(line) + ":\n  golden: " + line_e + "\n  actual: " + line_a;
    }
  }
}

class Golden : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(Golden, FinalStateMatchesTableToTheBit) {
  const GoldenCase& c = GetParam();
  SceneOverrides overrides;
  if (c.bodies > 0) overrides.bodies = c.bodies;
  if (c.substeps > 0) {
    overrides.sets.emplace_back("/solver/fx2d/substeps", std::to_string(c.substeps));
    overrides.sets.emplace_back("/solver/fx2d/velocity_passes", std::to_string(c.velocity_passes));
    overrides.sets.emplace_back("/solver/fx2d/relax_passes", std::to_string(c.relax_passes));
  }
  const std::string scene_path = std::string(FX2D_SOURCE_DIR) + "/" + c.scene;
  const SceneSpec scene = load_scene_file(scene_path, overrides);
  const std::vector<BodyState> state = final_state(scene, scene.steps);
  const std::string actual = pose_table(scene, scene.steps, state);
  const std::string path = golden_path(c.name);
  if (std::getenv("FX2D_UPDATE_GOLDENS")) {
    std::ofstream(path) << actual;
    GTEST_SKIP() << "regenerated " << path;
  }
  std::ifstream file(path);
  ASSERT_TRUE(file) << "missing golden " << path << "; regenerate with FX2D_UPDATE_GOLDENS=1";
  std::stringstream expected;
  expected << file.rdbuf();
  EXPECT_TRUE(actual == expected.str()) << "final state differs from " << path << " at "
                                        << first_difference(expected.str(), actual);
  for (const int workers : {2, 3, 8}) {
    const SceneSpec threaded = load_scene_file(scene_path, with_workers(overrides, workers));
    const std::string threaded_table = pose_table(threaded, threaded.steps, final_state(threaded, threaded.steps));
    EXPECT_TRUE(threaded_table == expected.str()) << workers << " workers: final state differs from " << path << " at "
                                                  << first_difference(expected.str(), threaded_table);
  }
  if (c.state_hash_entry != nullptr) {
    std::ifstream hashes_file(std::string(FX2D_SOURCE_DIR) + "/goldens/state_hashes.json");
    const auto hashes = nlohmann::json::parse(hashes_file, nullptr, false);
    ASSERT_TRUE(hashes.is_object()) << "goldens/state_hashes.json is missing or not a JSON object";
    EXPECT_EQ(state_hash(state), hashes.value(c.state_hash_entry, ""))
        << "final state hash differs from goldens/state_hashes.json /" << c.state_hash_entry;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, Golden,
    ::testing::Values(
        GoldenCase{"stacks_50", "scenes/stacks.json", 50, "stacks"},
        GoldenCase{"pile_300", "scenes/pile.json", 300, "pile"},
        GoldenCase{"settling_boxes_200", "scenes/settling_boxes.json", 200, "settling_boxes"},
        GoldenCase{"joints_and_bounce", "scenes/tests/joints_and_bounce.json", 0, nullptr},
        // 200 pinned links: a support chain deep enough for the full schedule in every step (the
        // scene above takes it only while its ball bounces).
        GoldenCase{"chain", "scenes/joints/chain.json", 0, nullptr},
        // The chain's swing on 200 distance joints: the rods' batches.
        GoldenCase{"rope", "scenes/joints/rope.json", 0, nullptr},
        // The schedule the seeds chose, still selectable (issue 19).
        GoldenCase{"settling_boxes_200_14x4r4", "scenes/settling_boxes.json", 200, nullptr, 14, 4, 4},
        GoldenCase{"joints_and_bounce_14x4r4", "scenes/tests/joints_and_bounce.json", 0, nullptr, 14, 4, 4}),
    [](const ::testing::TestParamInfo<GoldenCase>& param) { return std::string(param.param.name); });

// Sizes past the thresholds of every parallel loop (1024 pairs or bodies), and steps enough for
// bodies to fall asleep and be woken by others landing on them (0.5 s of rest): the narrow
// phase's serial pass over pairs that wake bodies runs too.
struct LargeCase {
  const char* scene;
  int bodies;
  friend void PrintTo(const LargeCase& c, std::ostream* os) { *os << c.scene << " " << c.bodies; }
};

class LargeScene : public ::testing::TestWithParam<LargeCase> {};

TEST_P(LargeScene, StateHashIsTheSameOnEveryWorkerCount) {
  const LargeCase& c = GetParam();
  SceneOverrides overrides;
  overrides.bodies = c.bodies;
  overrides.steps = 90;
  const std::string scene_path = std::string(FX2D_SOURCE_DIR) + "/scenes/" + c.scene + ".json";
  const SceneSpec serial = load_scene_file(scene_path, overrides);
  const std::string serial_hash = state_hash(final_state(serial, serial.steps));
  for (const int workers : {2, 3, 8}) {
    const SceneSpec threaded = load_scene_file(scene_path, with_workers(overrides, workers));
    EXPECT_EQ(state_hash(final_state(threaded, threaded.steps)), serial_hash) << workers << " workers";
  }
}

INSTANTIATE_TEST_SUITE_P(Canonical, LargeScene,
                         ::testing::Values(LargeCase{"pile", 1200}, LargeCase{"settling_boxes", 3000},
                                           LargeCase{"stacks", 1500}),
                         [](const ::testing::TestParamInfo<LargeCase>& param) {
                           return std::string(param.param.scene) + "_" + std::to_string(param.param.bodies);
                         });

}  // namespace
}  // namespace fxbench

// Tests of the scene loader: the canonical scenes expand to exactly the bodies scenes/SCENES.md defines
// at every listed size; each generator follows its formula; every default is filled in; overrides
// reach any field and are checked like the file; the hash follows the resolved scene; and every
// kind of mistake gives one line naming where it is and what was expected.
//
// Positions are compared exactly (EXPECT_EQ on doubles) where the loader must evaluate the same
// expression as scenes/SCENES.md, term by term: the scenes are defined to the bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/errors.h"
#include "common/hash.h"
#include "scene/scene_loader.h"

namespace fxbench {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string scene_path(const std::string& relative) {
  return std::string(FX2D_SOURCE_DIR) + "/scenes/" + relative;
}

SceneSpec canonical(const std::string& name, std::optional<int> bodies = std::nullopt) {
  SceneOverrides overrides;
  overrides.bodies = bodies;
  return load_scene_file(scene_path(name + ".json"), overrides);
}

SceneSpec load(const std::string& text, const SceneOverrides& overrides = {}) {
  return load_scene_text(text, "t.json", overrides);
}

// The message of the InputError `action` throws, or a failure if it throws none.
std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

std::string load_error(const std::string& text, const SceneOverrides& overrides = {}) {
  return error_of([&] { load(text, overrides); });
}

SceneOverrides sets(std::vector<std::pair<std::string, std::string>> pairs) {
  SceneOverrides overrides;
  overrides.sets = std::move(pairs);
  return overrides;
}

int count_of(const SceneSpec& scene, BodyType type) {
  return static_cast<int>(std::ranges::count(scene.bodies, type, &BodySpec::type));
}

double top_face(const BodySpec& body) { return body.position.y + body.half_extents.y; }

// --- The canonical scenes (scenes/SCENES.md) -------------------------------------------------------

TEST(CanonicalScenes, StacksPlacesTenTouchingUnitBoxesPerColumnTwoMetresApart) {
  const SceneSpec scene = canonical("stacks");
  ASSERT_EQ(scene.bodies.size(), 51u);
  const BodySpec& ground = scene.bodies[0];
  EXPECT_EQ(ground.type, BodyType::static_body);
  EXPECT_EQ(top_face(ground), 0.0);
  for (int k = 0; k < 50; ++k) {
    const BodySpec& box = scene.bodies[static_cast<std::size_t>(k) + 1];
    const int column = k / 10;
    const int level = k % 10;
    EXPECT_EQ(box.type, BodyType::dynamic);
    EXPECT_EQ(box.shape, ShapeKind::box);
    EXPECT_EQ(box.half_extents.x, 0.5);
    EXPECT_EQ(box.half_extents.y, 0.5);
    EXPECT_EQ(box.position.x, 2.0 * column) << k;
    EXPECT_EQ(box.position.y, 0.5 + 1.0 * level) << k;
    EXPECT_EQ(box.angle, 0.0);
  }
  // Each column is ten boxes high, its top box centred at 9.5: top face at exactly 10 m.
  EXPECT_EQ(top_face(scene.bodies[10]), 10.0);
  EXPECT_EQ(scene.bodies[50].position.x, 8.0);
}

TEST(CanonicalScenes, StacksHasNDynamicBoxesOnOneGroundCoveringEveryColumnAtEachListedSize) {
  for (const int n : {50, 200, 600}) {
    const SceneSpec scene = canonical("stacks", n);
    EXPECT_EQ(scene.size, n);
    EXPECT_EQ(count_of(scene, BodyType::dynamic), n);
    EXPECT_EQ(count_of(scene, BodyType::static_body), 1);
    const BodySpec& ground = scene.bodies[0];
    const double last_column_right = 2.0 * (n / 10 - 1) + 0.5;
    EXPECT_LE(ground.position.x - ground.half_extents.x, -0.5) << n;
    EXPECT_GE(ground.position.x + ground.half_extents.x, last_column_right) << n;
    EXPECT_EQ(scene.bodies.back().position.x, 2.0 * (n / 10 - 1));
  }
}

TEST(CanonicalScenes, PilePlacesRowsOfEighteenCirclesInsideTheContainer) {
  const SceneSpec scene = canonical("pile");
  ASSERT_EQ(scene.bodies.size(), 303u);
  EXPECT_EQ(top_face(scene.bodies[0]), 0.0);
  const BodySpec& left = scene.bodies[1];
  const BodySpec& right = scene.bodies[2];
  EXPECT_EQ(left.position.x + left.half_extents.x, -10.0);
  EXPECT_EQ(right.position.x - right.half_extents.x, 10.0);
  for (const BodySpec* wall : {&left, &right}) {
    EXPECT_EQ(wall->type, BodyType::static_body);
    EXPECT_EQ(2.0 * wall->half_extents.x, 1.0);
    EXPECT_EQ(2.0 * wall->half_extents.y, 100.0);
    EXPECT_EQ(wall->position.y - wall->half_extents.y, 0.0);
  }
  for (int k = 0; k < 300; ++k) {
    const BodySpec& circle = scene.bodies[static_cast<std::size_t>(k) + 3];
    const int row = k / 18;
    const int column = k % 18;
    ASSERT_EQ(circle.shape, ShapeKind::circle);
    EXPECT_EQ(circle.radius, 0.5);
    const double x = -9.4 + 1.1 * column;
    EXPECT_EQ(circle.position.x, row % 2 == 1 ? x + 0.15 : x) << k;
    EXPECT_EQ(circle.position.y, 0.6 + 1.1 * row) << k;
    EXPECT_LE(std::abs(circle.position.x) + circle.radius, 10.0) << k;
  }
  // Hand-computed: the first of row 1 is shifted by the odd-row offset; circle 299 is row 16,
  // column 11. 1e-12 allows the few ulps of rounding in -9.4 + 1.1 k.
  EXPECT_NEAR(scene.bodies[3 + 18].position.x, -9.25, 1e-12);
  EXPECT_NEAR(scene.bodies[302].position.x, 2.7, 1e-12);
  EXPECT_NEAR(scene.bodies[302].position.y, 18.2, 1e-12);
}

TEST(CanonicalScenes, PileHasNCirclesAndThreeStaticBodiesAtEachListedSize) {
  for (const int n : {300, 600, 1200}) {
    const SceneSpec scene = canonical("pile", n);
    EXPECT_EQ(count_of(scene, BodyType::dynamic), n);
    EXPECT_EQ(count_of(scene, BodyType::static_body), 3);
  }
}

TEST(CanonicalScenes, SettlingBoxesPlacesTiltedUnitBoxesInRowsOfForty) {
  const SceneSpec scene = canonical("settling_boxes");
  ASSERT_EQ(scene.bodies.size(), 201u);
  EXPECT_EQ(scene.bodies[0].half_extents.x, 60.0);
  EXPECT_EQ(top_face(scene.bodies[0]), 0.0);
  for (int i = 0; i < 200; ++i) {
    const BodySpec& box = scene.bodies[static_cast<std::size_t>(i) + 1];
    EXPECT_EQ(box.position.x, 1.5 * (i % 40) - 29.25) << i;
    EXPECT_EQ(box.position.y, 1.0 + 1.5 * (i / 40)) << i;
    EXPECT_EQ(box.angle, 0.1 * (((7 * i) % 11) - 5)) << i;
    EXPECT_EQ(box.half_extents.x, 0.5);
  }
  // By hand: i = 0 gives 0.1 * -5; i = 3 gives 21 mod 11 = 10, so 0.1 * 5.
  EXPECT_DOUBLE_EQ(scene.bodies[1].angle, -0.5);
  EXPECT_DOUBLE_EQ(scene.bodies[4].angle, 0.5);
  EXPECT_EQ(scene.bodies[200].position.y, 7.0);  // i = 199: row 4
}

TEST(CanonicalScenes, SettlingBoxesHasNBoxesAndOneGroundAtEachListedSize) {
  for (const int n : {200, 800, 3000}) {
    const SceneSpec scene = canonical("settling_boxes", n);
    EXPECT_EQ(count_of(scene, BodyType::dynamic), n);
    EXPECT_EQ(count_of(scene, BodyType::static_body), 1);
  }
}

TEST(CanonicalScenes, StateTheCommonSettingsAndEachEnginesSolverSettings) {
  for (const std::string name : {"pile", "stacks", "settling_boxes"}) {
    const SceneSpec scene = canonical(name);
    EXPECT_EQ(scene.name, name);
    EXPECT_EQ(scene.dt, 1.0 / 60.0) << name;
    EXPECT_EQ(scene.steps, 200);
    EXPECT_EQ(scene.gravity.x, 0.0);
    EXPECT_EQ(scene.gravity.y, -10.0);
    for (const BodySpec& body : scene.bodies) {
      EXPECT_EQ(body.material.density, 1.0);
      EXPECT_EQ(body.material.static_friction, 0.6);
      EXPECT_EQ(body.material.dynamic_friction, 0.6);
      EXPECT_EQ(body.material.restitution, 0.0);
    }
    EXPECT_EQ(nlohmann::json::parse(scene.resolved_json)["solver"]["fx2d"],
              nlohmann::json::parse(
                  R"({"substeps": 8, "velocity_passes": 1, "relax_passes": 3, "sleeping": true})"));
    EXPECT_EQ(
        nlohmann::json::parse(scene.resolved_json)["solver"]["box2d"],
        nlohmann::json::parse(R"({"velocity_iterations": 8, "position_iterations": 3, "sleeping": true})"));
    EXPECT_EQ(nlohmann::json::parse(scene.resolved_json)["solver"]["ode"],
              nlohmann::json::parse(R"({"iterations": 20, "erp": 0.2, "cfm": 1e-5, "auto_disable": true})"));
    // Every body starts inside the scene's escape bounds.
    for (const BodySpec& body : scene.bodies) {
      if (body.type != BodyType::dynamic) continue;
      EXPECT_GT(body.position.x, scene.bounds_lower.x);
      EXPECT_LT(body.position.x, scene.bounds_upper.x);
      EXPECT_GT(body.position.y, scene.bounds_lower.y);
      EXPECT_LT(body.position.y, scene.bounds_upper.y);
    }
  }
  EXPECT_EQ(canonical("stacks").primary_metric, PrimaryMetric::displacement);
  EXPECT_EQ(canonical("pile").primary_metric, PrimaryMetric::penetration);
  EXPECT_EQ(canonical("settling_boxes").primary_metric, PrimaryMetric::penetration);
}

TEST(CanonicalScenes, EmbeddedTextIsTheFileTextAndResolvesToTheSameHash) {
  for (const std::string name : {"pile", "stacks", "settling_boxes"}) {
    const std::optional<std::string> embedded = embedded_scene_text(name);
    ASSERT_TRUE(embedded.has_value()) << name;
    EXPECT_EQ(*embedded, read_text(scene_path(name + ".json")));
    EXPECT_EQ(load_scene_text(*embedded, "<embedded:" + name + ">").hash, canonical(name).hash);
  }
  EXPECT_FALSE(embedded_scene_text("piles").has_value());
}

// --- Generators -----------------------------------------------------------------------------

std::string scene_with(const std::string& members) {
  return R"({"schema": "fx2d.scene/1", )" + members + "}";
}

TEST(Generators, GroundPutsItsTopFaceAtTopWithTheGivenThickness) {
  const SceneSpec scene = load(scene_with(
      R"("generators": [{"type": "ground", "top": 2, "thickness": 4, "half_width": 3, "center_x": 1}])"));
  ASSERT_EQ(scene.bodies.size(), 1u);
  const BodySpec& ground = scene.bodies[0];
  EXPECT_EQ(ground.type, BodyType::static_body);
  EXPECT_EQ(ground.position.x, 1.0);
  EXPECT_EQ(ground.position.y, 0.0);
  EXPECT_EQ(ground.half_extents.x, 3.0);
  EXPECT_EQ(ground.half_extents.y, 2.0);
}

TEST(Generators, AutoGroundReachesTenMetresBeyondTheOutermostBody) {
  const SceneSpec scene = load(scene_with(
      R"("generators": [{"type": "ground"}], "bodies": [{"shape": {"circle": 1}, "position": [-30, 5]}])"));
  // The circle's left edge is at -31; the margin is 10 m.
  EXPECT_EQ(scene.bodies[0].half_extents.x, 41.0);
  EXPECT_NE(scene.resolved_json.find(R"("half_width": 41.0)"), std::string::npos) << scene.resolved_json;
}

TEST(Generators, WallsPutTheirInnerFacesAtPlusAndMinusInner) {
  const SceneSpec scene = load(scene_with(
      R"("generators": [{"type": "walls", "inner": 3, "thickness": 2, "height": 6, "bottom": 1}])"));
  ASSERT_EQ(scene.bodies.size(), 2u);
  EXPECT_EQ(scene.bodies[0].position.x, -4.0);
  EXPECT_EQ(scene.bodies[1].position.x, 4.0);
  for (const BodySpec& wall : scene.bodies) {
    EXPECT_EQ(wall.position.y, 4.0);
    EXPECT_EQ(wall.half_extents.x, 1.0);
    EXPECT_EQ(wall.half_extents.y, 3.0);
    EXPECT_EQ(wall.type, BodyType::static_body);
  }
}

TEST(Generators, BoxColumnsStackBottomUpAndLeaveTheLastColumnShort) {
  const SceneSpec scene = load(scene_with(
      R"("generators": [{"type": "box_columns", "count": 7, "per_column": 3, "x0": -1, "column_spacing": 1.5,
                          "bottom": 2, "half_extents": [0.25, 0.5]}])"));
  ASSERT_EQ(scene.bodies.size(), 7u);
  EXPECT_EQ(scene.bodies[0].position.x, -1.0);
  EXPECT_EQ(scene.bodies[0].position.y, 2.5);
  EXPECT_EQ(scene.bodies[5].position.x, 0.5);  // column 1, level 2
  EXPECT_EQ(scene.bodies[5].position.y, 4.5);
  EXPECT_EQ(scene.bodies[6].position.x, 2.0);  // column 2 holds one box
  EXPECT_EQ(scene.bodies[6].position.y, 2.5);
  EXPECT_EQ(scene.bodies[6].half_extents.x, 0.25);
}

TEST(Generators, CircleRowsShiftOddRowsByTheOffset) {
  const SceneSpec scene = load(scene_with(
      R"("generators": [{"type": "circle_rows", "count": 5, "per_row": 2, "radius": 0.25, "origin": [1, 2],
                          "spacing": [3, 4], "odd_row_offset": 0.5}])"));
  ASSERT_EQ(scene.bodies.size(), 5u);
  EXPECT_EQ(scene.bodies[1].position.x, 4.0);
  EXPECT_EQ(scene.bodies[1].position.y, 2.0);
  EXPECT_EQ(scene.bodies[2].position.x, 1.5);  // row 1
  EXPECT_EQ(scene.bodies[2].position.y, 6.0);
  EXPECT_EQ(scene.bodies[4].position.x, 1.0);  // row 2: even again
  EXPECT_EQ(scene.bodies[4].position.y, 10.0);
  EXPECT_EQ(scene.bodies[4].radius, 0.25);
}

TEST(Generators, BoxGridTiltsEachBoxByTheModularRule) {
  const SceneSpec scene = load(scene_with(
      R"("generators": [{"type": "box_grid", "count": 6, "per_row": 5, "origin": [0, 1], "spacing": [2, 3],
                          "tilt": {"step": 0.5, "multiplier": 3, "modulus": 4, "offset": 1}}])"));
  ASSERT_EQ(scene.bodies.size(), 6u);
  // angle(i) = 0.5 * (((3 i) mod 4) - 1): i = 0, 1, 2, 3 give -0.5, 1, 0.5, 0.
  EXPECT_EQ(scene.bodies[0].angle, -0.5);
  EXPECT_EQ(scene.bodies[1].angle, 1.0);
  EXPECT_EQ(scene.bodies[2].angle, 0.5);
  EXPECT_EQ(scene.bodies[3].angle, 0.0);
  EXPECT_EQ(scene.bodies[5].position.x, 0.0);  // second row
  EXPECT_EQ(scene.bodies[5].position.y, 4.0);
  EXPECT_EQ(scene.bodies[4].position.x, 8.0);
}

TEST(Generators, CountDefaultsToTheScenesSize) {
  const SceneSpec scene = load(scene_with(R"("size": 7, "generators": [{"type": "box_grid"}])"));
  EXPECT_EQ(scene.bodies.size(), 7u);
  EXPECT_NE(scene.resolved_json.find(R"("count": 7)"), std::string::npos);
}

TEST(Generators, MaterialInheritsEveryFieldItLeavesOutFromTheScene) {
  const SceneSpec scene = load(scene_with(R"("size": 1, "material": {"density": 2, "friction": 0.3},
      "generators": [{"type": "box_grid", "material": {"restitution": 0.5}}, {"type": "ground", "half_width": 1}])"));
  const MaterialSpec& box = scene.bodies[0].material;
  EXPECT_EQ(box.density, 2.0);
  EXPECT_EQ(box.static_friction, 0.3);
  EXPECT_EQ(box.dynamic_friction, 0.3);
  EXPECT_EQ(box.restitution, 0.5);
  EXPECT_EQ(scene.bodies[1].material.restitution, 0.0);
}

TEST(Generators, BodiesFollowGeneratorOrderThenExplicitBodies) {
  const SceneSpec scene =
      load(scene_with(R"("size": 2, "generators": [{"type": "box_grid"}, {"type": "ground"}],
      "bodies": [{"shape": {"circle": 1}}])"));
  ASSERT_EQ(scene.bodies.size(), 4u);
  EXPECT_EQ(scene.bodies[0].type, BodyType::dynamic);
  EXPECT_EQ(scene.bodies[2].type, BodyType::static_body);
  EXPECT_EQ(scene.bodies[3].shape, ShapeKind::circle);
}

// --- Defaults and explicit bodies -----------------------------------------------------------

TEST(Defaults, MinimalSceneResolvesEveryTopLevelDefault) {
  const SceneSpec scene = load_scene_text(R"({"schema": "fx2d.scene/1"})", "scenes/minimal.json");
  const SceneSpec defaults;
  EXPECT_EQ(scene.name, "minimal");
  EXPECT_EQ(scene.size, 0);
  EXPECT_EQ(scene.steps, defaults.steps);
  EXPECT_EQ(scene.dt, defaults.dt);
  EXPECT_EQ(scene.gravity.y, defaults.gravity.y);
  EXPECT_EQ(scene.primary_metric, PrimaryMetric::penetration);
  EXPECT_TRUE(scene.bodies.empty());
  EXPECT_EQ(scene.resolved_json, R"({
  "bodies": [],
  "bounds": {
    "lower": [
      -1000.0,
      -1000.0
    ],
    "upper": [
      1000.0,
      1000.0
    ]
  },
  "description": "",
  "dt": 0.016666666666666666,
  "generators": [],
  "gravity": [
    0.0,
    -10.0
  ],
  "joints": [],
  "material": {
    "density": 1.0,
    "dynamic_friction": 0.6,
    "restitution": 0.0,
    "static_friction": 0.6
  },
  "name": "minimal",
  "primary_metric": "penetration",
  "schema": "fx2d.scene/1",
  "size": 0,
  "solver": {
    "box2d": {
      "position_iterations": 3,
      "sleeping": true,
      "velocity_iterations": 8
    },
    "fx2d": {
      "sleeping": true,
      "substeps": 8,
      "velocity_passes": 1
    },
    "ode": {
      "auto_disable": true,
      "cfm": 1e-05,
      "erp": 0.2,
      "iterations": 20
    }
  },
  "steps": 200
})");
}

// relax_passes and max_push_speed came after scenes had hashes; left out, they stay out of the
// resolved scene (MinimalSceneResolvesEveryTopLevelDefault shows it) and the hash is unchanged.
TEST(Defaults, Fx2dRelaxPassesAndPushSpeedAreTheEnginesUnlessGiven) {
  const SceneSpec unset = load(scene_with(R"("size": 0)"));
  const SceneSpec set = load(scene_with(R"("solver": {"fx2d": {"relax_passes": 1, "max_push_speed": 0.5}})"));
  EXPECT_NE(set.hash, unset.hash);
  EXPECT_NE(set.resolved_json.find(R"("relax_passes": 1)"), std::string::npos);
  EXPECT_NE(set.resolved_json.find(R"("max_push_speed": 0.5)"), std::string::npos);
}

TEST(Defaults, GeneratorResolvesEveryParameter) {
  const SceneSpec scene = load(scene_with(R"("size": 1, "generators": [{"type": "circle_rows"}])"));
  EXPECT_EQ(scene.bodies[0].radius, 0.5);
  EXPECT_EQ(scene.bodies[0].position.y, 0.5);  // resting on a ground at y = 0
  for (const char* key :
       {R"("per_row": 10)", R"("odd_row_offset": 0.0)", R"("radius": 0.5)", R"("count": 1)"}) {
    EXPECT_NE(scene.resolved_json.find(key), std::string::npos) << key;
  }
}

TEST(Defaults, ExplicitBodyNeedsOnlyItsShape) {
  const SceneSpec scene = load(scene_with(R"("bodies": [{"shape": {"box": [1, 2]}}])"));
  const BodySpec& body = scene.bodies[0];
  EXPECT_EQ(body.type, BodyType::dynamic);
  EXPECT_EQ(body.half_extents.y, 2.0);
  EXPECT_EQ(body.position.x, 0.0);
  EXPECT_EQ(body.angle, 0.0);
  EXPECT_EQ(body.linear_velocity.x, 0.0);
  EXPECT_EQ(body.angular_velocity, 0.0);
  EXPECT_EQ(body.material.static_friction, 0.6);
}

// A scene that leaves `bullet` out resolves, and hashes, as it did before the key existed.
TEST(Defaults, BulletIsFalseAndLeftOutOfTheResolvedSceneWhenNotGiven) {
  const SceneSpec plain = load(scene_with(R"("bodies": [{"shape": {"circle": 1}}])"));
  EXPECT_FALSE(plain.bodies[0].bullet);
  EXPECT_EQ(plain.resolved_json.find("bullet"), std::string::npos);
  const SceneSpec bullet = load(scene_with(R"("bodies": [{"shape": {"circle": 1}, "bullet": true}])"));
  EXPECT_TRUE(bullet.bodies[0].bullet);
  EXPECT_NE(bullet.hash, plain.hash);
  EXPECT_NE(load_error(scene_with(R"("bodies": [{"shape": {"circle": 1}, "bullet": 1}])")).find("bullet: expected true or false, got 1"),
            std::string::npos);
}

TEST(Defaults, DistanceJointLengthDefaultsToAsBuilt) {
  const SceneSpec scene = load(scene_with(
      R"("bodies": [{"shape": {"circle": 1}}, {"shape": {"circle": 1}, "position": [3, 0]}],
         "joints": [{"type": "distance", "a": 0, "b": 1}])"));
  EXPECT_EQ(scene.joints[0].length, -1.0);
  EXPECT_NE(scene.resolved_json.find(R"("length": "as_built")"), std::string::npos);
}

TEST(Defaults, FrictionSetsBothFrictionsAndEachCanBeOverridden) {
  const SceneSpec scene = load(scene_with(
      R"("material": {"friction": 0.5, "static_friction": 0.9}, "bodies": [{"shape": {"circle": 1}}])"));
  EXPECT_EQ(scene.bodies[0].material.static_friction, 0.9);
  EXPECT_EQ(scene.bodies[0].material.dynamic_friction, 0.5);
}

TEST(TestScenes, SingleBoxRestsOnGround) {
  const SceneSpec scene = load_scene_file(scene_path("tests/single_box_on_ground.json"));
  ASSERT_EQ(scene.bodies.size(), 2u);
  EXPECT_EQ(top_face(scene.bodies[0]), 0.0);
  EXPECT_EQ(scene.bodies[1].position.y - scene.bodies[1].half_extents.y, 0.0);
  EXPECT_EQ(scene.source_path, scene_path("tests/single_box_on_ground.json"));
}

TEST(TestScenes, FallingCircleHasNothingBelowIt) {
  const SceneSpec scene = load_scene_file(scene_path("tests/falling_circle.json"));
  ASSERT_EQ(scene.bodies.size(), 1u);
  EXPECT_EQ(scene.bodies[0].shape, ShapeKind::circle);
  EXPECT_EQ(scene.bodies[0].position.y, 10.0);
}

TEST(TestScenes, PolygonAndJointsReadEveryField) {
  const SceneSpec scene = load_scene_file(scene_path("tests/polygon_and_joint.json"));
  ASSERT_EQ(scene.bodies.size(), 3u);
  EXPECT_EQ(scene.bodies[0].type, BodyType::static_body);
  const BodySpec& triangle = scene.bodies[1];
  ASSERT_EQ(triangle.shape, ShapeKind::polygon);
  ASSERT_EQ(triangle.vertices.size(), 3u);
  EXPECT_EQ(triangle.vertices[2].y, 0.5);
  EXPECT_EQ(triangle.material.density, 2.0);
  EXPECT_EQ(scene.bodies[2].angle, 0.3);
  EXPECT_EQ(scene.bodies[2].material.dynamic_friction, 0.2);
  ASSERT_EQ(scene.joints.size(), 2u);
  EXPECT_EQ(scene.joints[0].kind, JointKind::revolute);
  EXPECT_EQ(scene.joints[0].body_b, 1);
  EXPECT_EQ(scene.joints[0].local_anchor_b.x, -1.0);
  EXPECT_EQ(scene.joints[1].kind, JointKind::distance);
  EXPECT_EQ(scene.joints[1].body_a, 1);
  EXPECT_EQ(scene.joints[1].body_b, 2);
  EXPECT_EQ(scene.joints[1].length, 1.25);
}

TEST(TestScenes, CirclesApproachHeadOnWithoutGravity) {
  const SceneSpec scene = load_scene_file(scene_path("tests/circles_colliding_zero_gravity.json"));
  ASSERT_EQ(scene.bodies.size(), 2u);
  EXPECT_EQ(scene.gravity.y, 0.0);
  EXPECT_EQ(scene.bodies[0].linear_velocity.x + scene.bodies[1].linear_velocity.x, 0.0);
  EXPECT_EQ(scene.bodies[0].material.restitution, 1.0);
}

// --- Overrides ------------------------------------------------------------------------------

TEST(Overrides, BodiesAndStepsSetSizeAndSteps) {
  SceneOverrides overrides;
  overrides.bodies = 20;
  overrides.steps = 7;
  const SceneSpec scene = load_scene_file(scene_path("stacks.json"), overrides);
  EXPECT_EQ(scene.size, 20);
  EXPECT_EQ(scene.steps, 7);
  EXPECT_EQ(scene.bodies.size(), 21u);
}

// A size nothing reads would mislabel the results: the 200-link chain run "at 150 bodies" still
// holds its 200 links. Refused from --bodies; a file's own unread size is a resolved scene's.
TEST(Overrides, BodiesOnASceneWithoutASizeParameterIsRefused) {
  SceneOverrides overrides;
  overrides.bodies = 150;
  const std::string chain = scene_path("joints/chain.json");
  EXPECT_EQ(error_of([&] { load_scene_file(chain, overrides); }),
            "--bodies 150: /size: " + chain +
                " has no size parameter (no generator takes its count from /size); expected none, got 150");
  EXPECT_EQ(bodies_of(load_scene_file(chain)), 200);
  const std::string counted = scene_with(R"("size": 3, "generators": [{"type": "box_grid", "count": 2}])");
  EXPECT_EQ(load_error(counted, overrides),
            "--bodies 150: /size: t.json has no size parameter (no generator takes its count from /size); "
            "expected none, got 150");
  EXPECT_EQ(load(counted).bodies.size(), 2u);
  EXPECT_EQ(
      load(scene_with(R"("generators": [{"type": "box_grid", "count": 2}, {"type": "box_grid"}])"), overrides)
          .bodies.size(),
      152u);
}

TEST(Overrides, SetChangesANestedField) {
  const SceneSpec scene = load_scene_file(
      scene_path("stacks.json"),
      sets({{"/solver/box2d/velocity_iterations", "10"}, {"/generators/1/half_extents/0", "0.25"}}));
  EXPECT_EQ(
      nlohmann::json::parse(scene.resolved_json)["solver"]["box2d"],
      nlohmann::json::parse(R"({"velocity_iterations": 10, "position_iterations": 3, "sleeping": true})"));
  EXPECT_EQ(scene.bodies[1].half_extents.x, 0.25);
  EXPECT_EQ(scene.bodies[1].half_extents.y, 0.5);
}

TEST(Overrides, SetCreatesTheObjectsAFileLeavesOut) {
  const SceneSpec scene = load(scene_with(R"("size": 0)"), sets({{"/solver/ode/erp", "0.5"}}));
  EXPECT_EQ(nlohmann::json::parse(scene.resolved_json)["solver"]["ode"]["erp"], 0.5);
}

// The format wrote these keys in their defaults' kinds before the engines declared knobs; it still
// does, so that "erp": 1 and "erp": 1.0, or "iterations": 20.0 and 20, are one scene with one hash.
TEST(Overrides, BuiltInEnginesKeysAreRecordedInTheirDefaultsKinds) {
  const SceneSpec spelt_as_given =
      load(scene_with(R"("size": 0)"), sets({{"/solver/ode/erp", "1"},
                                             {"/solver/ode/iterations", "20.0"},
                                             {"/solver/box2d/velocity_iterations", "9.0"}}));
  const SceneSpec spelt_in_kind =
      load(scene_with(R"("size": 0)"), sets({{"/solver/ode/erp", "1.0"},
                                             {"/solver/ode/iterations", "20"},
                                             {"/solver/box2d/velocity_iterations", "9"}}));
  EXPECT_EQ(spelt_as_given.resolved_json, spelt_in_kind.resolved_json);
  EXPECT_EQ(spelt_as_given.hash, spelt_in_kind.hash);
  const nlohmann::json solver = nlohmann::json::parse(spelt_as_given.resolved_json)["solver"];
  EXPECT_TRUE(solver["ode"]["erp"].is_number_float());
  EXPECT_TRUE(solver["ode"]["iterations"].is_number_integer());
  EXPECT_TRUE(solver["box2d"]["velocity_iterations"].is_number_integer());
}

TEST(Overrides, SetTakesAValueThatIsNotJsonAsAString) {
  const SceneSpec scene =
      load(scene_with(R"("size": 0)"), sets({{"/name", "my scene"}, {"/primary_metric", "displacement"}}));
  EXPECT_EQ(scene.name, "my scene");
  EXPECT_EQ(scene.primary_metric, PrimaryMetric::displacement);
}

TEST(Overrides, SetAppendsToAnArrayWithDash) {
  const SceneSpec scene =
      load(scene_with(R"("size": 0)"), sets({{"/bodies/-", R"({"shape": {"circle": 2}})"}}));
  ASSERT_EQ(scene.bodies.size(), 1u);
  EXPECT_EQ(scene.bodies[0].radius, 2.0);
}

TEST(Overrides, LaterSetsWin) {
  const SceneSpec scene = load(scene_with(R"("size": 0)"), sets({{"/dt", "0.1"}, {"/dt", "0.01"}}));
  EXPECT_EQ(scene.dt, 0.01);
}

// --- Hash -----------------------------------------------------------------------------------

TEST(Hash, IsFnv1aOfTheResolvedJson) {
  const SceneSpec scene = canonical("pile");
  Fnv1a64 hash;
  hash.add(scene.resolved_json);
  EXPECT_EQ(scene.hash, hash.hex());
  EXPECT_EQ(scene.hash.size(), 16u);
}

TEST(Hash, ChangesWhenAValueChanges) {
  const std::string base = canonical("stacks").hash;
  EXPECT_NE(load_scene_file(scene_path("stacks.json"), sets({{"/dt", "0.01"}})).hash, base);
  EXPECT_NE(canonical("stacks", 200).hash, base);
  EXPECT_NE(load_scene_file(scene_path("stacks.json"), sets({{"/material/restitution", "0.1"}})).hash, base);
}

TEST(Hash, IgnoresWhitespaceKeyOrderAndEquivalentSpellings) {
  const SceneSpec compact =
      load(R"({"schema":"fx2d.scene/1","name":"a","size":3,"generators":[{"type":"box_grid"}]})");
  const SceneSpec spaced = load(R"({
      "generators": [ { "type": "box_grid", "count": 3 } ],
      "size": 3.0,
      "material": { "friction": 0.6 },
      "name": "a",
      "schema": "fx2d.scene/1"
  })");
  EXPECT_EQ(compact.hash, spaced.hash);
  EXPECT_EQ(compact.resolved_json, spaced.resolved_json);
}

// --- Errors ---------------------------------------------------------------------------------

TEST(Errors, SyntaxErrorGivesLineColumnAndAReadableReason) {
  EXPECT_EQ(load_error("{\n  \"schema\": \"fx2d.scene/1\",\n  \"size\": 5,\n}"),
            "t.json:4:1: syntax error: unexpected '}'; expected string literal");
  EXPECT_EQ(load_error("{\"size\": [1, 2,]}"),
            "t.json:1:16: syntax error: unexpected ']'; expected '[', '{', or a literal");
}

TEST(Errors, UnknownKeySuggestsTheNearestKeyAtTheKeysPosition) {
  EXPECT_EQ(load_error(R"({
  "schema": "fx2d.scene/1",
  "generators": [
    {"type": "ground"},
    {"type": "box_grid", "cout": 5}
  ]
})"),
            R"(t.json:5:26: /generators/1/cout: unknown key; did you mean "count"?)");
}

TEST(Errors, UnknownKeyFarFromEveryKeyListsTheKeysAccepted) {
  EXPECT_EQ(load_error(scene_with(R"("bounds": {"zzzzzz": 1})")),
            R"(t.json:1:39: /bounds/zzzzzz: unknown key; expected one of "lower", "upper")");
}

TEST(Errors, AKeyHoldingControlCharactersIsShownEscapedOnOneLine) {
  // The key as the file spells it: a newline or a terminal's escape in a message would break the
  // one line (libFuzzer found the newline, harness/fuzz/crashes/scene_loader/newline_in_key.json).
  EXPECT_EQ(load_error(scene_with(R"("bounds": {"low\ner": 1, "x\u001b[2J\"\\": 2})")),
            R"(t.json:1:39: /bounds/low\ner: unknown key; did you mean "lower"?)");
  EXPECT_EQ(load_error(scene_with(R"("bounds": {"x\u001b[2J\"\\": 2})")),
            R"(t.json:1:39: /bounds/x\u001b[2J\"\\: unknown key; expected one of "lower", "upper")");
}

TEST(Errors, WrongTypeNamesWhatWasExpectedAndWhatCame) {
  EXPECT_EQ(load_error("{\"schema\": \"fx2d.scene/1\",\n \"size\": \"a\"}"),
            R"(t.json:2:10: /size: expected an integer >= 0, got "a")");
  // Fx2D's block holds its knobs, checked by the engine when selected (plugin_commands_test).
  EXPECT_EQ(load_error(scene_with(R"("solver": {"fx2d": {"sleeping": "no"}})")),
            R"(t.json:1:60: /solver/fx2d/sleeping: expected a number or true or false, got "no")");
}

TEST(Errors, OutOfRangeValuesAreRefused) {
  EXPECT_EQ(load_error(scene_with(R"("size": -3)")), "t.json:1:36: /size: expected an integer >= 0, got -3");
  EXPECT_EQ(load_error(scene_with(R"("size": 2000000)")),
            "t.json:1:36: /size: expected an integer <= 1000000, got 2000000");
  EXPECT_EQ(load_error(scene_with(R"("dt": 0)")), "t.json:1:34: /dt: expected a number >= 1e-06, got 0");
  EXPECT_EQ(load_error(scene_with(R"("material": {"restitution": 1.5})")),
            "t.json:1:56: /material/restitution: expected a number from 0 to 1, got 1.5");
  EXPECT_EQ(load_error(scene_with(R"("bodies": [{"shape": {"circle": 1}, "position": [0, 1e300]}])")),
            "t.json:1:80: /bodies/0/position/1: expected a number from -1000000 to 1000000, got 1e+300");
}

TEST(Errors, GeneratorsTogetherAboveTheBodyLimitAreRefusedBeforeAllocating) {
  EXPECT_EQ(
      load_error(scene_with(R"("size": 1000000, "generators": [{"type": "ground"}, {"type": "box_grid"}])")),
      "t.json:1:36: /size: expected at most 1000000 bodies in the scene, got 1000001");
  EXPECT_EQ(
      load_error(scene_with(R"("generators": [{"type": "ground"}, {"type": "box_grid", "count": 1000000}])")),
      "t.json:1:93: /generators/1/count: expected at most 1000000 bodies in the scene, got 1000001");
  EXPECT_EQ(error_of([] { canonical("stacks", 1'000'000); }),
            "--bodies 1000000: /size: expected at most 1000000 bodies in the scene, got 1000001");
}

TEST(Errors, GeneratedBodiesFarFromTheOriginAreRefused) {
  EXPECT_EQ(
      load_error(scene_with(R"("generators": [{"type": "box_grid", "count": 3, "spacing": [900000, 1]}])")),
      "t.json:1:43: /generators/0: expected bodies within 1000000 m of the origin, got one at "
      "[1800000.0,0.5]");
}

TEST(Errors, MissingRequiredFieldIsReportedAtItsParent) {
  EXPECT_EQ(
      load_error(scene_with(R"("bodies": [{"position": [0, 1]}])")),
      R"(t.json:1:39: /bodies/0/shape: expected {"circle": radius}, {"box": [hw, hh]} or {"polygon": [[x, y], ...]}, got nothing)");
  EXPECT_EQ(load_error(scene_with(R"("bodies": [{"shape": {"circle": null}}])")),
            "t.json:1:60: /bodies/0/shape/circle: expected a number > 0, got null");
  EXPECT_EQ(
      load_error(scene_with(R"("generators": [{"count": 3}])")),
      R"(t.json:1:43: /generators/0/type: expected one of "ground", "walls", "box_columns", "circle_rows", "box_grid", got nothing)");
}

TEST(Errors, ShapeKindIsCheckedLikeAKey) {
  EXPECT_EQ(load_error(scene_with(R"("bodies": [{"shape": {"circel": 1}}])")),
            R"(t.json:1:50: /bodies/0/shape/circel: unknown key; did you mean "circle"?)");
  EXPECT_EQ(
      load_error(scene_with(R"("generators": [{"type": "grund"}])")),
      R"(t.json:1:52: /generators/0/type: expected one of "ground", "walls", "box_columns", "circle_rows", "box_grid", got "grund")");
}

TEST(Errors, SchemaMustBeVersionOne) {
  EXPECT_EQ(load_error(R"({"schema": "fx2d.scene/2"})"),
            R"(t.json:1:12: /schema: expected "fx2d.scene/1", got "fx2d.scene/2")");
  EXPECT_EQ(load_error(R"({"size": 3})"), R"(t.json:1:1: /schema: expected "fx2d.scene/1", got nothing)");
  EXPECT_EQ(load_error("[1]"), "t.json:1:1: (root): expected a scene object, got [1]");
}

TEST(Errors, MissingFileSaysWhyItCannotBeOpened) {
  EXPECT_EQ(error_of([] { load_scene_file("/nonexistent/pile.json"); }),
            "/nonexistent/pile.json: cannot open: No such file or directory");
  EXPECT_EQ(error_of([] { load_scene_file(FX2D_SOURCE_DIR); }),
            std::string(FX2D_SOURCE_DIR) + ": cannot open: Is a directory");
}

TEST(Errors, ValueFromSetIsReportedAgainstTheSet) {
  EXPECT_EQ(error_of([] {
              load_scene_file(scene_path("pile.json"), sets({{"/dt", "-1"}}));
            }),
            "--set /dt=-1: /dt: expected a number >= 1e-06, got -1");
  SceneOverrides bodies;
  bodies.bodies = -1;
  EXPECT_EQ(error_of([&] { load_scene_file(scene_path("pile.json"), bodies); }),
            "--bodies -1: /size: expected an integer >= 0, got -1");
}

TEST(Errors, SetOfAPointerOutsideTheSchemaSuggestsTheNearestKey) {
  EXPECT_EQ(error_of([] {
              load_scene_file(scene_path("pile.json"), sets({{"/generators/2/cout", "5"}}));
            }),
            R"(--set /generators/2/cout=5: /generators/2/cout: unknown key; did you mean "count"?)");
  EXPECT_EQ(error_of([] {
              load_scene_file(scene_path("pile.json"), sets({{"/solver/fx2x/substeps", "5"}}));
            }),
            R"(--set /solver/fx2x/substeps=5: /solver/fx2x: unknown key; did you mean "fx2d"?)");
}

TEST(Errors, SetIntoAMissingElementOrAScalarIsRefused) {
  EXPECT_EQ(error_of([] {
              load_scene_file(scene_path("pile.json"), sets({{"/generators/5/count", "1"}}));
            }),
            R"(--set /generators/5/count=1: /generators: expected an index below 3, got "5")");
  EXPECT_EQ(error_of([] {
              load_scene_file(scene_path("pile.json"), sets({{"/dt/x", "1"}}));
            }),
            R"(--set /dt/x=1: /dt: expected an object or an array to hold "x", got 0.016666666666666666)");
  EXPECT_EQ(error_of([] {
              load_scene_file(scene_path("pile.json"), sets({{"dt", "1"}}));
            }),
            R"(--set dt=1: expected a JSON pointer such as /solver/fx2d/substeps, got "dt")");
}

TEST(Errors, JointMustJoinTwoExistingBodies) {
  const std::string bodies = R"("bodies": [{"shape": {"circle": 1}}, {"shape": {"circle": 1}}], )";
  EXPECT_EQ(load_error(scene_with(bodies + R"("joints": [{"type": "revolute", "a": 0, "b": 2}])")),
            "t.json:1:137: /joints/0/b: expected a body index from 0 to 1, got 2");
  EXPECT_EQ(load_error(scene_with(bodies + R"("joints": [{"type": "revolute", "a": 1, "b": 1}])")),
            "t.json:1:137: /joints/0/b: expected a body other than a (1), got 1");
  EXPECT_EQ(
      load_error(scene_with(bodies + R"("joints": [{"type": "revolute", "a": 0, "b": 1, "length": 2}])")),
      R"(t.json:1:140: /joints/0/length: unknown key; expected one of "type", "a", "b", "anchor_a", "anchor_b")");
}

// Between two bodies that do not move no engine builds a joint: Fx2D and ODE refused it mid-build
// (exit 4) and Chipmunk2D aborted the process.
TEST(Errors, JointNeedsADynamicBody) {
  const std::string bodies =
      R"("bodies": [{"type": "static", "shape": {"circle": 1}}, {"type": "kinematic", "shape": {"circle": 1}}, )"
      R"({"shape": {"circle": 1}}], )";
  EXPECT_EQ(load_error(scene_with(bodies + R"("joints": [{"type": "revolute", "a": 0, "b": 1}])")),
            "t.json:1:202: /joints/0/b: expected a dynamic body, since body a (0) is not dynamic, got 1");
  EXPECT_EQ(load(scene_with(bodies + R"("joints": [{"type": "revolute", "a": 0, "b": 2}])")).joints.size(), 1u);
}

TEST(Errors, PolygonMustBeConvexAndCounterClockwise) {
  const std::string expected_what =
      "expected a convex counter-clockwise polygon of 3 to 8 [x, y] vertices, got ";
  EXPECT_EQ(load_error(scene_with(R"("bodies": [{"shape": {"polygon": [[0, 0], [0, 1], [1, 0]]}}])")),
            "t.json:1:61: /bodies/0/shape/polygon: " + expected_what + "[[0.0,0.0],[0.0,1.0],[1.0,0.0]]");
  EXPECT_EQ(load_error(scene_with(
                R"("bodies": [{"shape": {"polygon": [[0, 0], [2, 0], [1, 0.2], [2, 2], [0, 2]]}}])")),
            "t.json:1:61: /bodies/0/shape/polygon: " + expected_what +
                "[[0.0,0.0],[2.0,0.0],[1.0,0.2],[2.0,2.0],[0.0,2.0]]");
}

TEST(Errors, LocationIsExactInsideNestedArraysAndAfterEscapedKeys) {
  EXPECT_EQ(load_error(R"({
  "schema": "fx2d.scene/1",
  "description": "a \"quoted\" [text] {with} brackets",
  "generators": [
    {"type": "ground", "x\/y": [1, [2, {"k": "]"}]]},
    {"type": "box_grid", "count": 2,
     "half_extents": [0.5,
                      -0.5]}
  ]
})"),
            "t.json:5:24: /generators/0/x~1y: unknown key; expected one of \"type\", \"top\", \"thickness\", "
            "\"center_x\", \"half_width\", \"material\"");
  EXPECT_EQ(load_error(R"({
  "schema": "fx2d.scene/1",
  "description": "a \"quoted\" [text] {with} brackets",
  "generators": [
    {"type": "ground", "top": [1, [2, {"k": "]"}]]},
    {"type": "box_grid", "count": 2,
     "half_extents": [0.5,
                      -0.5]}
  ]
})"),
            "t.json:5:31: /generators/0/top: expected a number from -1000000 to 1000000, got "
            "[1,[2,{\"k\":\"]\"}]]");
}

TEST(Errors, LocationSkipsEarlierElementsOfNestedArrays) {
  EXPECT_EQ(load_error(R"({
  "schema": "fx2d.scene/1",
  "generators": [
    {"type": "ground", "top": 0},
    {"type": "box_grid", "count": 2,
     "half_extents": [0.5,
                      -0.5]}
  ]
})"),
            "t.json:7:23: /generators/1/half_extents/1: expected a number > 0, got -0.5");
}

TEST(Errors, DuplicateKeyIsLocatedAtItsLastOccurrenceLikeItsValue) {
  EXPECT_EQ(load_error("{\"schema\": \"fx2d.scene/1\", \"dt\": 0.1,\n\"dt\": -1}"),
            "t.json:2:7: /dt: expected a number >= 1e-06, got -1");
}

TEST(Errors, InvertedBoundsAreRefused) {
  EXPECT_EQ(load_error(scene_with(R"("bounds": {"lower": [0, 0], "upper": [1, -1]})")),
            "t.json:1:65: /bounds/upper: expected a corner above and right of /bounds/lower, got [1.0,-1.0]");
}

}  // namespace
}  // namespace fxbench

// Tests of the Box2D and ODE adapters and of the engine registry: both adapters build the same
// bodies, integrate free fall the way their integrator predicts, hold a resting box, and (ODE)
// stay in the plane. Scenes are written here as SceneSpec values so that these tests depend on
// no scene file. The fx2d adapter is tested elsewhere; nothing here constructs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "engines/engines.h"
#include "tests/support/spec_builders.h"

namespace fxbench {
namespace {

// Box2D stores positions and angles as float: a value of magnitude m comes back within
// m * 2^-24 (about 6e-8 m); 1e-6 relative, floored at 1e-6, leaves room for sin/cos rounding.
double float_tolerance(double magnitude) { return 1e-6 * std::max(1.0, std::abs(magnitude)); }

using test::box_at;
using test::circle_at;

// Base from (0, 0) to (2, 0) in body space; the centroid (1, 1/3) is off the body origin, which
// Box2D keeps apart from its centre of mass.
BodySpec triangle(Vec2 position, double angle = 0.0) {
  BodySpec body = box_at(position, angle);
  body.shape = ShapeKind::polygon;
  body.vertices = {{0.0, 0.0}, {2.0, 0.0}, {1.0, 1.0}};
  return body;
}

BodySpec static_box(Vec2 position, Vec2 half_extents) {
  BodySpec body = box_at(position);
  body.type = BodyType::static_body;
  body.half_extents = half_extents;
  return body;
}

// Top face at y = 0, as in every canonical scene.
BodySpec ground() { return static_box({0.0, -0.5}, {50.0, 0.5}); }

SceneSpec scene_of(std::vector<BodySpec> bodies) {
  SceneSpec scene;
  scene.name = "adapters_test";
  scene.bodies = std::move(bodies);
  return scene;
}

struct AdapterCase {
  std::string name;
  std::function<std::unique_ptr<Engine>()> make;
  // How far above touching a body resting on the ground settles, metres.
  double box_rest_gap;
  double circle_rest_gap;
  bool builds_polygons;
  // Moves bodies before updating their velocities (explicit rather than symplectic Euler).
  bool positions_first = false;
};

// Box2D 2.4 gives every polygon a skin of b2_polygonRadius = 10 mm and leaves contacts
// overlapping by b2_linearSlop = 5 mm, so a box on a box rests 2 * 10 - 5 = 15 mm up and a
// circle (no skin) on a box 10 - 5 = 5 mm up. ODE's contacts are springs of stiffness
// ERP / (dt CFM) = 1.2e6 N/m per point that sink about 2e-6 m under a 1 kg box: zero at 1 mm.
const AdapterCase box2d_case{"box2d", &make_box2d_engine, 0.015, 0.005, true};
const AdapterCase ode_case{"ode", &make_ode_engine, 0.0, 0.0, false};
// Chipmunk2D lets touching shapes overlap by up to its collision slop (the chipmunk.collision_slop
// knob, 5 mm unless the scene says otherwise) and pushes out only what lies beyond it: a box
// dropped from touching sinks 2.8 mm into it, a circle none. cpSpaceStep moves bodies first.
const AdapterCase chipmunk_case{
    "chipmunk", [] { return find_engine("chipmunk")->make(); }, -0.0028, 0.0, true, true};
// Within 1 mm of the engine's own resting height: well above Box2D's float rounding (6e-8 m)
// and ODE's sinking (2e-6 m), well below any real settling or drift.
constexpr double rest_tolerance = 1e-3;

std::vector<BodyState> run(Engine& engine, const SceneSpec& scene, int steps) {
  engine.build(scene);
  for (int i = 0; i < steps; ++i) engine.step();
  std::vector<BodyState> state;
  engine.read_state(state);
  return state;
}

class AdapterTest : public ::testing::TestWithParam<AdapterCase> {
 protected:
  std::unique_ptr<Engine> engine_ = GetParam().make();
};

TEST_P(AdapterTest, BuiltBodiesReadBackTheirSpecPosesAndVelocities) {
  BodySpec tilted = box_at({1.0, 2.0}, 0.3);
  tilted.linear_velocity = {0.5, -1.5};
  tilted.angular_velocity = 2.0;
  BodySpec kinematic = box_at({-4.0, 3.0}, -0.2);
  kinematic.type = BodyType::kinematic;
  kinematic.linear_velocity = {1.0, 0.0};
  SceneSpec scene = scene_of({ground(), tilted, circle_at({3.0, 7.5}), kinematic});
  if (GetParam().builds_polygons) {
    // A spinning off-centre polygon checks the conversion from centre of mass back to origin.
    BodySpec spinning = triangle({6.0, 4.0}, 0.7);
    spinning.linear_velocity = {-2.0, 1.0};
    spinning.angular_velocity = -3.0;
    BodySpec fixed = triangle({-8.0, 5.0}, -0.4);
    fixed.type = BodyType::static_body;
    scene.bodies.push_back(spinning);
    scene.bodies.push_back(fixed);
  }

  const std::vector<BodyState> state = run(*engine_, scene, 0);

  ASSERT_EQ(state.size(), scene.bodies.size());
  for (size_t i = 0; i < state.size(); ++i) {
    SCOPED_TRACE("body " + std::to_string(i));
    const BodySpec& spec = scene.bodies[i];
    EXPECT_NEAR(state[i].position.x, spec.position.x, float_tolerance(spec.position.x));
    EXPECT_NEAR(state[i].position.y, spec.position.y, float_tolerance(spec.position.y));
    EXPECT_NEAR(state[i].angle, spec.angle, float_tolerance(spec.angle));
    EXPECT_NEAR(state[i].linear_velocity.x, spec.linear_velocity.x, float_tolerance(spec.linear_velocity.x));
    EXPECT_NEAR(state[i].linear_velocity.y, spec.linear_velocity.y, float_tolerance(spec.linear_velocity.y));
    EXPECT_NEAR(state[i].angular_velocity, spec.angular_velocity, float_tolerance(spec.angular_velocity));
  }
}

TEST_P(AdapterTest, FreeFallForOneSecondMatchesSymplecticEuler) {
  const double y0 = 100.0;
  const SceneSpec scene = scene_of({box_at({0.0, y0})});
  const int steps = 60;
  const double g = -scene.gravity.y;
  const double t = steps * scene.dt;

  const std::vector<BodyState> state = run(*engine_, scene, steps);

  // Both engines update velocity, then position with the new velocity (symplectic Euler), so
  // after n steps y = y0 - g dt^2 n (n + 1) / 2: below the exact y0 - g t^2 / 2 by g dt t / 2
  // (8.3 cm here). Box2D's float rounding adds at most one ulp of 100 m (7.6e-6 m) per step:
  // 60 steps stay under 1 mm.
  // An engine that moves bodies first uses each step's velocity one step late: y = y0 -
  // g dt^2 n (n - 1) / 2, above the exact value by the same g dt t / 2.
  const double exact = y0 - g * t * t / 2.0;
  const double symplectic_euler_error = g * scene.dt * t / 2.0;
  const double rounding = 1e-3;
  const double integrator_error =
      GetParam().positions_first ? symplectic_euler_error : -symplectic_euler_error;
  EXPECT_NEAR(state[0].position.y, exact + integrator_error, rounding);
  EXPECT_NEAR(state[0].position.y, exact, symplectic_euler_error + rounding);
  EXPECT_NEAR(state[0].linear_velocity.y, -g * t, float_tolerance(g * t));
}

TEST_P(AdapterTest, BoxRestingOnGroundStaysWithinAMillimetreForTwoSeconds) {
  const SceneSpec scene = scene_of({ground(), box_at({0.0, 0.5})});

  const std::vector<BodyState> state = run(*engine_, scene, 120);

  EXPECT_NEAR(state[1].position.y, 0.5 + GetParam().box_rest_gap, rest_tolerance);
  EXPECT_NEAR(state[1].position.x, 0.0, rest_tolerance);
  EXPECT_NEAR(state[1].angle, 0.0, rest_tolerance);
}

TEST_P(AdapterTest, OneBoxRestingOnGroundMakesOneContact) {
  const SceneSpec scene = scene_of({ground(), box_at({0.0, 0.5})});

  run(*engine_, scene, 120);

  EXPECT_EQ(engine_->contact_count(), 1);
}

TEST_P(AdapterTest, CircleAndBoxOnGroundSettleAtTheirRestingHeights) {
  const SceneSpec scene = scene_of({ground(), circle_at({-2.0, 0.5}), box_at({2.0, 0.5})});

  const std::vector<BodyState> state = run(*engine_, scene, 60);

  ASSERT_EQ(state.size(), 3u);
  EXPECT_NEAR(state[1].position.y, 0.5 + GetParam().circle_rest_gap, rest_tolerance);
  EXPECT_NEAR(state[2].position.y, 0.5 + GetParam().box_rest_gap, rest_tolerance);
  for (size_t i = 1; i < state.size(); ++i) {
    EXPECT_NEAR(state[i].position.x, scene.bodies[i].position.x, rest_tolerance) << "body " << i;
  }
  EXPECT_EQ(engine_->contact_count(), 2);
}

TEST_P(AdapterTest, StackOfFiveBoxesStandsForTwoSeconds) {
  std::vector<BodySpec> bodies{ground()};
  for (int i = 0; i < 5; ++i) bodies.push_back(box_at({0.0, 0.5 + i}));
  const SceneSpec scene = scene_of(bodies);

  const std::vector<BodyState> state = run(*engine_, scene, 120);

  // Each contact holds two bodies within a skin or slop of touching (Box2D's 2 x 10 mm polygon
  // skin the thickest, Chipmunk's 5 mm slop on the other side), so box i stays within i x 2 cm of
  // its start, and sideways within i x 5 mm (Chipmunk's top box creeps 1 cm in these 2 s); a
  // toppled stack is off by metres.
  for (std::size_t i = 1; i < state.size(); ++i) {
    EXPECT_NEAR(state[i].position.y, scene.bodies[i].position.y, static_cast<double>(i) * 0.02)
        << "box " << i;
    EXPECT_NEAR(state[i].position.x, 0.0, static_cast<double>(i) * 0.005) << "box " << i;
  }
  EXPECT_EQ(engine_->contact_count(), 5);
}

JointSpec joint_between(JointKind kind, int a, int b, Vec2 local_anchor_a = {}, Vec2 local_anchor_b = {}) {
  JointSpec joint;
  joint.kind = kind;
  joint.body_a = a;
  joint.body_b = b;
  joint.local_anchor_a = local_anchor_a;
  joint.local_anchor_b = local_anchor_b;
  return joint;
}

// A static post with a box hanging from it on a rigid rod, and a second box pinned to the first.
SceneSpec pendulum_scene() {
  SceneSpec scene = scene_of({static_box({0.0, 10.0}, {0.1, 0.1}), box_at({3.0, 10.0}), box_at({4.0, 10.0})});
  scene.joints = {joint_between(JointKind::distance, 0, 1),
                  joint_between(JointKind::revolute, 1, 2, {0.5, 0.0}, {-0.5, 0.0})};
  return scene;
}

Vec2 world_point(const BodyState& body, Vec2 local) {
  const double c = std::cos(body.angle);
  const double s = std::sin(body.angle);
  return {body.position.x + c * local.x - s * local.y, body.position.y + s * local.x + c * local.y};
}

double distance(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

TEST_P(AdapterTest, JointsHoldTheirLengthAndPinWhileSwinging) {
  const SceneSpec scene = pendulum_scene();
  const double rod_length = 3.0;  // as built: origin to origin

  const std::vector<BodyState> state = run(*engine_, scene, 60);

  // The boxes swing down about 5 m, reaching v = sqrt(2 g h) = 10 m/s. A velocity-level solve
  // lets a rod of length L drift by v^2 dt^2 / (2 L) = 4.6 mm per step; Box2D's position pass
  // removes it down to b2_linearSlop (5 mm), ODE's ERP removes 20% a step, so its drift settles
  // below 4.6 mm / 0.2 = 2.3 cm. 3 cm covers both; a broken joint lets the box fall away by metres.
  const double allowed_error = 3e-2;
  EXPECT_LT(state[1].position.y, 9.0) << "the pendulum never swung";
  EXPECT_NEAR(distance(state[0].position, state[1].position), rod_length, allowed_error);
  const Vec2 pin_on_1 = world_point(state[1], scene.joints[1].local_anchor_a);
  const Vec2 pin_on_2 = world_point(state[2], scene.joints[1].local_anchor_b);
  EXPECT_LT(distance(pin_on_1, pin_on_2), allowed_error);
}

// Two boxes overlapping by half their width, pinned together where they overlap, with no gravity:
// bodies a joint connects never collide (scenes/README.md), so nothing pushes them apart. Were
// they collided, the overlap would be pushed out against the pin and both would move.
TEST_P(AdapterTest, JointedBodiesDoNotCollide) {
  SceneSpec scene = scene_of({box_at({0.0, 0.0}), box_at({0.5, 0.0})});
  scene.gravity = {0.0, 0.0};
  scene.joints = {joint_between(JointKind::revolute, 0, 1, {0.25, 0.0}, {-0.25, 0.0})};

  const std::vector<BodyState> state = run(*engine_, scene, 30);

  EXPECT_EQ(engine_->contact_count(), 0);
  for (std::size_t i = 0; i < state.size(); ++i) {
    EXPECT_NEAR(state[i].position.x, scene.bodies[i].position.x, 1e-3) << "box " << i;
    EXPECT_NEAR(state[i].position.y, 0.0, 1e-3) << "box " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Engines, AdapterTest, ::testing::Values(box2d_case, ode_case, chipmunk_case),
                         [](const ::testing::TestParamInfo<AdapterCase>& param) { return param.param.name; });

TEST(OdeAdapter, TumblingBodiesStayExactlyInThePlane) {
  std::vector<BodySpec> bodies{ground()};
  for (int i = 0; i < 40; ++i) {
    const Vec2 position{1.5 * (i % 10) - 7.0, 1.0 + 1.5 * (i / 10)};
    bodies.push_back(i % 3 == 0 ? circle_at(position) : box_at(position, 0.1 * ((7 * i) % 11 - 5)));
  }
  const SceneSpec scene = scene_of(bodies);
  auto engine = make_ode_engine();

  const std::vector<BodyState> state = run(*engine, scene, 120);

  // Boxes landing on their corners tumble; this is what tilts an unflattened ODE body.
  double largest_turn = 0.0;
  for (size_t i = 1; i < state.size(); ++i) {
    largest_turn = std::max(largest_turn, std::abs(state[i].angle - scene.bodies[i].angle));
  }
  EXPECT_GT(largest_turn, 0.1);
  // Flattening writes z = 0 and a quaternion about z, from which ODE builds a rotation matrix
  // whose out-of-plane entries are exact zeros: nothing is left to round.
  const OutOfPlaneDrift drift = ode_out_of_plane_drift(*engine);
  EXPECT_EQ(drift.position_z, 0.0);
  EXPECT_EQ(drift.linear_velocity_z, 0.0);
  EXPECT_EQ(drift.angular_velocity_xy, 0.0);
  EXPECT_EQ(drift.rotation_off_z, 0.0);
}

// ODE's random generator is one per process, and QuickStep's islands draw from it on whichever
// thread steps them. A one-thread world stepped in turn with a world on ODE's pool of two
// (ode.threads 2), alive beside it, ends bit for bit where it ends stepped alone.
TEST(OdeAdapter, AWorldOnTwoThreadsLeavesAOneThreadWorldBesideItAsIfAlone) {
  std::vector<BodySpec> bodies{ground()};
  for (int i = 0; i < 30; ++i) bodies.push_back(box_at({1.1 * (i % 10) - 5.0, 0.5 + 1.1 * (i / 10)}));
  const SceneSpec scene = scene_of(bodies);
  SceneSpec on_two_threads = scene;
  on_two_threads.resolved_json = R"({"solver": {"ode": {"threads": 2}}})";
  constexpr int steps = 60;
  const std::vector<BodyState> alone = run(*make_ode_engine(), scene, steps);

  auto one_thread = make_ode_engine();
  auto two_threads = make_ode_engine();
  one_thread->build(scene);
  two_threads->build(on_two_threads);
  for (int i = 0; i < steps; ++i) {
    two_threads->step();
    one_thread->step();
  }
  std::vector<BodyState> beside;
  one_thread->read_state(beside);
  ASSERT_EQ(beside.size(), alone.size());
  for (std::size_t i = 0; i < alone.size(); ++i) {
    EXPECT_EQ(beside[i].position.x, alone[i].position.x) << "body " << i;
    EXPECT_EQ(beside[i].position.y, alone[i].position.y) << "body " << i;
    EXPECT_EQ(beside[i].angle, alone[i].angle) << "body " << i;
  }
}

TEST(OdeAdapter, DriftQueryRejectsAnotherEngine) {
  const auto box2d = make_box2d_engine();
  EXPECT_THROW(ode_out_of_plane_drift(*box2d), std::invalid_argument);
}

TEST(OdeAdapter, ReportsNoPhases) { EXPECT_TRUE(make_ode_engine()->phase_names().empty()); }

TEST(Box2dAdapter, ReportsSixNonNegativePhases) {
  auto engine = make_box2d_engine();
  run(*engine, scene_of({ground(), box_at({0.0, 0.5})}), 1);
  const std::vector<std::string> names = engine->phase_names();
  ASSERT_EQ(names.size(), 6u);
  std::vector<double> ms(names.size(), -1.0);
  engine->read_phases(ms);
  for (size_t i = 0; i < ms.size(); ++i) EXPECT_GE(ms[i], 0.0) << names[i];
}

TEST(Box2dAdapter, RejectsPolygonsBeyondEightVertices) {
  BodySpec nonagon = box_at({0.0, 0.0});
  nonagon.shape = ShapeKind::polygon;
  for (int i = 0; i < 9; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / 9.0;
    nonagon.vertices.push_back({std::cos(angle), std::sin(angle)});
  }
  EXPECT_THROW(make_box2d_engine()->build(scene_of({nonagon})), std::runtime_error);
}

TEST(Box2dAdapter, OffCentrePolygonDroppedOnGroundRestsOnItsBase) {
  auto engine = make_box2d_engine();

  const std::vector<BodyState> state = run(*engine, scene_of({ground(), triangle({0.0, 0.2})}), 120);

  // The base is at the origin's height, so the origin rests at the gap between the skins. Box2D
  // corrects positions only beyond b2_linearSlop (5 mm) of overlap, so a body that lands settles
  // anywhere from skins just touching (2 x 10 mm) down to 5 mm into them (15 mm). A centre of
  // mass taken at the origin instead of the centroid would tip the triangle over its corner.
  EXPECT_GE(state[1].position.y, 0.015 - rest_tolerance);
  EXPECT_LE(state[1].position.y, 0.020 + rest_tolerance);
  EXPECT_NEAR(state[1].position.x, 0.0, rest_tolerance);
  EXPECT_NEAR(state[1].angle, 0.0, rest_tolerance);
  EXPECT_EQ(engine->contact_count(), 1);
}

TEST(OdeAdapter, RejectsPolygonsItCannotCollideFaceToFace) {
  EXPECT_THROW(make_ode_engine()->build(scene_of({ground(), triangle({0.0, 0.2})})), std::runtime_error);
}

// The SDK layer (fx2d_bench_plugin.hpp) turns the adapter's exception into the table's one-line
// error, and the half-built world is freed (the sanitizer build reports a leak otherwise).
TEST(ChipmunkAdapter, ReportsABuildFailureAsItsOneLineError) {
  SceneSpec scene = scene_of({ground(), box_at({0.0, 1.0})});
  scene.joints.push_back({JointKind::revolute, 1, 999, {}, {}, -1.0});
  try {
    find_engine("chipmunk")->make()->build(scene);
    FAIL() << "built a joint to a body that does not exist";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "chipmunk plugin: joint body index 999 out of range");
  }
}

TEST(EngineRegistry, ListsFx2dBox2dOdeChipmunkInOrderWithTheirVersions) {
  const auto engines = engine_registry();
  ASSERT_EQ(engines.size(), 4u);
  EXPECT_EQ(engines[0].name, "fx2d");
  EXPECT_EQ(engines[1].name, "box2d");
  EXPECT_EQ(engines[2].name, "ode");
  EXPECT_EQ(engines[3].name, "chipmunk");
  // The versions the project benchmarks against (Debian's packages).
  EXPECT_EQ(engines[1].version.rfind("2.4.", 0), 0u) << engines[1].version;
  EXPECT_EQ(engines[2].version.rfind("0.16", 0), 0u) << engines[2].version;
  EXPECT_EQ(engines[3].version.rfind("7.", 0), 0u) << engines[3].version;
  for (const EngineInfo& info : engines) {
    EXPECT_FALSE(info.settings.empty()) << info.name;
    EXPECT_TRUE(static_cast<bool>(info.make)) << info.name;
    EXPECT_EQ(info.solver, info.name) << "each built-in engine reads its own /solver block";
  }
}

TEST(EngineRegistry, FindsEnginesByExactName) {
  ASSERT_NE(find_engine("ode"), nullptr);
  EXPECT_EQ(find_engine("ode")->name, "ode");
  using Factory = std::unique_ptr<Engine> (*)();
  const Factory* box2d_factory = find_engine("box2d")->make.target<Factory>();
  ASSERT_NE(box2d_factory, nullptr);
  EXPECT_EQ(*box2d_factory, &make_box2d_engine);
  EXPECT_EQ(find_engine("Box2D"), nullptr);
  EXPECT_EQ(find_engine("bullet"), nullptr);
}

}  // namespace
}  // namespace fxbench

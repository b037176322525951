// Tests of the engine-neutral accuracy figures against hand-built poses whose overlaps, motions
// and energies are known in closed form.
//
// Tolerances: the geometry is double precision on lengths of order 1 m, and each figure is a
// handful of additions, products and one sin/cos/sqrt, each good to a few units in the last
// place (~1e-16); 1e-12 leaves four orders of margin and still catches any wrong formula.
#include "metrics/accuracy.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <numbers>
#include <stdexcept>

#include "tests/support/counting_allocator.h"
#include "tests/support/spec_builders.h"


namespace fxbench {
namespace {

constexpr double tolerance = 1e-12;

using test::box_at;
using test::circle_at;

BodySpec polygon_at(Vec2 position, std::vector<Vec2> vertices) {
  BodySpec body;
  body.shape = ShapeKind::polygon;
  body.vertices = std::move(vertices);
  body.position = position;
  return body;
}

SceneSpec scene_of(std::vector<BodySpec> bodies) {
  SceneSpec scene;
  scene.bodies = std::move(bodies);
  return scene;
}

std::vector<BodyState> poses_of(const SceneSpec& scene) {
  std::vector<BodyState> states;
  for (const BodySpec& body : scene.bodies) {
    states.push_back({body.position, body.angle, body.linear_velocity, body.angular_velocity});
  }
  return states;
}

// The figures of a scene measured as built, against its own start.
AccuracySample measure_as_built(const SceneSpec& scene) {
  AccuracyProbe probe(scene, poses_of(scene));
  return probe.measure(1, poses_of(scene));
}

TEST(Penetration, UnitBoxesOverlappingByATenthReportATenth) {
  const AccuracySample sample = measure_as_built(scene_of({box_at({0.0, 0.0}), box_at({0.9, 0.0})}));
  EXPECT_NEAR(sample.max_penetration, 0.1, tolerance);
  EXPECT_NEAR(sample.mean_penetration, 0.1, tolerance);
}

TEST(Penetration, RotatedBoxCornerIntoBoxFaceReportsCornerDepth) {
  // A unit box turned 45 degrees reaches sqrt(2)/2 below its centre; centred so that its lowest
  // corner sits 0.05 below the top face (y = 0.5) of the box beneath.
  const double centre_y = 0.5 + std::numbers::sqrt2 / 2.0 - 0.05;
  const AccuracySample sample =
      measure_as_built(scene_of({box_at({0.0, 0.0}), box_at({0.0, centre_y}, std::numbers::pi / 4.0)}));
  EXPECT_NEAR(sample.max_penetration, 0.05, tolerance);
}

TEST(Penetration, CircleIntoBoxFaceReportsDepthBelowFace) {
  const AccuracySample sample = measure_as_built(scene_of({box_at({0.0, 0.0}), circle_at({0.2, 0.8})}));
  EXPECT_NEAR(sample.max_penetration, 0.2, tolerance);
}

TEST(Penetration, CircleOverBoxCornerReportsRadiusMinusCornerDistance) {
  // Beyond both faces of the corner (0.5, 0.5): only the distance to the corner, 0.3 sqrt(2),
  // counts; the face axes alone would report 0.2.
  const AccuracySample sample = measure_as_built(scene_of({box_at({0.0, 0.0}), circle_at({0.8, 0.8})}));
  EXPECT_NEAR(sample.max_penetration, 0.5 - 0.3 * std::numbers::sqrt2, tolerance);
}

TEST(Penetration, CirclesReportSumOfRadiiMinusCentreDistance) {
  // Centres 0.5 apart along a diagonal: 0.3 + 0.4 - 0.5.
  const AccuracySample sample =
      measure_as_built(scene_of({circle_at({1.0, 1.0}, 0.3), circle_at({1.3, 1.4}, 0.4)}));
  EXPECT_NEAR(sample.max_penetration, 0.2, tolerance);
}

TEST(Penetration, TriangleTipIntoBoxReportsTipDepth) {
  const std::vector<Vec2> tip_down{{0.0, 0.0}, {0.5, 1.0}, {-0.5, 1.0}};
  const AccuracySample sample =
      measure_as_built(scene_of({box_at({0.0, 0.0}), polygon_at({0.0, 0.4}, tip_down)}));
  EXPECT_NEAR(sample.max_penetration, 0.1, tolerance);
}

TEST(Penetration, TouchingOrSeparatedShapesReportZero) {
  const SceneSpec scene = scene_of({
      box_at({0.0, 0.0}), box_at({1.0, 0.0}),          // faces exactly touching
      circle_at({10.0, 0.0}), circle_at({11.5, 0.0}),  // apart
      box_at({20.0, 0.0}), circle_at({20.9, 0.9}),     // bounding boxes overlap, the corner is 0.57 away
  });
  const AccuracySample sample = measure_as_built(scene);
  EXPECT_EQ(sample.max_penetration, 0.0);
  EXPECT_EQ(sample.mean_penetration, 0.0);
}

TEST(Penetration, MeanIsOverOverlappingPairsOnly) {
  const SceneSpec scene = scene_of({
      box_at({0.0, 0.0}), box_at({0.75, 0.0}),     // 0.25
      box_at({10.0, 0.0}), box_at({10.875, 0.0}),  // 0.125
      box_at({20.0, 0.0}), box_at({22.0, 0.0}),    // apart: not in the mean
  });
  const AccuracySample sample = measure_as_built(scene);
  EXPECT_NEAR(sample.max_penetration, 0.25, tolerance);
  EXPECT_NEAR(sample.mean_penetration, 0.1875, tolerance);
}

TEST(Penetration, StaticPairsAndJoinedPairsAreNotMeasured) {
  SceneSpec scene = scene_of({
      box_at({0.0, 0.0}, 0.0, BodyType::static_body),
      box_at({0.5, 0.0}, 0.0, BodyType::static_body),
      box_at({10.0, 0.0}),
      box_at({10.5, 0.0}),
  });
  scene.joints.push_back({JointKind::revolute, 3, 2, {}, {}, -1.0});
  EXPECT_EQ(measure_as_built(scene).max_penetration, 0.0);
}

// A grid of separated unit boxes (gaps of 0.5 m) on a static ground, wide or tall so that both
// sweep axes are exercised, with one box moved 0.75 m towards its neighbour.
SceneSpec grid_with_one_overlap(int columns, int rows, int moved_box) {
  std::vector<BodySpec> bodies;
  for (int i = 0; i < columns * rows; ++i) {
    bodies.push_back(box_at({1.5 * (i % columns), 1.5 * (i / columns)}));
  }
  BodySpec ground = box_at({0.0, -2.0}, 0.0, BodyType::static_body);
  ground.half_extents = {200.0, 0.5};
  bodies.push_back(ground);
  SceneSpec scene = scene_of(std::move(bodies));
  scene.bodies[moved_box].position.x += 0.75;
  return scene;
}

TEST(Penetration, PairSearchFindsOnePlantedOverlapAmongThreeThousandBoxes) {
  for (const auto& [columns, rows] : {std::pair{60, 50}, std::pair{50, 60}}) {
    SceneSpec scene = grid_with_one_overlap(columns, rows, 1234);
    const std::vector<BodyState> start = poses_of(scene);
    AccuracyProbe probe(scene, start);
    std::vector<BodyState> separated = start;
    separated[1234].position.x -= 0.75;
    EXPECT_EQ(probe.measure(1, separated).max_penetration, 0.0) << columns << " x " << rows;
    const AccuracySample planted = probe.measure(2, start);
    EXPECT_NEAR(planted.max_penetration, 0.25, tolerance) << columns << " x " << rows;
    EXPECT_NEAR(planted.mean_penetration, 0.25, tolerance) << columns << " x " << rows;
  }
}

TEST(Motion, DisplacementAndDriftOfDynamicBodiesFromTheirStart) {
  const SceneSpec scene =
      scene_of({box_at({0.0, 0.0}), box_at({10.0, 0.0}), box_at({20.0, 0.0}, 0.0, BodyType::static_body)});
  AccuracyProbe probe(scene, poses_of(scene));
  std::vector<BodyState> moved = poses_of(scene);
  moved[0].position = {3.0, 4.0};    // 5 m away, 3 m sideways
  moved[1].position = {6.0, 0.0};    // 4 m away, all sideways
  moved[2].position = {120.0, 0.0};  // static: not a figure of the simulation
  const AccuracySample sample = probe.measure(7, moved);
  EXPECT_EQ(sample.step, 7);
  EXPECT_NEAR(sample.max_displacement, 5.0, tolerance);
  EXPECT_NEAR(sample.max_lateral_drift, 4.0, tolerance);
}

TEST(Motion, KineticEnergyOfMovingBoxAndSpinningCircle) {
  BodySpec box = box_at({0.0, 0.0});
  box.half_extents = {1.0, 0.5};
  box.material.density = 2.0;
  box.linear_velocity = {3.0, 4.0};
  box.angular_velocity = 2.0;
  BodySpec circle = circle_at({10.0, 0.0});
  circle.angular_velocity = 3.0;
  BodySpec moving_static = box_at({20.0, 0.0}, 0.0, BodyType::static_body);
  moving_static.linear_velocity = {100.0, 0.0};
  const AccuracySample sample = measure_as_built(scene_of({box, circle, moving_static}));

  const double box_mass = 2.0 * 2.0 * 1.0;                               // density * width * height
  const double box_inertia = box_mass * (2.0 * 2.0 + 1.0 * 1.0) / 12.0;  // m (w^2 + h^2) / 12
  const double circle_mass = std::numbers::pi * 0.25;                    // density pi r^2
  const double circle_inertia = circle_mass * 0.25 / 2.0;                // m r^2 / 2
  const double expected = 0.5 * box_mass * 25.0 + 0.5 * box_inertia * 4.0 + 0.5 * circle_inertia * 9.0;
  EXPECT_NEAR(sample.kinetic_energy, expected, tolerance * expected);
}

TEST(Motion, PolygonInertiaIsAboutItsCentroid) {
  // A unit square whose centroid is (2, 1) from the body origin spins with I = m (1 + 1) / 12;
  // a right triangle with legs 3 has m = 4.5 and I = m (3^2 + 3^2) / 18 about its centroid.
  BodySpec square = polygon_at({0.0, 0.0}, {{1.5, 0.5}, {2.5, 0.5}, {2.5, 1.5}, {1.5, 1.5}});
  square.angular_velocity = 2.0;
  BodySpec triangle = polygon_at({10.0, 0.0}, {{0.0, 0.0}, {3.0, 0.0}, {0.0, 3.0}});
  triangle.angular_velocity = 1.0;
  const double expected = 0.5 * (2.0 / 12.0) * 4.0 + 0.5 * (4.5 * 18.0 / 18.0) * 1.0;
  EXPECT_NEAR(measure_as_built(scene_of({square, triangle})).kinetic_energy, expected, tolerance * expected);
}

TEST(Motion, EscapedAndNonFiniteBodiesAreCountedAndKeptOutOfOtherFigures) {
  SceneSpec scene = scene_of({box_at({0.0, 0.0}), box_at({0.0, 5.0}), box_at({0.0, 10.0}),
                              box_at({5000.0, 0.0}, 0.0, BodyType::static_body),
                              box_at({0.0, -10.0}, 0.0, BodyType::static_body)});
  AccuracyProbe probe(scene, poses_of(scene));
  std::vector<BodyState> states = poses_of(scene);
  states[1].position.x = 1500.0;  // beyond the default bounds of +-1000
  states[2].position.x = 1.0e9;
  states[2].angle = std::numeric_limits<double>::quiet_NaN();
  states[4].linear_velocity.y = std::numeric_limits<double>::infinity();
  const AccuracySample sample = probe.measure(1, states);
  EXPECT_EQ(sample.escaped, 1);  // the static body far outside does not count
  EXPECT_EQ(sample.nan, 2);
  EXPECT_NEAR(sample.max_displacement, 1500.0, tolerance * 1500.0);
  EXPECT_EQ(sample.kinetic_energy, 0.0);
  EXPECT_EQ(sample.max_penetration, 0.0);
}

TEST(Probe, MeasureAllocatesNothing) {
  const SceneSpec scene = grid_with_one_overlap(20, 20, 7);
  const std::vector<BodyState> states = poses_of(scene);
  const long long before_construction = test::heap_allocations.load();
  AccuracyProbe probe(scene, states);
  EXPECT_GT(test::heap_allocations.load(), before_construction);  // the counter does see the probe's scratch
  const long long before = test::heap_allocations.load();
  double depth = 0.0;
  for (int step = 1; step <= 3; ++step) depth += probe.measure(step, states).max_penetration;
  EXPECT_EQ(test::heap_allocations.load() - before, 0);
  EXPECT_NEAR(depth, 0.75, tolerance);
}

TEST(Probe, WrongNumberOfStatesIsRejected) {
  const SceneSpec scene = scene_of({box_at({0.0, 0.0}), box_at({5.0, 0.0})});
  EXPECT_THROW(AccuracyProbe(scene, {}), std::invalid_argument);
  AccuracyProbe probe(scene, poses_of(scene));
  EXPECT_THROW(probe.measure(1, {BodyState{}}), std::invalid_argument);
}

TEST(StateHash, OneBitOfOneAngleChangesTheHash) {
  const std::vector<BodyState> states = poses_of(grid_with_one_overlap(5, 5, 0));
  std::vector<BodyState> flipped = states;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &flipped[12].angle, sizeof bits);
  bits ^= 1u;
  std::memcpy(&flipped[12].angle, &bits, sizeof bits);

  EXPECT_EQ(state_hash(states), state_hash(poses_of(grid_with_one_overlap(5, 5, 0))));
  EXPECT_NE(state_hash(states), state_hash(flipped));
  EXPECT_EQ(state_hash(states).size(), 16u);
}

}  // namespace
}  // namespace fxbench

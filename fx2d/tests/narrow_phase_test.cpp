// Tests for the narrow phase's shortcut for pairs apart: a pair it skips is one the collision
// would have given no point.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>

#include "collision/collide.h"
#include "collision/narrow_phase.h"

namespace fx2d::detail {
namespace {

// A fixed sequence of floats in [0, 1), the same on every platform (std::uniform_real_distribution
// is not).
class Sequence {
 public:
  float next() {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<float>(state_ >> 40) * 0x1.0p-24f;
  }
  float between(float low, float high) { return low + (high - low) * next(); }

 private:
  std::uint64_t state_ = 0x2545f4914f6cdd1dull;
};

std::array<FxShape, 6> shapes() {
  const float r = 0.5f;
  return {FxShape::box(0.5f, 0.5f),
          FxShape::box(2.0f, 0.05f),
          FxShape::circle(0.3f),
          FxShape::polygon(std::array<FxVec2f, 3>{FxVec2f{-0.4f, -0.3f}, {0.5f, -0.2f}, {0.0f, 0.6f}}),
          FxShape::polygon(std::array<FxVec2f, 8>{FxVec2f{r, 0.0f},
                                                  {0.7f * r, 0.7f * r},
                                                  {0.0f, r},
                                                  {-0.7f * r, 0.7f * r},
                                                  {-r, 0.0f},
                                                  {-0.7f * r, -0.7f * r},
                                                  {0.0f, -r},
                                                  {0.7f * r, -0.7f * r}}),
          FxShape::box(1.0f, 0.25f, {0.3f, 0.1f}, 0.4f)};
}

// A body's sim as the scene makes it: its centre of mass at the shape's centroid.
BodySim sim_of(const FxShape& shape, FxVec2f origin, float angle, FxVec2f velocity, float spin) {
  BodySim sim;
  sim.origin = origin;
  sim.rotation = FxRot::from_angle(angle);
  sim.local_center = shape.centroid();
  sim.linear_velocity = velocity;
  sim.angular_velocity = spin;
  sim.enclosing_radius = shape.extent();
  return sim;
}

// For pairs placed about the boundary of the test, some far from the origin, with speeds and spins
// up to those of a fast heap: whenever surely_apart() holds, collide() at the margin it allows for
// (0.02 m plus a step of both speeds, which the narrow phase's own margin never exceeds) keeps no
// point, so the narrow phase skips no pair that would have touched.
TEST(NarrowPhase, APairSurelyApartIsOneTheCollisionGivesNoPoint) {
  const std::array<FxShape, 6> all = shapes();
  const float dt = 1.0f / 60.0f;
  Sequence random;
  int skipped = 0, with_points = 0;
  const int trials = 20000;
  for (int trial = 0; trial < trials; ++trial) {
    const FxShape& a = all[trial % all.size()];
    const FxShape& b = all[(trial / all.size()) % all.size()];
    const float far = (trial % 3 == 0) ? 0.0f : (trial % 3 == 1 ? 950.0f : -30000.0f);
    const FxVec2f origin_a{far + random.between(-1.0f, 1.0f), random.between(-1.0f, 1.0f)};
    const float turn = random.between(-3.0f, 3.0f);
    const float distance = a.extent() + b.extent() + random.between(-0.3f, 1.2f);
    const FxVec2f direction{std::cos(turn), std::sin(turn)};
    const auto velocity = [&] {
      return FxVec2f{random.between(-12.0f, 12.0f), random.between(-12.0f, 12.0f)};
    };
    const BodySim sa =
        sim_of(a, origin_a, random.between(-3.0f, 3.0f), velocity(), random.between(-8.0f, 8.0f));
    // B's centroid `distance` from A's, along `direction`.
    const FxVec2f centre_a = sa.origin + rotate(sa.rotation, a.centroid());
    const float angle_b = random.between(-3.0f, 3.0f);
    const FxVec2f origin_b =
        centre_a + distance * direction - rotate(FxRot::from_angle(angle_b), b.centroid());
    const BodySim sb = sim_of(b, origin_b, angle_b, velocity(), random.between(-8.0f, 8.0f));
    const BodyReach reach_a = reach_of(sa), reach_b = reach_of(sb);
    const float margin = 0.02f + dt * (reach_a.speed + reach_b.speed);
    Manifold manifold;
    // In A's frame, as the narrow phase collides a pair.
    collide(a, {{}, sa.rotation}, b, {sb.origin - sa.origin, sb.rotation}, margin, {}, manifold);
    if (surely_apart(reach_a, reach_b, dt)) {
      ++skipped;
      EXPECT_EQ(manifold.point_count, 0) << "trial " << trial << ": a pair said to be apart touches";
    } else if (manifold.point_count > 0) {
      ++with_points;
    }
  }
  // Both sides of the boundary are well visited.
  EXPECT_GT(skipped, trials / 5);
  EXPECT_GT(with_points, trials / 5);
}

// The test's circles hold their shapes and its speeds cover their points' motion: a box spinning
// in place reaches its circle, and its spin counts in its speed.
TEST(NarrowPhase, ABodysReachIsItsEnclosingCircleAndItsFastestPoint) {
  const FxShape box = FxShape::box(0.3f, 0.4f);
  const BodyReach reach = reach_of(sim_of(box, {2.0f, 1.0f}, 0.0f, {3.0f, 4.0f}, -2.0f));
  EXPECT_FLOAT_EQ(reach.radius, 0.5f);
  EXPECT_FLOAT_EQ(reach.centre.x, 2.0f);
  EXPECT_FLOAT_EQ(reach.centre.y, 1.0f);
  EXPECT_FLOAT_EQ(reach.speed, 5.0f + 2.0f * 0.5f);
  const BodyReach still = reach_of(sim_of(box, {2.0f + 1.0f + 0.02f + 1e-3f, 1.0f}, 0.0f, {}, 0.0f));
  const BodyReach here = reach_of(sim_of(box, {2.0f, 1.0f}, 0.0f, {}, 0.0f));
  // 1 mm beyond the two circles and the 2 cm margin: apart; 1 mm inside it: not.
  EXPECT_TRUE(surely_apart(here, still, 1.0f / 60.0f));
  const BodyReach near = reach_of(sim_of(box, {2.0f + 1.0f + 0.02f - 1e-3f, 1.0f}, 0.0f, {}, 0.0f));
  EXPECT_FALSE(surely_apart(here, near, 1.0f / 60.0f));
}

// A pair keeps its manifold's features while it moves less than a fiftieth of its shapes' shortest
// edge, and 8 mm: a card standing on its 2 cm end has its lever arm off by a fifth of a millimetre
// at most, not the 4 mm that an 8 mm allowance would leave it.
TEST(NarrowPhase, AManifoldIsReusedOverAFiftiethOfTheShortestEdgeAndEightMillimetresAtMost) {
  const FxShape ground = FxShape::box(60.0f, 0.5f);
  const FxShape box = FxShape::box(0.5f, 0.5f);
  const FxShape card = FxShape::box(0.01f, 0.4f);
  const FxShape small = FxShape::box(0.05f, 0.05f);
  EXPECT_FLOAT_EQ(manifold_reuse_distance(box, ground), 0.008f);
  EXPECT_FLOAT_EQ(manifold_reuse_distance(ground, card), 0.02f * 0.02f);
  EXPECT_FLOAT_EQ(manifold_reuse_distance(small, box), 0.02f * 0.1f);
  EXPECT_FLOAT_EQ(manifold_reuse_distance(FxShape::circle(0.01f), small), 0.02f * 0.1f);
}

}  // namespace
}  // namespace fx2d::detail

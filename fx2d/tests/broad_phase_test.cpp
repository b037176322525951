// Tests for the broad phase's box arithmetic: swept() gives, to the bit, what adding
// std::min(d, 0) to the lower corner and std::max(d, 0) to the upper gives, for every sign of
// the displacement, signed zeros and NaN included.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>

#include "collision/broad_phase.h"

namespace fx2d::detail {
namespace {

FxAABB swept_per_coordinate(FxAABB box, FxVec2f d) {
  box.lower.x += std::min(d.x, 0.0f);
  box.lower.y += std::min(d.y, 0.0f);
  box.upper.x += std::max(d.x, 0.0f);
  box.upper.y += std::max(d.y, 0.0f);
  return box;
}

std::uint32_t bits(float value) { return std::bit_cast<std::uint32_t>(value); }

TEST(BroadPhaseSwept, MatchesMinAndMaxPerCoordinateToTheBit) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float values[] = {0.0f, -0.0f, 1.5f, -1.5f, 1e-30f, -1e-30f, 3e38f, -3e38f, nan};
  // Corners of both signs and zeros, so that a signed zero added to a signed zero shows.
  const FxAABB boxes[] = {{{-1.0f, -2.0f}, {3.0f, 4.0f}}, {{-0.0f, 0.0f}, {-0.0f, 0.0f}}, {{0.0f, -0.0f}, {0.0f, -0.0f}}};
  for (const FxAABB& box : boxes) {
    for (const float dx : values) {
      for (const float dy : values) {
        const FxAABB expected = swept_per_coordinate(box, {dx, dy});
        const FxAABB got = swept(box, {dx, dy});
        EXPECT_EQ(bits(got.lower.x), bits(expected.lower.x)) << dx << ", " << dy;
        EXPECT_EQ(bits(got.lower.y), bits(expected.lower.y)) << dx << ", " << dy;
        EXPECT_EQ(bits(got.upper.x), bits(expected.upper.x)) << dx << ", " << dy;
        EXPECT_EQ(bits(got.upper.y), bits(expected.upper.y)) << dx << ", " << dy;
      }
    }
  }
}

TEST(BroadPhaseSwept, StretchesTheLowerCornerBackwardsAndTheUpperForwards) {
  const FxAABB box{{0.0f, 0.0f}, {1.0f, 1.0f}};
  const FxAABB moved = swept(box, {0.5f, -0.25f});
  EXPECT_EQ(moved.lower.x, 0.0f);
  EXPECT_EQ(moved.lower.y, -0.25f);
  EXPECT_EQ(moved.upper.x, 1.5f);
  EXPECT_EQ(moved.upper.y, 1.0f);
}

}  // namespace
}  // namespace fx2d::detail

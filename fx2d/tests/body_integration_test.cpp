// The substep's body loops against the scalar arithmetic of one body, lane by lane, to the bit:
// a group whose lanes the speed limits leave alone and one whose lanes they change.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "solver/body_integration.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {
namespace {

std::uint32_t bits(float value) { return std::bit_cast<std::uint32_t>(value); }

// What integrate_positions() does to one body: limits, then the displacement and the turn.
FxBodyState integrated_alone(FxBodyState state, float h, SpeedLimits limits) {
  state.linear_velocity = limited_speed(state.linear_velocity, limits.max_speed);
  state.angular_velocity = limited_spin(state.angular_velocity, limits.max_spin);
  state.delta_position += h * state.linear_velocity;
  state.delta_rotation = integrate_rotation(state.delta_rotation, h * state.angular_velocity);
  return state;
}

void expect_same_bits(const FxBodyState& actual, const FxBodyState& expected, std::uint32_t body) {
  EXPECT_EQ(bits(actual.linear_velocity.x), bits(expected.linear_velocity.x)) << "body " << body;
  EXPECT_EQ(bits(actual.linear_velocity.y), bits(expected.linear_velocity.y)) << "body " << body;
  EXPECT_EQ(bits(actual.angular_velocity), bits(expected.angular_velocity)) << "body " << body;
  EXPECT_EQ(bits(actual.delta_position.x), bits(expected.delta_position.x)) << "body " << body;
  EXPECT_EQ(bits(actual.delta_position.y), bits(expected.delta_position.y)) << "body " << body;
  EXPECT_EQ(bits(actual.delta_rotation.c), bits(expected.delta_rotation.c)) << "body " << body;
  EXPECT_EQ(bits(actual.delta_rotation.s), bits(expected.delta_rotation.s)) << "body " << body;
}

// The position loop writes back a group's velocities only when a limit changed one of them; the
// states must still end as if every body had been limited and written back on its own.
TEST(BodyIntegration, PositionLoopLeavesEachBodyAsItsScalarArithmeticDoes) {
  const SpeedLimits limits{10.0f, 50.0f};
  const float h = 1.0f / 240.0f;
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr float infinity = std::numeric_limits<float>::infinity();
  constexpr std::uint32_t bodies = 2 * lane_count;  // a slow group, then a group with fast lanes
  std::vector<FxBodyState> states(bodies + 1);      // the last one is the padding body
  for (std::uint32_t i = 0; i < bodies; ++i) {
    const float k = static_cast<float>(i);
    states[i] = {{0.5f * k - 3.0f, 1.25f - 0.3f * k}, 2.0f - 0.7f * k, 0, {0.01f * k, -0.02f * k}, FxRot::from_angle(0.1f * k)};
  }
  FxBodyState* fast = states.data() + lane_count;
  fast[1].linear_velocity = {30.0f, -40.0f};
  fast[3].angular_velocity = -80.0f;
  fast[4].angular_velocity = nan;
  fast[6].linear_velocity = {infinity, 1.0f};
  const std::vector<FxBodyState> before = states;

  BodyIntegration integration;
  integration.reserve(bodies);
  integration.clear(bodies, bodies);
  for (std::uint32_t i = 0; i < bodies; ++i) integration.add_moving(i);
  integration.finish();
  integration.integrate_positions(states, h, limits, Tasks{});

  for (std::uint32_t i = 0; i < bodies; ++i) expect_same_bits(states[i], integrated_alone(before[i], h, limits), i);
}

}  // namespace
}  // namespace fx2d::detail

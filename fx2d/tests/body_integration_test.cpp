// The substep's body loops and the step's write-back against the scalar arithmetic of one body,
// lane by lane, to the bit: a group whose lanes the speed limits leave alone and one whose lanes
// they change.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
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

// What write_back_bodies() does to one body's rest time, branch by branch.
BodyRecord rested_alone(BodyRecord record, const BodySim& sim, const FxSceneSettings& settings) {
  const float speed_squared = length_squared(sim.linear_velocity);
  const bool slow = speed_squared < settings.linear_sleep_speed * settings.linear_sleep_speed &&
                    sim.angular_velocity * sim.angular_velocity < settings.angular_sleep_speed * settings.angular_sleep_speed;
  if (!slow || !record.can_sleep) {
    record.sleep_time = 0.0f;
    return record;
  }
  if (record.sleep_time == 0.0f) record.rest_start_speed = std::sqrt(speed_squared);
  record.sleep_time += settings.dt;
  if (record.sleep_time < settings.time_to_sleep) return record;
  const float sliding_speed = record.rest_start_speed + 0.5f * settings.linear_sleep_speed;
  if (speed_squared > sliding_speed * sliding_speed) record.sleep_time = 0.0f;
  return record;
}

// What write_back_bodies() does to one body's sim: the pose advanced by the state's, the origin
// with its carry, and the state's velocity, limited.
BodySim written_back_alone(BodySim sim, const FxBodyState& state, SpeedLimits limits) {
  const FxRot start = sim.rotation;
  FxRot end = mul(state.delta_rotation, start);
  const float norm = std::sqrt(end.c * end.c + end.s * end.s);
  end = {end.c / norm, end.s / norm};
  FxCarryAdd(sim.origin, sim.carry,
             state.delta_position + rotate(start, sim.local_center) - rotate(end, sim.local_center));
  sim.rotation = end;
  sim.linear_velocity = limited_speed(state.linear_velocity, limits.max_speed);
  sim.angular_velocity = limited_spin(state.angular_velocity, limits.max_spin);
  return sim;
}

void expect_same_bits(const BodySim& actual, const BodySim& expected, std::uint32_t body) {
  const float actual_fields[] = {actual.origin.x,          actual.origin.y,          actual.carry.x,
                                 actual.carry.y,           actual.rotation.c,        actual.rotation.s,
                                 actual.local_center.x,    actual.local_center.y,    actual.linear_velocity.x,
                                 actual.linear_velocity.y, actual.angular_velocity, actual.inv_mass,
                                 actual.inv_inertia,       actual.force.x,           actual.force.y};
  const float expected_fields[] = {expected.origin.x,          expected.origin.y,          expected.carry.x,
                                   expected.carry.y,           expected.rotation.c,        expected.rotation.s,
                                   expected.local_center.x,    expected.local_center.y,    expected.linear_velocity.x,
                                   expected.linear_velocity.y, expected.angular_velocity, expected.inv_mass,
                                   expected.inv_inertia,       expected.force.x,           expected.force.y};
  for (std::size_t field = 0; field < std::size(actual_fields); ++field) {
    EXPECT_EQ(bits(actual_fields[field]), bits(expected_fields[field])) << "body " << body << ", field " << field;
  }
}

// A whole group with fast lanes, then a group of three (its lanes repeat the last body), in a
// shuffled order that skips two bodies, which must stay as they were; the rest times take every
// branch: too fast, spinning, unable to sleep, starting to rest, resting on, resting past
// time_to_sleep, and sliding from rest.
TEST(BodyIntegration, WriteBackLeavesEachSimAsItsScalarArithmeticDoes) {
  const SpeedLimits limits{10.0f, 50.0f};
  FxSceneSettings settings;
  settings.dt = 1.0f / 60.0f;
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr std::uint32_t bodies = lane_count + 5;
  std::vector<FxBodyState> states(bodies);
  std::vector<BodySim> sims(bodies);
  for (std::uint32_t i = 0; i < bodies; ++i) {
    const float k = static_cast<float>(i);
    states[i] = {{0.5f * k - 3.0f, 1.25f - 0.3f * k}, 2.0f - 0.7f * k, 0, {0.01f * k, -0.02f * k}, FxRot::from_angle(0.1f * k)};
    BodySim& sim = sims[i];
    sim.origin = {1000.0f + 3.0f * k, -7.0f * k};
    sim.carry = {1.0e-5f * k, -2.0e-5f * k};
    sim.rotation = FxRot::from_angle(0.37f * k - 1.0f);
    sim.local_center = {0.25f * k - 1.0f, 0.5f - 0.125f * k};
    sim.inv_mass = 1.0f / (k + 1.0f);
    sim.inv_inertia = 2.0f / (k + 1.0f);
    sim.force = {k, -k};
  }
  states[1].linear_velocity = {30.0f, -40.0f};
  states[3].angular_velocity = -80.0f;
  states[4].angular_velocity = nan;
  states[6].linear_velocity = {nan, 1.0f};
  std::vector<BodyRecord> records(bodies);
  const float time_to_sleep = settings.time_to_sleep;
  struct Rest {
    std::uint32_t body;
    FxVec2f velocity;
    float spin, sleep_time, rest_start_speed;
    bool can_sleep;
  };
  for (const Rest& rest : {Rest{0, {0.01f, 0.02f}, 0.0f, 0.0f, 0.0f, true},                       // starts
                           Rest{2, {0.01f, 0.02f}, 0.01f, 0.1f, 0.02f, true},                     // rests on
                           Rest{5, {0.0f, 0.01f}, 0.0f, time_to_sleep, 0.001f, true},             // past it
                           Rest{7, {0.03f, 0.03f}, 0.0f, time_to_sleep, 0.001f, true},            // slides
                           Rest{9, {0.01f, 0.0f}, 0.2f, 0.3f, 0.01f, true},                       // spins
                           Rest{10, {0.01f, 0.0f}, 0.0f, 0.3f, 0.01f, false},                     // cannot
                           Rest{12, {0.2f, 0.0f}, 0.0f, 0.3f, 0.01f, true}}) {                    // too fast
    states[rest.body].linear_velocity = rest.velocity;
    states[rest.body].angular_velocity = rest.spin;
    records[rest.body].sleep_time = rest.sleep_time;
    records[rest.body].rest_start_speed = rest.rest_start_speed;
    records[rest.body].can_sleep = rest.can_sleep;
  }
  const std::vector<std::uint32_t> block = {12, 0, 3, 1, 5, 4, 6, 2, 9, 7, 10};  // not 8 or 11
  const std::vector<BodySim> before = sims;
  const std::vector<BodyRecord> records_before = records;

  write_back_bodies(block, states.data(), sims.data(), records.data(), limits, settings);

  std::vector<BodySim> expected = before;
  std::vector<BodyRecord> expected_records = records_before;
  for (const std::uint32_t i : block) {
    expected[i] = written_back_alone(before[i], states[i], limits);
    expected_records[i] = rested_alone(records_before[i], expected[i], settings);
  }
  for (std::uint32_t i = 0; i < bodies; ++i) {
    expect_same_bits(sims[i], expected[i], i);
    EXPECT_EQ(bits(records[i].sleep_time), bits(expected_records[i].sleep_time)) << "body " << i;
    EXPECT_EQ(bits(records[i].rest_start_speed), bits(expected_records[i].rest_start_speed)) << "body " << i;
  }
  // The branches above were taken: one body starts to rest, one slides, one rests on past it.
  EXPECT_GT(records[0].rest_start_speed, 0.0f);
  EXPECT_EQ(records[7].sleep_time, 0.0f);
  EXPECT_GT(records[5].sleep_time, time_to_sleep);
}

// A later substep's integration carries on each body's impulses since the last integration (its
// warm start, Substep::carries_warm_start) but not what the speed limits took off in between, which no
// impulse applied: carried on, the limit would be applied again as if it were an impulse.
TEST(BodyIntegration, ACarryingIntegrationReappliesTheImpulsesButNotTheLimits) {
  const SpeedLimits limits{10.0f, 50.0f};
  const float h = 1.0f / 480.0f;
  const FxVec2f gravity{0.0f, -10.0f};
  const float damping = 1.0f / (1.0f + 0.5f * h);
  constexpr std::uint32_t bodies = lane_count;
  std::vector<FxBodyState> states(bodies + 1);  // the last one is the padding body
  BodyIntegration integration;
  integration.reserve(bodies);
  integration.clear(bodies, bodies);
  for (std::uint32_t i = 0; i < bodies; ++i) {
    const float k = static_cast<float>(i);
    states[i] = {{0.5f * k - 2.0f, 1.0f - 0.25f * k}, 1.5f - 0.4f * k, movable_flag, {}, {}};
    integration.add_moving(i);
    integration.add_dynamic(i, gravity, damping, damping);
  }
  integration.finish();
  struct Velocity {
    FxVec2f linear;
    float angular;
  };
  const auto integrated = [&](FxVec2f v, float w) {
    return Velocity{limited_speed(damping * (v + h * gravity), limits.max_speed),
                    limited_spin(damping * w, limits.max_spin)};
  };

  integration.integrate_velocities(states, h, limits, false, Tasks{});
  // The substep's impulses; body 3's takes it past max_speed and body 5's past max_spin, so the
  // position integration limits them.
  std::vector<Velocity> impulse(bodies);
  for (std::uint32_t i = 0; i < bodies; ++i) {
    const float k = static_cast<float>(i);
    impulse[i] = {{0.3f * k - 1.0f, 0.75f + 0.1f * k}, 0.2f * k - 0.5f};
  }
  impulse[3].linear = {40.0f, 0.0f};
  impulse[5].angular = 90.0f;
  for (std::uint32_t i = 0; i < bodies; ++i) {
    states[i].linear_velocity += impulse[i].linear;
    states[i].angular_velocity += impulse[i].angular;
  }
  integration.integrate_positions(states, h, limits, Tasks{});
  ASSERT_FLOAT_EQ(length(states[3].linear_velocity), limits.max_speed);
  ASSERT_FLOAT_EQ(states[5].angular_velocity, limits.max_spin);
  const std::vector<FxBodyState> substep_end = states;

  integration.integrate_velocities(states, h, limits, true, Tasks{});
  for (std::uint32_t i = 0; i < bodies; ++i) {
    const Velocity next = integrated(substep_end[i].linear_velocity, substep_end[i].angular_velocity);
    const FxVec2f v = next.linear + impulse[i].linear;
    const float w = next.angular + impulse[i].angular;
    // Equal but for rounding: the impulses are recovered as a difference of velocities.
    EXPECT_NEAR(states[i].linear_velocity.x, v.x, 1e-5f) << "body " << i;
    EXPECT_NEAR(states[i].linear_velocity.y, v.y, 1e-5f) << "body " << i;
    EXPECT_NEAR(states[i].angular_velocity, w, 1e-4f) << "body " << i;
  }
  EXPECT_EQ(states[bodies].linear_velocity.x, 0.0f);  // the padding body stays at rest
  EXPECT_EQ(states[bodies].angular_velocity, 0.0f);
}
}  // namespace
}  // namespace fx2d::detail

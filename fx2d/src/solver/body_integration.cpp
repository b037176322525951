// The substep's body loops (body_integration.h): each group of eight bodies is gathered into lane
// columns, integrated as one loop the compiler vectorises, and scattered back; the rare lane over
// the speed limit is slowed by the scalar slowed_to(), defined here too.
#include "solver/body_integration.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "solver/lane_rows.h"

namespace fx2d::detail {

FxVec2f slowed_to(FxVec2f v, float max_speed) {
  const float speed_squared = length_squared(v);
  if (std::isfinite(speed_squared)) return v * (max_speed / std::sqrt(speed_squared));
  // Overflowed, or not a number: keep the direction of the largest components, or the infinite
  // components' signs alone; a NaN component counts as zero.
  if (!is_finite(v)) {
    v = {std::isinf(v.x) ? std::copysign(1.0f, v.x) : 0.0f, std::isinf(v.y) ? std::copysign(1.0f, v.y) : 0.0f};
  }
  const float largest = std::max(std::fabs(v.x), std::fabs(v.y));
  return largest > 0.0f ? max_speed * normalize((1.0f / largest) * v) : FxVec2f{};
}

namespace {

// The rare lanes the vectorised limit did not cover: faster than max_speed, overflowed or NaN.
// One vector test for the whole group first, so the usual group, with none, skips the eight
// scalar compare-and-branches. Returns whether it slowed any lane.
FX2D_LANE_INLINE bool slow_fast_lanes(float* vx, float* vy, const float* speed_squared, float max_speed) {
  const float max_speed_squared = max_speed * max_speed;
  int fast_lanes = 0;
  // check-vectorized(1, gcc): the lane loop below must be vectorised (ci/check-vectorized)
#pragma GCC unroll 1
  for (int lane = 0; lane < lane_count; ++lane) fast_lanes |= !(speed_squared[lane] <= max_speed_squared);  // NaN too
  if (fast_lanes == 0) return false;
  for (int lane = 0; lane < lane_count; ++lane) {
    if (speed_squared[lane] <= max_speed_squared) continue;  // also false for NaN
    const FxVec2f slowed = slowed_to({vx[lane], vy[lane]}, max_speed);
    vx[lane] = slowed.x, vy[lane] = slowed.y;
  }
  return true;
}

// v <- linear_factor * (v + h * acceleration), with its squared speed for slow_fast_lanes();
// w <- angular_factor * w, limited.
FX2D_LANE_INLINE void accelerate_lanes(float* __restrict vx, float* __restrict vy, float* __restrict w,
                                       float* __restrict speed_squared, const float* __restrict ax,
                                       const float* __restrict ay, const float* __restrict linear_factor,
                                       const float* __restrict angular_factor, float h, float max_spin) {
  // check-vectorized(1, gcc): the lane loop below must be vectorised (ci/check-vectorized)
#pragma GCC unroll 1  // unrolled first, the loop is left to the weaker straight-line vectoriser
  for (int lane = 0; lane < lane_count; ++lane) {
    const float x = linear_factor[lane] * (vx[lane] + h * ax[lane]);
    const float y = linear_factor[lane] * (vy[lane] + h * ay[lane]);
    vx[lane] = x, vy[lane] = y;
    speed_squared[lane] = x * x + y * y;
    w[lane] = limited_spin(w[lane] * angular_factor[lane], max_spin);
  }
}

struct DynamicColumns {
  const std::uint32_t* body;
  const float *acceleration_x, *acceleration_y, *linear_factor, *angular_factor;
  float *integrated_x, *integrated_y, *integrated_w;
};

FX2D_LANE_KERNEL void integrate_velocity_groups(DynamicColumns d, std::size_t count, FxBodyState* states,
                                                float h, SpeedLimits limits, bool carry_impulses) {
  for (std::size_t first = 0; first < count; first += lane_count) {
    LaneColumns row;
    gather_columns<velocity_row>(states, d.body + first, row);
    alignas(32) float vx[lane_count], vy[lane_count], w[lane_count], speed_squared[lane_count];
    to_lanes(row.c0, vx), to_lanes(row.c1, vy), to_lanes(row.c2, w);
    accelerate_lanes(vx, vy, w, speed_squared, d.acceleration_x + first, d.acceleration_y + first, d.linear_factor + first,
                     d.angular_factor + first, h, limits.max_spin);
    slow_fast_lanes(vx, vy, speed_squared, limits.max_speed);
    // What the impulses changed each velocity by since its last integration, its velocity now less
    // the one that integration gave it, is carried on.
    LaneColumn integrated_x, integrated_y, integrated_w;
    from_lanes(vx, integrated_x), from_lanes(vy, integrated_y), from_lanes(w, integrated_w);
    if (carry_impulses) {
      LaneColumn last_x, last_y, last_w;
      from_lanes(d.integrated_x + first, last_x), from_lanes(d.integrated_y + first, last_y);
      from_lanes(d.integrated_w + first, last_w);
      row.c0 = integrated_x + (row.c0 - last_x);
      row.c1 = integrated_y + (row.c1 - last_y);
      row.c2 = integrated_w + (row.c2 - last_w);
    } else {
      row.c0 = integrated_x, row.c1 = integrated_y, row.c2 = integrated_w;
    }
    to_lanes(integrated_x, d.integrated_x + first), to_lanes(integrated_y, d.integrated_y + first);
    to_lanes(integrated_w, d.integrated_w + first);
    scatter_columns<velocity_row>(states, d.body + first, row);
  }
}

// Where the integrated velocities of the awake dynamic bodies are kept (BodyIntegration).
struct IntegratedVelocities {
  float *x, *y, *w;
  const std::uint32_t* entry_of_body;
};

// A limit that slows a dynamic body between two integrations changes its velocity as no impulse
// does: its integrated velocity takes the change, so that the next integration carries on only
// what the impulses did. Reads each lane's velocity before the limits from its state, not yet
// written back; `vx`, `vy`, `w` are after. Out of line: few groups have a lane over a limit.
[[gnu::cold, gnu::noinline]] void take_limits_into_integrated(const std::uint32_t* body,
                                                              const FxBodyState* states, const float* vx,
                                                              const float* vy, const float* w,
                                                              const IntegratedVelocities& integrated) {
  for (int lane = 0; lane < lane_count; ++lane) {
    const FxBodyState& before = states[body[lane]];
    if ((before.flags & movable_flag) == 0) continue;  // kinematic, or the padding body
    const std::uint32_t entry = integrated.entry_of_body[body[lane]];
    integrated.x[entry] += vx[lane] - before.linear_velocity.x;
    integrated.y[entry] += vy[lane] - before.linear_velocity.y;
    integrated.w[entry] += w[lane] - before.angular_velocity;
  }
}

FX2D_LANE_KERNEL void integrate_position_groups(const std::uint32_t* body, std::size_t count,
                                                FxBodyState* states, float h, SpeedLimits limits,
                                                const IntegratedVelocities& integrated) {
  for (std::size_t first = 0; first < count; first += lane_count) {
    LaneColumns velocity, pose;
    gather_columns<velocity_row>(states, body + first, velocity);
    gather_columns<pose_row>(states, body + first, pose);
    alignas(32) float vx[lane_count], vy[lane_count], w[lane_count], speed_squared[lane_count];
    to_lanes(velocity.c0, vx), to_lanes(velocity.c1, vy), to_lanes(velocity.c2, w);
    int spinning_too_fast = 0;  // limited_spin() changes exactly a spin beyond +-max_spin, or NaN
    // check-vectorized(1, gcc): the lane loop below must be vectorised (ci/check-vectorized)
#pragma GCC unroll 1
    for (int lane = 0; lane < lane_count; ++lane) {
      speed_squared[lane] = vx[lane] * vx[lane] + vy[lane] * vy[lane];
      spinning_too_fast |= !(std::fabs(w[lane]) <= limits.max_spin);
      w[lane] = limited_spin(w[lane], limits.max_spin);
    }
    // Velocities the limits left alone are already in the states: not written back.
    const bool limited = slow_fast_lanes(vx, vy, speed_squared, limits.max_speed) || spinning_too_fast != 0;
    alignas(32) float dpx[lane_count], dpy[lane_count], qc[lane_count], qs[lane_count];
    to_lanes(pose.c0, dpx), to_lanes(pose.c1, dpy), to_lanes(pose.c2, qc), to_lanes(pose.c3, qs);
    // check-vectorized(1, gcc): the lane loop below must be vectorised (ci/check-vectorized)
#pragma GCC unroll 1
    for (int lane = 0; lane < lane_count; ++lane) {
      dpx[lane] += h * vx[lane];
      dpy[lane] += h * vy[lane];
      const FxRot q = integrate_rotation({qc[lane], qs[lane]}, h * w[lane]);
      qc[lane] = q.c, qs[lane] = q.s;
    }
    from_lanes(dpx, pose.c0), from_lanes(dpy, pose.c1), from_lanes(qc, pose.c2), from_lanes(qs, pose.c3);
    scatter_columns<pose_row>(states, body + first, pose);
    // Last, so that no vector register is live across the call.
    if (limited) {
      take_limits_into_integrated(body + first, states, vx, vy, w, integrated);
      from_lanes(vx, velocity.c0), from_lanes(vy, velocity.c1), from_lanes(w, velocity.c2);
      scatter_columns<velocity_row>(states, body + first, velocity);
    }
  }
}

// The group of eight at `body`, or, for the last `count` < 8 bodies of a block, those bodies with
// the last repeated: a repeated lane computes and writes the same values as the lane it repeats.
FX2D_LANE_INLINE const std::uint32_t* whole_group(const std::uint32_t* body, std::size_t count,
                                                  std::uint32_t* repeated) {
  if (count >= lane_count) return body;
  for (std::size_t lane = 0; lane < lane_count; ++lane) repeated[lane] = body[std::min(lane, count - 1)];
  return repeated;
}

// A body that speeds up by this share of linear_sleep_speed while it rests is sliding, not resting.
constexpr float rest_speed_gain_share = 0.5f;

struct RestColumns {
  alignas(32) float sleep_time[lane_count];
  alignas(32) float rest_start_speed[lane_count];
  alignas(32) std::int32_t can_sleep[lane_count];
};

// Counts how long each lane's body has rested: slower than the sleep speeds, and not speeding up.
// Speed alone would put to sleep a box that slides from rest at less than linear_sleep_speed /
// time_to_sleep (0.1 m/s^2): it falls asleep before it reaches the sleep speed, and stability's
// friction_ramp found a mu = 2.28 box stopped on a 66.5 degree slope that Coulomb friction slides
// at 0.0996 m/s^2. So a body that has gained half the sleep speed since it began to rest
// (accelerating at 0.05 m/s^2 or more over time_to_sleep) starts its rest anew. Settling bodies
// only slow down, and a resting one's speed jitters far below that, so neither sleeps later.
// Reads the limited velocities; every lane computes every branch and keeps the one it takes.
FX2D_LANE_INLINE void count_rest_lanes(const float* vx, const float* vy, const float* w, RestColumns& rest,
                                       const FxSceneSettings& settings) {
  const float linear_squared = settings.linear_sleep_speed * settings.linear_sleep_speed;
  const float angular_squared = settings.angular_sleep_speed * settings.angular_sleep_speed;
  const float sliding_gain = rest_speed_gain_share * settings.linear_sleep_speed;
  const float dt = settings.dt, time_to_sleep = settings.time_to_sleep;
  // check-vectorized(1, gcc): the lane loop below must be vectorised (ci/check-vectorized)
#pragma GCC unroll 1
  for (int lane = 0; lane < lane_count; ++lane) {
    const float speed_squared = vx[lane] * vx[lane] + vy[lane] * vy[lane];
    // & rather than &&: a branch would keep the loop scalar.
    const bool resting =
        (speed_squared < linear_squared) & (w[lane] * w[lane] < angular_squared) & (rest.can_sleep[lane] != 0);
    const float sleep_time = rest.sleep_time[lane];
    const float speed = std::sqrt(speed_squared);  // for every lane, as a branch would keep it scalar
    const float start_speed = (resting & (sleep_time == 0.0f)) ? speed : rest.rest_start_speed[lane];
    const float rested = resting ? sleep_time + dt : 0.0f;
    const float sliding_speed = start_speed + sliding_gain;
    const bool sliding = !(rested < time_to_sleep) & (speed_squared > sliding_speed * sliding_speed);
    rest.rest_start_speed[lane] = start_speed;
    rest.sleep_time[lane] = sliding ? 0.0f : rested;
  }
}

FX2D_LANE_KERNEL void write_back_groups(const std::uint32_t* body, std::size_t count, const FxBodyState* states,
                                        BodySim* sims, BodyRecord* records, SpeedLimits limits,
                                        const FxSceneSettings& settings) {
  for (std::size_t first = 0; first < count; first += lane_count) {
    std::uint32_t repeated[lane_count];
    const std::uint32_t* group = whole_group(body + first, count - first, repeated);
    LaneColumns velocity, pose, place, turn, sim_velocity;
    gather_columns<velocity_row>(states, group, velocity);
    gather_columns<pose_row>(states, group, pose);
    gather_columns<sim_place_row>(sims, group, place);
    gather_columns<sim_turn_row>(sims, group, turn);
    gather_columns<sim_velocity_row>(sims, group, sim_velocity);
    alignas(32) float dpx[lane_count], dpy[lane_count], dqc[lane_count], dqs[lane_count];
    to_lanes(pose.c0, dpx), to_lanes(pose.c1, dpy), to_lanes(pose.c2, dqc), to_lanes(pose.c3, dqs);
    alignas(32) float ox[lane_count], oy[lane_count], kx[lane_count], ky[lane_count];
    to_lanes(place.c0, ox), to_lanes(place.c1, oy), to_lanes(place.c2, kx), to_lanes(place.c3, ky);
    alignas(32) float rc[lane_count], rs[lane_count], lx[lane_count], ly[lane_count];
    to_lanes(turn.c0, rc), to_lanes(turn.c1, rs), to_lanes(turn.c2, lx), to_lanes(turn.c3, ly);
    alignas(32) float vx[lane_count], vy[lane_count], w[lane_count], speed_squared[lane_count];
    to_lanes(velocity.c0, vx), to_lanes(velocity.c1, vy), to_lanes(velocity.c2, w);
    // check-vectorized(1, gcc): the lane loop below must be vectorised (ci/check-vectorized)
#pragma GCC unroll 1
    for (int lane = 0; lane < lane_count; ++lane) {
      const FxRot start{rc[lane], rs[lane]};
      FxRot end = mul(FxRot{dqc[lane], dqs[lane]}, start);
      const float norm = std::sqrt(end.c * end.c + end.s * end.s);
      end = {end.c / norm, end.s / norm};
      // The origin moves with the centre of mass and swings about it as the body turns.
      const FxVec2f local_center{lx[lane], ly[lane]};
      const FxVec2f origin_step =
          FxVec2f{dpx[lane], dpy[lane]} + rotate(start, local_center) - rotate(end, local_center);
      FxCarryAdd(ox[lane], kx[lane], origin_step.x);
      FxCarryAdd(oy[lane], ky[lane], origin_step.y);
      rc[lane] = end.c, rs[lane] = end.s;
      speed_squared[lane] = vx[lane] * vx[lane] + vy[lane] * vy[lane];
      w[lane] = limited_spin(w[lane], limits.max_spin);
    }
    slow_fast_lanes(vx, vy, speed_squared, limits.max_speed);
    RestColumns rest;
    for (int lane = 0; lane < lane_count; ++lane) {
      const BodyRecord& record = records[group[lane]];
      rest.sleep_time[lane] = record.sleep_time;
      rest.rest_start_speed[lane] = record.rest_start_speed;
      rest.can_sleep[lane] = record.can_sleep;
    }
    count_rest_lanes(vx, vy, w, rest, settings);
    for (int lane = 0; lane < lane_count; ++lane) {
      BodyRecord& record = records[group[lane]];
      record.sleep_time = rest.sleep_time[lane];
      record.rest_start_speed = rest.rest_start_speed[lane];
    }
    from_lanes(ox, place.c0), from_lanes(oy, place.c1), from_lanes(kx, place.c2), from_lanes(ky, place.c3);
    from_lanes(rc, turn.c0), from_lanes(rs, turn.c1);
    from_lanes(vx, sim_velocity.c0), from_lanes(vy, sim_velocity.c1), from_lanes(w, sim_velocity.c2);
    scatter_columns<sim_place_row>(sims, group, place);
    scatter_columns<sim_turn_row>(sims, group, turn);
    scatter_columns<sim_velocity_row>(sims, group, sim_velocity);
  }
}

}  // namespace

void write_back_bodies(std::span<const std::uint32_t> bodies, const FxBodyState* states, BodySim* sims,
                       BodyRecord* records, SpeedLimits limits, const FxSceneSettings& settings) {
  write_back_groups(bodies.data(), bodies.size(), states, sims, records, limits, settings);
}

void BodyIntegration::reserve(std::size_t bodies) {
  const std::size_t padded = bodies + lane_count;
  moving_.reserve(padded);
  dynamic_.reserve(padded);
  entry_of_body_.reserve(padded);
  for (std::vector<float>* column : {&acceleration_x_, &acceleration_y_, &linear_factor_, &angular_factor_,
                                     &integrated_x_, &integrated_y_, &integrated_w_}) {
    column->reserve(padded);
  }
}

void BodyIntegration::clear(std::uint32_t padding_body, std::size_t body_count) {
  padding_body_ = padding_body;
  moving_count_ = 0;
  moving_size_ = 0;
  dynamic_size_ = 0;
  // Only grows (within reserve()'s room for the scene's bodies), so a step re-initialises nothing.
  const std::size_t padded = body_count + lane_count;
  if (moving_.size() >= padded) return;
  moving_.resize(padded);
  dynamic_.resize(padded);
  entry_of_body_.resize(padded);
  for (std::vector<float>* column : {&acceleration_x_, &acceleration_y_, &linear_factor_, &angular_factor_,
                                     &integrated_x_, &integrated_y_, &integrated_w_}) {
    column->resize(padded);
  }
}

void BodyIntegration::finish() {
  moving_count_ = moving_size_;
  while (moving_size_ % lane_count != 0) add_moving(padding_body_);
  while (dynamic_size_ % lane_count != 0) add_dynamic(padding_body_, {}, 1.0f, 1.0f);
}

void BodyIntegration::integrate_velocities(std::span<FxBodyState> states, float h, SpeedLimits limits,
                                           bool carry_impulses, const Tasks& tasks) {
  const auto count = static_cast<std::uint32_t>(dynamic_size_);
  tasks.for_each_range(
      count, tasks.per_worker(count, lane_count), min_parallel_bodies,
      [&](std::uint32_t first, std::uint32_t last) {
        const DynamicColumns columns{dynamic_.data() + first,        acceleration_x_.data() + first,
                                     acceleration_y_.data() + first, linear_factor_.data() + first,
                                     angular_factor_.data() + first, integrated_x_.data() + first,
                                     integrated_y_.data() + first,   integrated_w_.data() + first};
        integrate_velocity_groups(columns, last - first, states.data(), h, limits, carry_impulses);
      });
}

float BodyIntegration::largest_acceleration() const {
  float largest = 0.0f;
  for (std::size_t i = 0; i < dynamic_size_; ++i) {
    largest = std::max(largest, std::fabs(acceleration_x_[i]) + std::fabs(acceleration_y_[i]));
  }
  return largest;
}

void BodyIntegration::integrate_positions(std::span<FxBodyState> states, float h, SpeedLimits limits,
                                          const Tasks& tasks) {
  const auto count = static_cast<std::uint32_t>(moving_size_);
  const IntegratedVelocities integrated{integrated_x_.data(), integrated_y_.data(), integrated_w_.data(),
                                        entry_of_body_.data()};
  tasks.for_each_range(count, tasks.per_worker(count, lane_count), min_parallel_bodies,
                       [&](std::uint32_t first, std::uint32_t last) {
                         integrate_position_groups(moving_.data() + first, last - first, states.data(), h,
                                                   limits, integrated);
                       });
}

}  // namespace fx2d::detail

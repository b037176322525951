// The pins' batched passes (pin_batches.h): a batch's bodies gathered into columns, its eight pins
// worked out as one loop the compiler vectorises, each lane with a pin's arithmetic
// (joint_arithmetic.h), and the velocities scattered back to the bodies that move.
#include "solver/pin_batches.h"

#include <algorithm>
#include <bit>

namespace fx2d::detail {
namespace {

// A batch's bodies: their velocities and their poses.
struct PinLanes {
  LaneVelocities velocity;
  LanePoses pose;
};

FX2D_LANE_INLINE void gather(const PinBatch& k, const FxBodyState* __restrict states, PinLanes& v) {
  gather_velocities(k, states, v.velocity);
  gather_poses(k, states, v.pose);
}

// Only the bodies that move are written: a static, kinematic or sleeping body may sit in several
// lanes of one colour.
FX2D_LANE_INLINE void scatter(const PinBatch& k, FxBodyState* __restrict states, const PinLanes& v) {
  scatter_velocities<true>(k, states, v.velocity);
}

// Lane `lane`'s anchors, turned as their bodies have since the step's start.
struct TurnedAnchors {
  FxVec2f ra, rb;
};

FX2D_LANE_INLINE TurnedAnchors turned_anchors(const PinBatch& k, const PinLanes& v, int lane) {
  return {rotate(FxRot{v.pose.aqc[lane], v.pose.aqs[lane]}, FxVec2f{k.anchor_ax[lane], k.anchor_ay[lane]}),
          rotate(FxRot{v.pose.bqc[lane], v.pose.bqs[lane]}, FxVec2f{k.anchor_bx[lane], k.anchor_by[lane]})};
}

FX2D_LANE_INLINE void apply(const PinBatch& k, PinLanes& lanes, int lane, TurnedAnchors r, FxVec2f impulse) {
  LaneVelocities& v = lanes.velocity;
  v.avx[lane] -= k.inv_mass_a[lane] * impulse.x;
  v.avy[lane] -= k.inv_mass_a[lane] * impulse.y;
  v.aw[lane] -= k.inv_inertia_a[lane] * cross(r.ra, impulse);
  v.bvx[lane] += k.inv_mass_b[lane] * impulse.x;
  v.bvy[lane] += k.inv_mass_b[lane] * impulse.y;
  v.bw[lane] += k.inv_inertia_b[lane] * cross(r.rb, impulse);
}

// apply_joint_impulse() of warm_start_revolute(), lane by lane.
FX2D_LANE_INLINE void warm_start_lane(const PinBatch& k, PinLanes& v, int lane) {
  apply(k, v, lane, turned_anchors(k, v, lane), FxVec2f{k.impulse_x[lane], k.impulse_y[lane]});
}

// What solve_revolute() works out before its clamp, for one lane: the anchors and the impulse, zero
// where K could not be inverted; and whether the accumulated impulse may reach the clamp.
template <bool UseBias>
FX2D_LANE_INLINE bool solve_lane(PinBatch& k, PinLanes& v, int lane, const JointPassParams& p,
                                 TurnedAnchors& r, FxVec2f& impulse) {
  r = turned_anchors(k, v, lane);
  const LaneVelocities& velocity = v.velocity;
  const FxVec2f va{velocity.avx[lane], velocity.avy[lane]}, vb{velocity.bvx[lane], velocity.bvy[lane]};
  const FxVec2f cdot_rigid = (vb + cross(velocity.bw[lane], r.rb)) - (va + cross(velocity.aw[lane], r.ra));
  FxVec2f cdot = cdot_rigid;
  float mass_scale = 1.0f, impulse_scale = 0.0f;
  if constexpr (UseBias) {
    const FxVec2f separation0{k.separation_x[lane], k.separation_y[lane]};
    const FxVec2f moved{v.pose.dpx[lane], v.pose.dpy[lane]};
    const FxVec2f separation = separation0 + moved + (r.rb - FxVec2f{k.anchor_bx[lane], k.anchor_by[lane]}) -
                               (r.ra - FxVec2f{k.anchor_ax[lane], k.anchor_ay[lane]});
    cdot = cdot_rigid + p.softness.bias_rate * separation;
    mass_scale = p.softness.mass_scale;
    impulse_scale = p.softness.impulse_scale;
  }
  const FxVec2f accumulated{k.impulse_x[lane], k.impulse_y[lane]};
  const PinImpulse pin =
      pin_impulse(r.ra, r.rb, k.inv_mass_a[lane], k.inv_mass_b[lane], k.inv_inertia_a[lane],
                  k.inv_inertia_b[lane], cdot, mass_scale, impulse_scale, accumulated);
  impulse = pin.solvable ? pin.impulse : FxVec2f{};
  const float limit = k.within_limit[lane];
  return pin.solvable & !(length_squared(accumulated + impulse) < limit * limit);
}

// The impulse a lane applies once the clamp holds its accumulated total (clamped_pin_impulse()).
FX2D_LANE_INLINE FxVec2f clamped(const PinBatch& k, int lane, const JointPassParams& p, TurnedAnchors r,
                                 FxVec2f impulse) {
  return clamped_pin_impulse(impulse, FxVec2f{k.impulse_x[lane], k.impulse_y[lane]},
                             max_anchor_speed(p, r.ra, r.rb), k.inv_mass_a[lane] + k.inv_mass_b[lane]);
}

// Adds a lane's impulse to its accumulated one and applies it to the lane's bodies.
FX2D_LANE_INLINE void accumulate(PinBatch& k, PinLanes& v, int lane, TurnedAnchors r, FxVec2f impulse) {
  k.impulse_x[lane] += impulse.x;
  k.impulse_y[lane] += impulse.y;
  apply(k, v, lane, r, impulse);
}

// One batch. Its lanes share no body that moves: they are solved as one loop, and the clamp, which
// binds only for joints that cannot all hold, is taken lane by lane after it.
template <bool UseBias>
FX2D_LANE_INLINE void solve_batch(PinBatch& k, FxBodyState* __restrict states, const JointPassParams& p) {
  PinLanes v;
  gather(k, states, v);
  alignas(32) float rax[lane_count], ray[lane_count], rbx[lane_count], rby[lane_count];
  alignas(32) float ix[lane_count], iy[lane_count];
  alignas(32) std::int32_t clamp[lane_count];
  // check-vectorized(2): the lane loop below, soft and rigid, must be vectorised
  for (int lane = 0; lane < lane_count; ++lane) {
    TurnedAnchors r;
    FxVec2f impulse;
    clamp[lane] = solve_lane<UseBias>(k, v, lane, p, r, impulse);
    rax[lane] = r.ra.x, ray[lane] = r.ra.y, rbx[lane] = r.rb.x, rby[lane] = r.rb.y;
    ix[lane] = impulse.x, iy[lane] = impulse.y;
  }
  const auto anchors = [&](int lane) {
    return TurnedAnchors{{rax[lane], ray[lane]}, {rbx[lane], rby[lane]}};
  };
  std::int32_t any_clamp = 0;
  for (int lane = 0; lane < lane_count; ++lane) any_clamp |= clamp[lane];
  for (int lane = 0; any_clamp != 0 && lane < lane_count; ++lane) {
    if (clamp[lane] == 0) continue;
    const FxVec2f impulse = clamped(k, lane, p, anchors(lane), FxVec2f{ix[lane], iy[lane]});
    ix[lane] = impulse.x, iy[lane] = impulse.y;
  }
  // check-vectorized(2): the lane loop below, soft and rigid, must be vectorised
  for (int lane = 0; lane < lane_count; ++lane)
    accumulate(k, v, lane, anchors(lane), FxVec2f{ix[lane], iy[lane]});
  scatter(k, states, v);
}

FX2D_LANE_INLINE void warm_start_batch(PinBatch& k, FxBodyState* __restrict states) {
  PinLanes v;
  gather(k, states, v);
  // check-vectorized(1): the lane loop below must be vectorised
  for (int lane = 0; lane < lane_count; ++lane) warm_start_lane(k, v, lane);
  scatter(k, states, v);
}

// The scalar twin of a batch: `lane_pass` on its lanes one at a time, each gathered and scattered
// alone, with the same arithmetic as the loops above.
template <class LanePass>
FX2D_LANE_INLINE void lane_by_lane(PinBatch& k, FxBodyState* __restrict states, const LanePass& lane_pass) {
  for (int lane = 0; lane < lane_count; ++lane) {
    PinLanes v;
    gather(k, states, v);
    lane_pass(v, lane);
    scatter(k, states, v);
  }
}

FX2D_LANE_KERNEL void warm_start_pins(PinBatch* batches, int count, FxBodyState* states, bool scalar) {
  for (int i = 0; i < count; ++i) {
    PinBatch& k = batches[i];
    if (scalar) {
      lane_by_lane(k, states, [&](PinLanes& v, int lane) { warm_start_lane(k, v, lane); });
    } else {
      warm_start_batch(k, states);
    }
  }
}

template <bool UseBias>
FX2D_LANE_INLINE void solve_pins(PinBatch* batches, int count, FxBodyState* states, const JointPassParams& p,
                                 bool scalar) {
  for (int i = 0; i < count; ++i) {
    PinBatch& k = batches[i];
    if (!scalar) {
      solve_batch<UseBias>(k, states, p);
      continue;
    }
    lane_by_lane(k, states, [&](PinLanes& v, int lane) {
      TurnedAnchors r;
      FxVec2f impulse;
      if (solve_lane<UseBias>(k, v, lane, p, r, impulse)) impulse = clamped(k, lane, p, r, impulse);
      accumulate(k, v, lane, r, impulse);
    });
  }
}

FX2D_LANE_KERNEL void solve_pins_soft(PinBatch* batches, int count, FxBodyState* states,
                                      const JointPassParams& p, bool scalar) {
  solve_pins<true>(batches, count, states, p, scalar);
}

FX2D_LANE_KERNEL void solve_pins_rigid(PinBatch* batches, int count, FxBodyState* states,
                                       const JointPassParams& p, bool scalar) {
  solve_pins<false>(batches, count, states, p, scalar);
}

}  // namespace

void PinBatches::pack(std::span<const JointRow> rows, std::span<const FxBodyState> states,
                      std::uint32_t padding_state, std::vector<std::uint8_t>& packed) {
  colours_.assign(states.size(), 0u);
  colour_of_.assign(rows.size(), 0);
  packed.assign(rows.size(), 0);
  lanes_.assign(rows.size(), -1);
  int pins_in_colour[max_colours] = {};
  const auto moves = [&](std::uint32_t state) { return (states[state].flags & movable_flag) != 0; };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const JointRow& pin = rows[i];
    if (pin.kind != JointKind::revolute_joint) continue;
    const std::uint32_t taken = (moves(pin.a) ? colours_[pin.a] : 0u) | (moves(pin.b) ? colours_[pin.b] : 0u);
    if (taken == ~0u) continue;
    const int colour = std::countr_one(taken);
    colours_[pin.a] |= 1u << colour;
    colours_[pin.b] |= 1u << colour;
    colour_of_[i] = static_cast<std::uint8_t>(colour);
    packed[i] = 1;
    ++pins_in_colour[colour];
  }
  // Each colour's batches follow the last colour's; within a colour, the pins in their order.
  int first_batch[max_colours + 1] = {};
  for (int c = 0; c < max_colours; ++c)
    first_batch[c + 1] = first_batch[c] + (pins_in_colour[c] + lane_count - 1) / lane_count;
  batch_count_ = first_batch[max_colours];
  if (batches_.size() < static_cast<std::size_t>(batch_count_)) batches_.resize(batch_count_);
  const std::uint32_t padding_offset = state_offset(padding_state);
  for (int b = 0; b < batch_count_; ++b) {
    PinBatch& k = batches_[b];
    k = PinBatch{};
    std::fill(std::begin(k.state_a), std::end(k.state_a), padding_offset);
    std::fill(std::begin(k.state_b), std::end(k.state_b), padding_offset);
  }
  int filled[max_colours] = {};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!packed[i]) continue;
    const int colour = colour_of_[i];
    const int slot = first_batch[colour] * lane_count + filled[colour]++;
    lanes_[i] = slot;
    PinBatch& k = batches_[slot / lane_count];
    const int lane = slot % lane_count;
    const JointRow& pin = rows[i];
    k.state_a[lane] = state_offset(pin.a);
    k.state_b[lane] = state_offset(pin.b);
    k.inv_mass_a[lane] = pin.inv_mass_a, k.inv_inertia_a[lane] = pin.inv_inertia_a;
    k.inv_mass_b[lane] = pin.inv_mass_b, k.inv_inertia_b[lane] = pin.inv_inertia_b;
    k.anchor_ax[lane] = pin.frame.anchor_a.x, k.anchor_ay[lane] = pin.frame.anchor_a.y;
    k.anchor_bx[lane] = pin.frame.anchor_b.x, k.anchor_by[lane] = pin.frame.anchor_b.y;
    k.separation_x[lane] = pin.frame.separation0.x, k.separation_y[lane] = pin.frame.separation0.y;
    k.impulse_x[lane] = pin.impulse.x, k.impulse_y[lane] = pin.impulse.y;
    k.within_limit[lane] = pin.within_limit;
  }
}

void PinBatches::warm_start(std::span<FxBodyState> states, bool scalar) {
  warm_start_pins(batches_.data(), batch_count_, states.data(), scalar);
}

void PinBatches::solve(std::span<FxBodyState> states, const JointPassParams& params, bool use_bias,
                       bool scalar) {
  if (use_bias) {
    solve_pins_soft(batches_.data(), batch_count_, states.data(), params, scalar);
  } else {
    solve_pins_rigid(batches_.data(), batch_count_, states.data(), params, scalar);
  }
}

FxVec2f PinBatches::impulse(std::size_t row) const {
  const int slot = lanes_[row];
  const PinBatch& k = batches_[slot / lane_count];
  return {k.impulse_x[slot % lane_count], k.impulse_y[slot % lane_count]};
}

}  // namespace fx2d::detail

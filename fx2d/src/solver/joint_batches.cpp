// The joints' batched passes (joint_batches.h): a batch's bodies gathered into columns, its eight
// joints worked out as one loop the compiler vectorises, each lane with its joint's arithmetic
// (joint_arithmetic.h), and the velocities scattered back to the bodies that move.
#include "solver/joint_batches.h"

#include <algorithm>
#include <bit>

namespace fx2d::detail {
namespace {

// A batch's bodies: their velocities and their poses.
struct JointLanes {
  LaneVelocities velocity;
  LanePoses pose;
};

FX2D_LANE_INLINE void gather(const JointBatchColumns& k, const FxBodyState* __restrict states,
                             JointLanes& v) {
  gather_velocities(k, states, v.velocity);
  gather_poses(k, states, v.pose);
}

// Only the bodies that move are written: a static, kinematic or sleeping body may sit in several
// lanes of one colour.
FX2D_LANE_INLINE void scatter(const JointBatchColumns& k, FxBodyState* __restrict states,
                              const JointLanes& v) {
  scatter_velocities<true>(k, states, v.velocity);
}

// Lane `lane`'s anchors, turned as their bodies have since the step's start.
struct TurnedAnchors {
  FxVec2f ra, rb;
};

FX2D_LANE_INLINE TurnedAnchors turned_anchors(const JointBatchColumns& k, const JointLanes& v, int lane) {
  return {rotate(FxRot{v.pose.aqc[lane], v.pose.aqs[lane]}, FxVec2f{k.anchor_ax[lane], k.anchor_ay[lane]}),
          rotate(FxRot{v.pose.bqc[lane], v.pose.bqs[lane]}, FxVec2f{k.anchor_bx[lane], k.anchor_by[lane]})};
}

// current_separation(), for one lane.
FX2D_LANE_INLINE FxVec2f current_separation(const JointBatchColumns& k, const JointLanes& v, int lane,
                                            TurnedAnchors r) {
  const FxVec2f separation0{k.separation_x[lane], k.separation_y[lane]};
  const FxVec2f moved{v.pose.dpx[lane], v.pose.dpy[lane]};
  return separation0 + moved + (r.rb - FxVec2f{k.anchor_bx[lane], k.anchor_by[lane]}) -
         (r.ra - FxVec2f{k.anchor_ax[lane], k.anchor_ay[lane]});
}

// anchors_relative_velocity(), for one lane.
FX2D_LANE_INLINE FxVec2f anchors_relative_velocity(const JointLanes& v, int lane, TurnedAnchors r) {
  const LaneVelocities& velocity = v.velocity;
  const FxVec2f va{velocity.avx[lane], velocity.avy[lane]}, vb{velocity.bvx[lane], velocity.bvy[lane]};
  return (vb + cross(velocity.bw[lane], r.rb)) - (va + cross(velocity.aw[lane], r.ra));
}

// apply_joint_impulse(), for one lane.
FX2D_LANE_INLINE void apply(const JointBatchColumns& k, JointLanes& lanes, int lane, TurnedAnchors r,
                            FxVec2f impulse) {
  LaneVelocities& v = lanes.velocity;
  v.avx[lane] -= k.inv_mass_a[lane] * impulse.x;
  v.avy[lane] -= k.inv_mass_a[lane] * impulse.y;
  v.aw[lane] -= k.inv_inertia_a[lane] * cross(r.ra, impulse);
  v.bvx[lane] += k.inv_mass_b[lane] * impulse.x;
  v.bvy[lane] += k.inv_mass_b[lane] * impulse.y;
  v.bw[lane] += k.inv_inertia_b[lane] * cross(r.rb, impulse);
}

// What a pass works out for each lane before the clamp: the turned anchors and the impulse (a pin's
// vector; a rod's along its axis), zero where the joint had no finite effective mass. Columns, so
// that the loops that write and read them vectorise.
struct Solved {
  alignas(32) float rax[lane_count], ray[lane_count], rbx[lane_count], rby[lane_count];
  alignas(32) float ix[lane_count], iy[lane_count];          // a pin's impulse; a rod's is ix
  alignas(32) float axis_x[lane_count], axis_y[lane_count];  // a rod's axis
};

FX2D_LANE_INLINE TurnedAnchors anchors_of(const Solved& s, int lane) {
  return {{s.rax[lane], s.ray[lane]}, {s.rbx[lane], s.rby[lane]}};
}

FX2D_LANE_INLINE void keep_anchors(Solved& s, int lane, TurnedAnchors r) {
  s.rax[lane] = r.ra.x, s.ray[lane] = r.ra.y, s.rbx[lane] = r.rb.x, s.rby[lane] = r.rb.y;
}

// --- pins: solve_revolute() and warm_start_revolute(), lane by lane -------------------------------

FX2D_LANE_INLINE void warm_start_lane(const PinBatch& k, JointLanes& v, int lane) {
  apply(k, v, lane, turned_anchors(k, v, lane), FxVec2f{k.impulse_x[lane], k.impulse_y[lane]});
}

// Whether the lane's accumulated impulse may reach the clamp.
template <bool UseBias>
FX2D_LANE_INLINE bool solve_lane(const PinBatch& k, JointLanes& v, int lane, const JointPassParams& p,
                                 Solved& s) {
  const TurnedAnchors r = turned_anchors(k, v, lane);
  FxVec2f cdot = anchors_relative_velocity(v, lane, r);
  float mass_scale = 1.0f, impulse_scale = 0.0f;
  if constexpr (UseBias) {
    cdot = cdot + p.softness.bias_rate * current_separation(k, v, lane, r);
    mass_scale = p.softness.mass_scale;
    impulse_scale = p.softness.impulse_scale;
  }
  const FxVec2f accumulated{k.impulse_x[lane], k.impulse_y[lane]};
  const PinImpulse pin =
      pin_impulse(r.ra, r.rb, k.inv_mass_a[lane], k.inv_mass_b[lane], k.inv_inertia_a[lane],
                  k.inv_inertia_b[lane], cdot, mass_scale, impulse_scale, accumulated);
  // Chosen coordinate by coordinate, as rod_axis() chooses (Clang's loop vectoriser refuses a choice
  // of whole vectors).
  const FxVec2f impulse{pin.solvable ? pin.impulse.x : 0.0f, pin.solvable ? pin.impulse.y : 0.0f};
  keep_anchors(s, lane, r);
  s.ix[lane] = impulse.x, s.iy[lane] = impulse.y;
  const float limit = k.within_limit[lane];
  return pin.solvable & !(length_squared(accumulated + impulse) < limit * limit);
}

FX2D_LANE_INLINE void clamp_lane(const PinBatch& k, int lane, const JointPassParams& p, Solved& s) {
  const TurnedAnchors r = anchors_of(s, lane);
  const FxVec2f impulse =
      clamped_pin_impulse(FxVec2f{s.ix[lane], s.iy[lane]}, FxVec2f{k.impulse_x[lane], k.impulse_y[lane]},
                          max_anchor_speed(p, r.ra, r.rb), k.inv_mass_a[lane] + k.inv_mass_b[lane]);
  s.ix[lane] = impulse.x, s.iy[lane] = impulse.y;
}

// Adds the lane's impulse to its accumulated one and applies it to the lane's bodies.
FX2D_LANE_INLINE void accumulate(PinBatch& k, JointLanes& v, int lane, const Solved& s) {
  k.impulse_x[lane] += s.ix[lane];
  k.impulse_y[lane] += s.iy[lane];
  apply(k, v, lane, anchors_of(s, lane), FxVec2f{s.ix[lane], s.iy[lane]});
}

// --- rods: solve_distance() and warm_start_distance(), lane by lane --------------------------------

FX2D_LANE_INLINE void warm_start_lane(const RodBatch& k, JointLanes& v, int lane) {
  const TurnedAnchors r = turned_anchors(k, v, lane);
  const FxVec2f axis = rod_axis(current_separation(k, v, lane, r)).axis;
  apply(k, v, lane, r, k.impulse[lane] * axis);
}

template <bool UseBias>
FX2D_LANE_INLINE bool solve_lane(const RodBatch& k, JointLanes& v, int lane, const JointPassParams& p,
                                 Solved& s) {
  const TurnedAnchors r = turned_anchors(k, v, lane);
  const RodAxis rod = rod_axis(current_separation(k, v, lane, r));
  float bias = 0.0f, mass_scale = 1.0f, impulse_scale = 0.0f;
  if constexpr (UseBias) {
    bias = p.softness.bias_rate * (rod.length - k.length[lane]);
    mass_scale = p.softness.mass_scale;
    impulse_scale = p.softness.impulse_scale;
  }
  const float accumulated = k.impulse[lane];
  const float mass = rod_mass(r.ra, r.rb, rod.axis, k.inv_mass_a[lane], k.inv_mass_b[lane],
                              k.inv_inertia_a[lane], k.inv_inertia_b[lane]);
  const bool solvable = rod_solvable(mass);
  // Worked out in every lane and then chosen, so that the loop needs no branch.
  const float solved = rod_impulse(mass, dot(anchors_relative_velocity(v, lane, r), rod.axis), bias,
                                   mass_scale, impulse_scale, accumulated);
  const float impulse = solvable ? solved : 0.0f;
  keep_anchors(s, lane, r);
  s.ix[lane] = impulse;
  s.axis_x[lane] = rod.axis.x, s.axis_y[lane] = rod.axis.y;
  return solvable & !(std::fabs(accumulated + impulse) < k.within_limit[lane]);
}

FX2D_LANE_INLINE void clamp_lane(const RodBatch& k, int lane, const JointPassParams& p, Solved& s) {
  const TurnedAnchors r = anchors_of(s, lane);
  s.ix[lane] = clamped_rod_impulse(s.ix[lane], k.impulse[lane], max_anchor_speed(p, r.ra, r.rb),
                                   k.inv_mass_a[lane] + k.inv_mass_b[lane]);
}

FX2D_LANE_INLINE void accumulate(RodBatch& k, JointLanes& v, int lane, const Solved& s) {
  k.impulse[lane] += s.ix[lane];
  apply(k, v, lane, anchors_of(s, lane), s.ix[lane] * FxVec2f{s.axis_x[lane], s.axis_y[lane]});
}

// --- the passes, for either kind --------------------------------------------------------------------

// One batch. Its lanes share no body that moves: they are solved as one loop, and the clamp, which
// binds only for joints that cannot all hold, is taken lane by lane after it.
template <bool UseBias, class Batch>
FX2D_LANE_INLINE void solve_batch(Batch& k, FxBodyState* __restrict states, const JointPassParams& p) {
  JointLanes v;
  gather(k, states, v);
  Solved s;
  alignas(32) std::int32_t clamp[lane_count];
  // check-vectorized(4): the lane loop below, pins and rods, soft and rigid, must be vectorised
  for (int lane = 0; lane < lane_count; ++lane) clamp[lane] = solve_lane<UseBias>(k, v, lane, p, s);
  std::int32_t any_clamp = 0;
  for (int lane = 0; lane < lane_count; ++lane) any_clamp |= clamp[lane];
  for (int lane = 0; any_clamp != 0 && lane < lane_count; ++lane) {
    if (clamp[lane] != 0) clamp_lane(k, lane, p, s);
  }
  // check-vectorized(4): the lane loop below, pins and rods, soft and rigid, must be vectorised
  for (int lane = 0; lane < lane_count; ++lane) accumulate(k, v, lane, s);
  scatter(k, states, v);
}

template <class Batch>
FX2D_LANE_INLINE void warm_start_batch(Batch& k, FxBodyState* __restrict states) {
  JointLanes v;
  gather(k, states, v);
  // check-vectorized(2): the lane loop below, pins and rods, must be vectorised
  for (int lane = 0; lane < lane_count; ++lane) warm_start_lane(k, v, lane);
  scatter(k, states, v);
}

// The scalar twin of a batch: `lane_pass` on its lanes one at a time, each gathered and scattered
// alone, with the same arithmetic as the loops above.
template <class Batch, class LanePass>
FX2D_LANE_INLINE void lane_by_lane(Batch& k, FxBodyState* __restrict states, const LanePass& lane_pass) {
  for (int lane = 0; lane < lane_count; ++lane) {
    JointLanes v;
    gather(k, states, v);
    lane_pass(v, lane);
    scatter(k, states, v);
  }
}

template <class Batch>
FX2D_LANE_INLINE void warm_start_batches(Batch* batches, int count, FxBodyState* states, bool scalar) {
  for (int i = 0; i < count; ++i) {
    Batch& k = batches[i];
    if (scalar) {
      lane_by_lane(k, states, [&](JointLanes& v, int lane) { warm_start_lane(k, v, lane); });
    } else {
      warm_start_batch(k, states);
    }
  }
}

template <bool UseBias, class Batch>
FX2D_LANE_INLINE void solve_batches(Batch* batches, int count, FxBodyState* states, const JointPassParams& p,
                                    bool scalar) {
  for (int i = 0; i < count; ++i) {
    Batch& k = batches[i];
    if (!scalar) {
      solve_batch<UseBias>(k, states, p);
      continue;
    }
    lane_by_lane(k, states, [&](JointLanes& v, int lane) {
      Solved s;
      if (solve_lane<UseBias>(k, v, lane, p, s)) clamp_lane(k, lane, p, s);
      accumulate(k, v, lane, s);
    });
  }
}

// The kernels, each compiled once per instruction set FX2D_LANE_KERNEL names.
FX2D_LANE_KERNEL void warm_start_kernel(PinBatch* batches, int count, FxBodyState* states, bool scalar) {
  warm_start_batches(batches, count, states, scalar);
}

FX2D_LANE_KERNEL void warm_start_kernel(RodBatch* batches, int count, FxBodyState* states, bool scalar) {
  warm_start_batches(batches, count, states, scalar);
}

// One pass, soft or rigid, over every batch of a kind.
template <class Batch>
FX2D_LANE_INLINE void solve_pass(Batch* batches, int count, FxBodyState* states, const JointPassParams& p,
                                 bool use_bias, bool scalar) {
  if (use_bias) {
    solve_batches<true>(batches, count, states, p, scalar);
  } else {
    solve_batches<false>(batches, count, states, p, scalar);
  }
}

FX2D_LANE_KERNEL void solve_kernel(PinBatch* batches, int count, FxBodyState* states,
                                   const JointPassParams& p, bool use_bias, bool scalar) {
  solve_pass(batches, count, states, p, use_bias, scalar);
}

FX2D_LANE_KERNEL void solve_kernel(RodBatch* batches, int count, FxBodyState* states,
                                   const JointPassParams& p, bool use_bias, bool scalar) {
  solve_pass(batches, count, states, p, use_bias, scalar);
}

// The kind's own columns of a packed lane.
void pack_lane(PinBatch& k, int lane, const JointRow& row) {
  k.impulse_x[lane] = row.impulse.x, k.impulse_y[lane] = row.impulse.y;
}

void pack_lane(RodBatch& k, int lane, const JointRow& row) {
  k.impulse[lane] = row.impulse.x;
  k.length[lane] = row.length;
}

FxVec2f impulse_of(const PinBatch& k, int lane) { return {k.impulse_x[lane], k.impulse_y[lane]}; }
FxVec2f impulse_of(const RodBatch& k, int lane) { return {k.impulse[lane], 0.0f}; }

}  // namespace

template <class Batch>
void JointBatches<Batch>::pack(std::span<const JointRow> rows, std::span<const FxBodyState> states,
                               std::uint32_t padding_state, std::vector<std::uint8_t>& packed) {
  // A scene without joints of this kind pays for this look alone.
  batch_count_ = 0;
  if (std::ranges::none_of(rows, [](const JointRow& row) { return row.kind == Batch::kind; })) return;
  colours_.assign(states.size(), 0u);
  colour_of_.assign(rows.size(), 0);
  lanes_.assign(rows.size(), -1);
  int joints_in_colour[max_colours] = {};
  const auto moves = [&](std::uint32_t state) { return (states[state].flags & movable_flag) != 0; };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const JointRow& joint = rows[i];
    if (joint.kind != Batch::kind) continue;
    const std::uint32_t taken =
        (moves(joint.a) ? colours_[joint.a] : 0u) | (moves(joint.b) ? colours_[joint.b] : 0u);
    if (taken == ~0u) continue;
    const int colour = std::countr_one(taken);
    colours_[joint.a] |= 1u << colour;
    colours_[joint.b] |= 1u << colour;
    colour_of_[i] = static_cast<std::uint8_t>(colour);
    packed[i] = 1;
    ++joints_in_colour[colour];
  }
  // Each colour's batches follow the last colour's; within a colour, the joints in their order.
  int first_batch[max_colours + 1] = {};
  for (int c = 0; c < max_colours; ++c)
    first_batch[c + 1] = first_batch[c] + (joints_in_colour[c] + lane_count - 1) / lane_count;
  batch_count_ = first_batch[max_colours];
  if (batches_.size() < static_cast<std::size_t>(batch_count_)) batches_.resize(batch_count_);
  const std::uint32_t padding_offset = state_offset(padding_state);
  for (int b = 0; b < batch_count_; ++b) {
    Batch& k = batches_[b];
    k = Batch{};
    std::fill(std::begin(k.state_a), std::end(k.state_a), padding_offset);
    std::fill(std::begin(k.state_b), std::end(k.state_b), padding_offset);
  }
  int filled[max_colours] = {};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].kind != Batch::kind || !packed[i]) continue;
    const int colour = colour_of_[i];
    const int slot = first_batch[colour] * lane_count + filled[colour]++;
    lanes_[i] = slot;
    Batch& k = batches_[slot / lane_count];
    const int lane = slot % lane_count;
    const JointRow& joint = rows[i];
    k.state_a[lane] = state_offset(joint.a);
    k.state_b[lane] = state_offset(joint.b);
    k.inv_mass_a[lane] = joint.inv_mass_a, k.inv_inertia_a[lane] = joint.inv_inertia_a;
    k.inv_mass_b[lane] = joint.inv_mass_b, k.inv_inertia_b[lane] = joint.inv_inertia_b;
    k.anchor_ax[lane] = joint.frame.anchor_a.x, k.anchor_ay[lane] = joint.frame.anchor_a.y;
    k.anchor_bx[lane] = joint.frame.anchor_b.x, k.anchor_by[lane] = joint.frame.anchor_b.y;
    k.separation_x[lane] = joint.frame.separation0.x, k.separation_y[lane] = joint.frame.separation0.y;
    k.within_limit[lane] = joint.within_limit;
    pack_lane(k, lane, joint);
  }
}

// Without batches (a scene with no joint of the kind), not even the kernel is called: it is called
// through the loader's choice of clone, several times a substep.
template <class Batch>
void JointBatches<Batch>::warm_start(std::span<FxBodyState> states, bool scalar) {
  if (batch_count_ > 0) warm_start_kernel(batches_.data(), batch_count_, states.data(), scalar);
}

template <class Batch>
void JointBatches<Batch>::solve(std::span<FxBodyState> states, const JointPassParams& params, bool use_bias,
                                bool scalar) {
  if (batch_count_ > 0) solve_kernel(batches_.data(), batch_count_, states.data(), params, use_bias, scalar);
}

template <class Batch>
FxVec2f JointBatches<Batch>::impulse(std::size_t row) const {
  const int slot = lanes_[row];
  return impulse_of(batches_[slot / lane_count], slot % lane_count);
}

template class JointBatches<PinBatch>;
template class JointBatches<RodBatch>;

}  // namespace fx2d::detail

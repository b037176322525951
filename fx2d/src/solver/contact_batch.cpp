// The batched passes over packed contacts (contact_batch.h): the arithmetic of one lane
// (solve_lane, warm start, push-out, separation update) and the sweeps that run it over a batch's
// lanes as vectorisable loops or lane by lane (the scalar twin, and the overflow). Packing the
// constraints in and out of their columns is contact_packing.cpp.
#include "solver/contact_batch.h"

#include <algorithm>
#include <bit>

namespace fx2d::detail {
namespace {

// By value, not std::max's references, so a lane loop if-converts to selects instead of branching
// between two loads. Same semantics as std::max/std::min (the first argument wins ties).
FX2D_LANE_INLINE float max_of(float a, float b) { return a < b ? b : a; }
FX2D_LANE_INLINE float min_of(float a, float b) { return b < a ? b : a; }

// The relative velocity of a point's two anchors along a direction (dx, dy), given the anchors'
// lever arms about it.
FX2D_LANE_INLINE float relative_speed(const LaneBody& a, const LaneBody& b, float dx, float dy, float arm_a,
                                      float arm_b) {
  return ((b.vx - a.vx) * dx + (b.vy - a.vy) * dy) + (b.w * arm_b - a.w * arm_a);
}

// An impulse `impulse` along a direction: A loses and B gains, per unit, the velocity (ax, ay),
// (bx, by) and the spin sa, sb.
FX2D_LANE_INLINE void apply_impulse(LaneBody& a, LaneBody& b, float impulse, float ax, float ay, float sa,
                                    float bx, float by, float sb) {
  a.vx -= impulse * ax;
  a.vy -= impulse * ay;
  a.w -= impulse * sa;
  b.vx += impulse * bx;
  b.vy += impulse * by;
  b.w += impulse * sb;
}

// What the rows of one lane's points share: the normal, and the velocity a unit impulse along it
// takes from A and gives to B. The tangent is right_perp(normal) = (ny, -nx), so its velocity
// changes are the normal's turned a quarter.
struct PointRows {
  float nx, ny;
  float mass_ax, mass_ay, mass_bx, mass_by;
};

FX2D_LANE_INLINE PointRows rows_of(const ContactBatch& __restrict k, int lane) {
  return {k.normal_x[lane], k.normal_y[lane], k.mass_normal_ax[lane], k.mass_normal_ay[lane], k.mass_normal_bx[lane],
          k.mass_normal_by[lane]};
}

FX2D_LANE_INLINE void apply_normal(const ContactBatch& __restrict k, const PointRows& r, int i, int lane,
                                   LaneBody& a, LaneBody& b, float impulse) {
  apply_impulse(a, b, impulse, r.mass_ax, r.mass_ay, k.point[i].spin_normal_a[lane], r.mass_bx, r.mass_by,
                k.point[i].spin_normal_b[lane]);
}

FX2D_LANE_INLINE void apply_tangent(const ContactBatch& __restrict k, const PointRows& r, int i, int lane,
                                    LaneBody& a, LaneBody& b, float impulse) {
  apply_impulse(a, b, impulse, r.mass_ay, -r.mass_ax, k.point[i].spin_tangent_a[lane], r.mass_by, -r.mass_bx,
                k.point[i].spin_tangent_b[lane]);
}

template <int Points>
FX2D_LANE_INLINE void warm_start_lane(ContactBatch& __restrict k, int lane, LaneBody& a, LaneBody& b,
                                      const ContactSolveParams&) {
  const PointRows r = rows_of(k, lane);
  for (int i = 0; i < Points; ++i) {
    apply_normal(k, r, i, lane, a, b, k.point[i].normal_impulse[lane]);
    apply_tangent(k, r, i, lane, a, b, k.point[i].tangent_impulse[lane]);
  }
}

// One soft sequential-impulse pass over one contact: normal rows first (speculative points stop
// the approach at the surface; overlaps are pushed apart softly, at most max_push_speed), then
// friction bounded by each point's normal impulse. Branch-free so that lanes vectorise.
//
// Every row's relative speed is taken once, at the velocities the contact starts from; each
// row's impulse then reaches the later rows through their coupling (the change of one row's
// speed per unit impulse on another, worked out by pack()), and the bodies once at the end. That
// is the same Gauss-Seidel sweep, but between two rows lie one multiply and one add, not a
// velocity update and a dot product. The couplings are symmetric, so either point may go first
// (PointOrder).
template <int Points, bool UseBias, PointOrder Order = PointOrder::first_to_last>
FX2D_LANE_INLINE void solve_lane(ContactBatch& __restrict k, int lane, LaneBody& a, LaneBody& b,
                                 const ContactSolveParams& p) {
  // Row n of the sweep is point i = leading ^ n: point 0 then 1, or 1 then 0.
  constexpr int leading = Points == 2 && Order == PointOrder::last_to_first ? 1 : 0;
  const PointRows r = rows_of(k, lane);
  float normal_speed[Points], tangent_speed[Points];
  for (int i = 0; i < Points; ++i) {
    normal_speed[i] =
        relative_speed(a, b, r.nx, r.ny, k.point[i].arm_normal_a[lane], k.point[i].arm_normal_b[lane]);
    tangent_speed[i] =
        relative_speed(a, b, r.ny, -r.nx, k.point[i].arm_tangent_a[lane], k.point[i].arm_tangent_b[lane]);
  }
  // Read unconditionally, so the selects below need no conditional loads.
  const float bias_rate = p.softness.bias_rate, soft_mass_scale = p.softness.mass_scale;
  const float soft_impulse_scale = p.softness.impulse_scale, max_spring = p.max_spring_speed, inv_h = p.inv_substep_dt;
  float normal_applied[Points], tangent_applied[Points];
  for (int n = 0; n < Points; ++n) {
    const int i = leading ^ n;
    const float separation = k.point[i].separation[lane];
    const bool speculative = separation > 0.0f;
    const bool soft = UseBias && !speculative;
    // The soft spring pushes only slowly (max_spring_speed): pushed through the velocities, pushes
    // add up down a column, and what the relaxation passes fail to take out again launches it.
    // What it leaves of a deeper overlap is push()'s, through the positions.
    const float spring = max_of(bias_rate * separation, -max_spring);
    const float bias = speculative ? separation * inv_h : (soft ? spring : 0.0f);
    const float mass_scale = soft ? soft_mass_scale : 1.0f;
    const float impulse_scale = soft ? soft_impulse_scale : 0.0f;

    const float old_impulse = k.point[i].normal_impulse[lane];
    const float speed_to_impulse = -k.point[i].normal_mass[lane] * mass_scale;
    const float offset = speed_to_impulse * bias - impulse_scale * old_impulse;
    float vn = normal_speed[i];
    if (n == 1) vn += normal_applied[leading] * k.normal1_from_normal0[lane];
    // The clamp of the accumulated impulse at zero, put on the increment.
    const float applied = max_of(vn * speed_to_impulse + offset, -old_impulse);
    k.point[i].normal_impulse[lane] = old_impulse + applied;
    k.point[i].max_normal_impulse[lane] = max_of(k.point[i].max_normal_impulse[lane], applied);
    normal_applied[i] = applied;
  }
  const float friction = k.friction[lane];
  for (int n = 0; n < Points; ++n) {
    const int i = leading ^ n;
    float vt = tangent_speed[i];
    for (int j = 0; j < Points; ++j) vt += normal_applied[j] * k.point[i].tangent_from_normal[j][lane];
    if (n == 1) vt += tangent_applied[leading] * k.tangent1_from_tangent0[lane];
    const float limit = friction * k.point[i].normal_impulse[lane];
    const float old_impulse = k.point[i].tangent_impulse[lane];
    // The friction cone |accumulated| <= limit, put on the increment likewise.
    const float applied =
        min_of(max_of(-k.point[i].tangent_mass[lane] * vt, -limit - old_impulse), limit - old_impulse);
    k.point[i].tangent_impulse[lane] = old_impulse + applied;
    tangent_applied[i] = applied;
  }
  for (int i = 0; i < Points; ++i) {
    apply_normal(k, r, i, lane, a, b, normal_applied[i]);
    apply_tangent(k, r, i, lane, a, b, tangent_applied[i]);
  }
}

// One pass that pushes overlaps apart, after the soft passes and before the positions move: each
// point deeper than the slop gets the impulse that separates it at the soft contact's rate, at
// most max_push_speed. The impulse is recorded, kept out of the accumulated impulse, and taken back
// once the positions have moved (take_back_push_lane), so the push moves bodies but launches
// none. Pushed through velocities and taken out by relaxation passes instead, pushes add up down
// a column (the top of a column of n overlaps moves at n times the push), and a Gauss-Seidel pass
// removes them one contact at a time: n passes before the column is back at rest.
template <int Points>
FX2D_LANE_INLINE void push_lane(ContactBatch& __restrict k, int lane, LaneBody& a, LaneBody& b,
                                const ContactSolveParams& p) {
  const PointRows r = rows_of(k, lane);
  float normal_speed[Points];
  for (int i = 0; i < Points; ++i) {
    normal_speed[i] =
        relative_speed(a, b, r.nx, r.ny, k.point[i].arm_normal_a[lane], k.point[i].arm_normal_b[lane]);
  }
  const float bias_rate = p.softness.bias_rate, max_push = p.max_push_speed, slop = p.linear_slop;
  float pushed[Points];
  for (int i = 0; i < Points; ++i) {
    const float separation = k.point[i].separation[lane];
    const float push_speed = min_of(-bias_rate * separation, max_push);
    float vn = normal_speed[i];
    if (i == 1) vn += pushed[0] * k.normal1_from_normal0[lane];
    const float wanted = max_of(k.point[i].normal_mass[lane] * (push_speed - vn), 0.0f);
    // Within the slop the soft passes' spring has pushed already (solve_lane).
    pushed[i] = separation < -slop ? wanted : 0.0f;
    k.point[i].push_impulse[lane] = pushed[i];
  }
  for (int i = 0; i < Points; ++i) apply_normal(k, r, i, lane, a, b, pushed[i]);
}

// Takes back what push_lane applied: exact in one sweep whatever the order, since each contact
// subtracts its own recorded impulse.
template <int Points>
FX2D_LANE_INLINE void take_back_push_lane(ContactBatch& __restrict k, int lane, LaneBody& a, LaneBody& b,
                                          const ContactSolveParams&) {
  const PointRows r = rows_of(k, lane);
  for (int i = 0; i < Points; ++i) {
    apply_normal(k, r, i, lane, a, b, -k.point[i].push_impulse[lane]);
  }
}

FX2D_LANE_INLINE LaneBody load(const FxBodyState& s) {
  return {s.linear_velocity.x, s.linear_velocity.y, s.angular_velocity};
}

FX2D_LANE_INLINE void store(FxBodyState& s, const LaneBody& body) {
  s.linear_velocity = {body.vx, body.vy};
  s.angular_velocity = body.w;
}

// Lanes may share bodies: gather, solve and scatter one lane at a time, in lane order.
template <LaneFn LaneSolve>
FX2D_LANE_INLINE void run_serial(ContactBatch& k, FxBodyState* states, const ContactSolveParams& p) {
  for (int lane = 0; lane < lane_count; ++lane) {
    FxBodyState& state_a = states[state_index(k.state_a[lane])];
    FxBodyState& state_b = states[state_index(k.state_b[lane])];
    LaneBody a = load(state_a);
    LaneBody b = load(state_b);
    LaneSolve(k, lane, a, b, p);
    store(state_a, a);
    store(state_b, b);
  }
}

// Lane `lane` of one batch, on velocities gathered into `v`.
template <LaneFn LaneSolve>
FX2D_LANE_INLINE void solve_lane_of(ContactBatch& __restrict k, LaneVelocities& __restrict v, int lane,
                                    const ContactSolveParams& p) {
  LaneBody a{v.avx[lane], v.avy[lane], v.aw[lane]};
  LaneBody b{v.bvx[lane], v.bvy[lane], v.bw[lane]};
  LaneSolve(k, lane, a, b, p);
  v.avx[lane] = a.vx, v.avy[lane] = a.vy, v.aw[lane] = a.w;
  v.bvx[lane] = b.vx, v.bvy[lane] = b.vy, v.bw[lane] = b.w;
}

// Invariant: no two lanes share a movable body, here across all `Count` batches (consecutive
// batches of one colour). Gather every lane, solve them as one vectorisable loop over local
// columns, scatter every lane; the result is the same as solving the batches one after the other.
// One batch is a chain of dependent arithmetic that leaves most of the core idle; two in one loop
// give it two chains to interleave (the sweep alone, timed interleaved with the one-batch loop:
// 0.80x the time with one-point batches, 0.885x with two-point ones, on a core of its own;
// 1.00-1.03x when the core's other hardware thread is busy and leaves no idle capacity to fill).
template <LaneFn LaneSolve, int Count, bool Shared>
FX2D_LANE_INLINE void run_batched(ContactBatch* __restrict k, FxBodyState* __restrict states,
                                  const ContactSolveParams& p) {
  static_assert(Count == 1 || Count == 2);
  // Named variables, not an array indexed by batch: GCC keeps those in registers.
  LaneVelocities first, second;
  gather_velocities(k[0], states, first);
  if constexpr (Count == 2) gather_velocities(k[1], states, second);
  // check-vectorized(48): the lane loop below, in all forty-eight instantiations (warm start,
  // solve with and without softness, a two-point solve in either point order, the push and its
  // take-back; one and two points, one and two batches; on one thread or shared), must be vectorised
  for (int lane = 0; lane < lane_count; ++lane) {
    solve_lane_of<LaneSolve>(k[0], first, lane, p);
    if constexpr (Count == 2) solve_lane_of<LaneSolve>(k[1], second, lane, p);
  }
  scatter_velocities<Shared>(k[0], states, first);
  if constexpr (Count == 2) scatter_velocities<Shared>(k[1], states, second);
}

// Every lane's normal turned as its NormalFrame says: with A, with B, or not at all. The last
// multiplies by exactly one and zero, so a world-frame normal keeps its bits. A circle's anchor
// turns as the normal does (ContactBatch::round_sides), so its rotation becomes the normal's.
FX2D_LANE_INLINE void turn_normals(const ContactBatch& __restrict k, LanePoses& __restrict q) {
  constexpr auto with_a = static_cast<std::int32_t>(NormalFrame::body_a);
  constexpr auto with_b = static_cast<std::int32_t>(NormalFrame::body_b);
  // check-vectorized(2): the lane loop below, once per point count (not unrolled first, like the one
  // below; every load unconditional, so that the choices are blends)
#pragma GCC unroll 1
  for (int lane = 0; lane < lane_count; ++lane) {
    const std::int32_t frame = k.normal_frame[lane];
    const float ac = q.aqc[lane], as = q.aqs[lane], bc = q.bqc[lane], bs = q.bqs[lane];
    const float c = frame == with_a ? ac : (frame == with_b ? bc : 1.0f);
    const float s = frame == with_a ? as : (frame == with_b ? bs : 0.0f);
    q.nx[lane] = c * k.normal_x[lane] - s * k.normal_y[lane];
    q.ny[lane] = s * k.normal_x[lane] + c * k.normal_y[lane];
    const std::int32_t round = k.round_sides[lane];
    q.aqc[lane] = (round & round_side_a) != 0 ? c : ac;
    q.aqs[lane] = (round & round_side_a) != 0 ? s : as;
    q.bqc[lane] = (round & round_side_b) != 0 ? c : bc;
    q.bqs[lane] = (round & round_side_b) != 0 ? s : bs;
  }
}

// Point `Point` of every lane: its separation at the current poses, the separation at the step's
// start plus how far the anchors moved apart since then along the turned normal. Whether any
// lane's point lies deeper than `slop`.
template <int Point>
FX2D_LANE_INLINE bool update_point_separations(ContactBatch& __restrict k, const LanePoses& __restrict q,
                                               float slop) {
  int deep = 0;
  // check-vectorized(2): the lane loop below, for the first and the second point, must be vectorised
  // (not unrolled first: a fully unrolled loop is left to the weaker straight-line vectoriser)
#pragma GCC unroll 1
  for (int lane = 0; lane < lane_count; ++lane) {
    const float rax = k.point[Point].anchor_ax[lane], ray = k.point[Point].anchor_ay[lane];
    const float rbx = k.point[Point].anchor_bx[lane], rby = k.point[Point].anchor_by[lane];
    const float gap_x = q.dpx[lane] + ((q.bqc[lane] * rbx - q.bqs[lane] * rby) - (q.aqc[lane] * rax - q.aqs[lane] * ray));
    const float gap_y = q.dpy[lane] + ((q.bqs[lane] * rbx + q.bqc[lane] * rby) - (q.aqs[lane] * rax + q.aqc[lane] * ray));
    // The separation at the step's start plus the anchors' motion since along the turned normal:
    // start . n + adjusted + (gap - start) . n', written as gap . n' + adjusted + start . (n - n'),
    // so that a normal that did not turn (n' = n: two circles, a static body's face) gives the bits
    // of the fixed normal.
    const float start_x = rbx - rax, start_y = rby - ray;
    const float turn_x = k.normal_x[lane] - q.nx[lane], turn_y = k.normal_y[lane] - q.ny[lane];
    const float separation = gap_x * q.nx[lane] + gap_y * q.ny[lane] + k.point[Point].adjusted_separation[lane] +
                             (start_x * turn_x + start_y * turn_y);
    k.point[Point].separation[lane] = separation;
    deep |= separation < -slop;
  }
  return deep != 0;
}

// Every point of one batch. It reads poses and writes only the batch, so lanes never conflict,
// even in an overflow batch.
template <int Points>
FX2D_LANE_INLINE bool update_batch_separations(ContactBatch& __restrict k,
                                               const FxBodyState* __restrict states, float slop) {
  LanePoses q;
  gather_poses(k, states, q);
  turn_normals(k, q);
  bool deep = update_point_separations<0>(k, q, slop);
  if constexpr (Points == 2) deep |= update_point_separations<1>(k, q, slop);
  return deep;
}

// The batches of one run, in order; two at a time where lanes are independent, with one left over
// for an odd count. A serial run (the overflow) is never swept `Shared`.
template <LaneFn LaneSolve, bool Shared>
FX2D_LANE_INLINE void sweep_run(ContactBatch* batches, int count, FxBodyState* states,
                                const ContactSolveParams& params, bool serial) {
  int i = 0;
  if (serial) {
    for (; i < count; ++i) run_serial<LaneSolve>(batches[i], states, params);
    return;
  }
  for (; i + 2 <= count; i += 2) run_batched<LaneSolve, 2, Shared>(batches + i, states, params);
  if (i < count) run_batched<LaneSolve, 1, Shared>(batches + i, states, params);
}

// The batches of one run that `marked` flags, in order; two at a time where two marked batches
// follow each other. Lanes of one colour are independent, so leaving a batch out changes no other.
template <LaneFn LaneSolve, bool Shared>
FX2D_LANE_INLINE void sweep_marked_run(ContactBatch* batches, const std::uint8_t* marked, int count,
                                       FxBodyState* states, const ContactSolveParams& params, bool serial) {
  for (int i = 0; i < count;) {
    if (!marked[i]) {
      ++i;
    } else if (serial) {
      run_serial<LaneSolve>(batches[i++], states, params);
    } else if (i + 1 < count && marked[i + 1]) {
      run_batched<LaneSolve, 2, Shared>(batches + i, states, params);
      i += 2;
    } else {
      run_batched<LaneSolve, 1, Shared>(batches + i++, states, params);
    }
  }
}

// Every batch of every run, or with `marked` only the batches it flags.
template <LaneFn OnePoint, LaneFn TwoPoints, bool Shared>
FX2D_LANE_INLINE void sweep(std::span<const BatchRun> runs, ContactBatch* batches, FxBodyState* states,
                            const ContactSolveParams& caller_params, bool scalar,
                            const std::uint8_t* marked = nullptr) {
  // A local copy, which no store to a batch or a body can change, so it is not re-read per batch.
  const ContactSolveParams params = caller_params;
  for (const BatchRun& run : runs) {
    const bool serial = scalar || run.serial;
    ContactBatch* first = batches + run.first;
    if (marked != nullptr) {
      const std::uint8_t* run_marks = marked + run.first;
      if (run.point_count == 1) {
        sweep_marked_run<OnePoint, Shared>(first, run_marks, run.count, states, params, serial);
      } else {
        sweep_marked_run<TwoPoints, Shared>(first, run_marks, run.count, states, params, serial);
      }
    } else if (run.point_count == 1) {
      sweep_run<OnePoint, Shared>(first, run.count, states, params, serial);
    } else {
      sweep_run<TwoPoints, Shared>(first, run.count, states, params, serial);
    }
  }
}

// sweep(), writing back every body (on one thread) or, when `shared`, the movable ones alone.
template <LaneFn OnePoint, LaneFn TwoPoints>
FX2D_LANE_INLINE void sweep_writing(bool shared, std::span<const BatchRun> runs, ContactBatch* batches,
                                    FxBodyState* states, const ContactSolveParams& params, bool scalar,
                                    const std::uint8_t* marked = nullptr) {
  if (shared) {
    sweep<OnePoint, TwoPoints, true>(runs, batches, states, params, scalar, marked);
  } else {
    sweep<OnePoint, TwoPoints, false>(runs, batches, states, params, scalar, marked);
  }
}

// The sweeps the step runs, each compiled once per instruction set FX2D_LANE_KERNEL names.
FX2D_LANE_KERNEL void warm_start_runs(std::span<const BatchRun> runs, ContactBatch* batches, FxBodyState* states,
                                      bool scalar, bool shared) {
  sweep_writing<&warm_start_lane<1>, &warm_start_lane<2>>(shared, runs, batches, states, {}, scalar);
}

FX2D_LANE_KERNEL void push_runs(std::span<const BatchRun> runs, ContactBatch* batches, FxBodyState* states,
                                const ContactSolveParams& params, bool scalar, bool shared, const std::uint8_t* deep) {
  sweep_writing<&push_lane<1>, &push_lane<2>>(shared, runs, batches, states, params, scalar, deep);
}

FX2D_LANE_KERNEL void take_back_push_runs(std::span<const BatchRun> runs, ContactBatch* batches, FxBodyState* states,
                                          bool scalar, bool shared, const std::uint8_t* deep) {
  sweep_writing<&take_back_push_lane<1>, &take_back_push_lane<2>>(shared, runs, batches, states, {}, scalar, deep);
}

// The lanes of one batch with a point the position projection (ContactSolver::project_positions)
// would push at these poses, a bit per lane: the point's separation as that pass measures it,
// against the step's normal with each anchor turned as its body has (a circle's not at all), in
// the same operations, so to the bit; pushed when not at least -slop (a superset of the points
// that pass corrects, which also leaves alone a product that underflows to zero).
template <int Points>
FX2D_LANE_INLINE unsigned projection_overlap_lanes(const ContactBatch& __restrict k,
                                                   const FxBodyState* __restrict states, float slop) {
  LanePoses q;
  gather_poses(k, states, q);
  alignas(32) std::int32_t pushed[lane_count];
  // check-vectorized(2): the lane loop below, once per point count, must be vectorised
#pragma GCC unroll 1
  for (int lane = 0; lane < lane_count; ++lane) {
    const std::int32_t round = k.round_sides[lane];
    const bool still_a = (round & round_side_a) != 0, still_b = (round & round_side_b) != 0;
    const float ac = still_a ? 1.0f : q.aqc[lane], as = still_a ? 0.0f : q.aqs[lane];
    const float bc = still_b ? 1.0f : q.bqc[lane], bs = still_b ? 0.0f : q.bqs[lane];
    std::int32_t any = 0;
    for (int i = 0; i < Points; ++i) {
      const PointColumns& point = k.point[i];
      const float ax = point.anchor_ax[lane], ay = point.anchor_ay[lane];
      const float bx = point.anchor_bx[lane], by = point.anchor_by[lane];
      const float gap_x = q.dpx[lane] + ((bc * bx - bs * by) - (ac * ax - as * ay));
      const float gap_y = q.dpy[lane] + ((bs * bx + bc * by) - (as * ax + ac * ay));
      const float separation = (gap_x * k.normal_x[lane] + gap_y * k.normal_y[lane]) + point.adjusted_separation[lane];
      any |= !(separation + slop >= 0.0f);
    }
    pushed[lane] = any;
  }
  unsigned lanes = 0;
  for (int lane = 0; lane < lane_count; ++lane) lanes |= static_cast<unsigned>(pushed[lane] != 0) << lane;
  return lanes;
}

FX2D_LANE_KERNEL void mark_projection_overlaps(std::span<const BatchRun> runs, const ContactBatch* batches,
                                               const FxBodyState* states, float slop, std::uint8_t* lanes) {
  for (const BatchRun& run : runs) {
    for (int i = run.first; i < run.first + run.count; ++i) {
      lanes[i] = static_cast<std::uint8_t>(run.point_count == 1 ? projection_overlap_lanes<1>(batches[i], states, slop)
                                                                : projection_overlap_lanes<2>(batches[i], states, slop));
    }
  }
}

// Marks in `deep` each batch with a point deeper than `slop`; whether any has one.
FX2D_LANE_KERNEL bool update_run_separations(std::span<const BatchRun> runs, ContactBatch* batches,
                                             const FxBodyState* states, float slop, std::uint8_t* deep) {
  bool any = false;
  for (const BatchRun& run : runs) {
    for (int i = run.first; i < run.first + run.count; ++i) {
      deep[i] = run.point_count == 1 ? update_batch_separations<1>(batches[i], states, slop)
                                     : update_batch_separations<2>(batches[i], states, slop);
      any |= deep[i] != 0;
    }
  }
  return any;
}

// Whether every point of every batch of `runs` moves within the step too little for its separation
// to need measuring again (ContactBatches::separations_hold). Padding lanes, at rest and touching,
// hold.
FX2D_LANE_KERNEL bool runs_hold_separations(std::span<const BatchRun> runs, const ContactBatch* batches,
                                            float dt, float fall, float touching_travel) {
  std::int32_t moved = 0;
  for (const BatchRun& run : runs) {
    for (int i = run.first; i < run.first + run.count; ++i) {
      const ContactBatch& k = batches[i];
      for (int p = 0; p < run.point_count; ++p) {
        // check-vectorized(1): the lane loop below must be vectorised (not unrolled first)
#pragma GCC unroll 1
        for (int lane = 0; lane < lane_count; ++lane) {
          const float separation = k.point[p].separation[lane];
          const float travel = max_of(-k.relative_velocity[p][lane], 0.0f) * dt;
          moved |= separation > 0.0f ? !(travel + fall < separation) : !(travel <= touching_travel);
        }
      }
    }
  }
  return moved == 0;
}

template <bool UseBias>
FX2D_LANE_INLINE void solve_runs(std::span<const BatchRun> runs, ContactBatch* batches, FxBodyState* states,
                                 const ContactSolveParams& params, PointOrder order, bool scalar,
                                 bool shared) {
  if (order == PointOrder::first_to_last) {
    sweep_writing<&solve_lane<1, UseBias>, &solve_lane<2, UseBias, PointOrder::first_to_last>>(
        shared, runs, batches, states, params, scalar);
  } else {
    sweep_writing<&solve_lane<1, UseBias>, &solve_lane<2, UseBias, PointOrder::last_to_first>>(
        shared, runs, batches, states, params, scalar);
  }
}

FX2D_LANE_KERNEL void solve_runs_biased(std::span<const BatchRun> runs, ContactBatch* batches,
                                        FxBodyState* states, const ContactSolveParams& params,
                                        PointOrder order, bool scalar, bool shared) {
  solve_runs<true>(runs, batches, states, params, order, scalar, shared);
}

FX2D_LANE_KERNEL void solve_runs_relaxed(std::span<const BatchRun> runs, ContactBatch* batches,
                                         FxBodyState* states, const ContactSolveParams& params,
                                         PointOrder order, bool scalar, bool shared) {
  solve_runs<false>(runs, batches, states, params, order, scalar, shared);
}

// The runs among `runs` (in batch order) cut to the batches [begin, end), written to `cut`.
std::span<const BatchRun> cut_runs(std::span<const BatchRun> runs, int begin, int end, BatchRun* cut) {
  std::size_t count = 0;
  for (const BatchRun& run : runs) {
    const int first = std::max(run.first, begin);
    const int last = std::min(run.first + run.count, end);
    if (first < last) cut[count++] = {first, last - first, run.point_count, run.serial};
  }
  return {cut, count};
}

// The most runs pack() makes: one per point count, per colour and for the overflow.
constexpr int max_runs = 2 * (ContactGraph::max_colours + 1);

}  // namespace

template <class Sweep>
void ContactBatches::sweep_by_colour(const Tasks& tasks, const Sweep& sweep) {
  if (spread_) {
    sweep_colours_apart(tasks, sweep);
  } else {
    sweep(std::span<const BatchRun>(runs_), false);
  }
}

template <class Sweep>
void ContactBatches::sweep_colours_apart(const Tasks& tasks, const Sweep& sweep) {
  const std::span<const BatchRun> runs(runs_);
  for (int colour = 0; colour < colour_count_; ++colour) {
    const std::span<const BatchRun> colour_runs = runs.subspan(first_run_[colour], first_run_[colour + 1] - first_run_[colour]);
    const int first = colour_runs.front().first;
    const auto count = static_cast<std::uint32_t>(colour_runs.back().first + colour_runs.back().count - first);
    const bool shared = tasks.runs_in_parallel(count, min_parallel_batches);
    tasks.for_each_range(count, tasks.per_worker(count, 1), min_parallel_batches, [&](std::uint32_t begin, std::uint32_t end) {
      BatchRun cut[2];
      sweep(cut_runs(colour_runs, first + static_cast<int>(begin), first + static_cast<int>(end), cut), shared);
    });
  }
  sweep(runs.subspan(first_run_[colour_count_]), false);
}

void ContactBatches::warm_start(std::span<FxBodyState> states, bool scalar, const Tasks& tasks) {
  sweep_by_colour(tasks, [&](std::span<const BatchRun> runs, bool shared) {
    warm_start_runs(runs, batches_.data(), states.data(), scalar, shared);
  });
}

void ContactBatches::push(std::span<FxBodyState> states, const ContactSolveParams& params, bool scalar,
                          const Tasks& tasks) {
  if (!any_deep_) return;
  sweep_by_colour(tasks, [&](std::span<const BatchRun> runs, bool shared) {
    push_runs(runs, batches_.data(), states.data(), params, scalar, shared, deep_.data());
  });
}

void ContactBatches::take_back_push(std::span<FxBodyState> states, bool scalar, const Tasks& tasks) {
  if (!any_deep_) return;
  sweep_by_colour(tasks, [&](std::span<const BatchRun> runs, bool shared) {
    take_back_push_runs(runs, batches_.data(), states.data(), scalar, shared, deep_.data());
  });
}

void ContactBatches::update_separations(std::span<const FxBodyState> states, float slop, const Tasks& tasks) {
  // Spread when the passes are (a colour as wide as min_parallel_batches): a pile of 300 circles,
  // 66 batches in all, took 1.19x as long to relax with its separations spread over two workers,
  // and spread from 256 batches in all, settling_boxes 3000 (some 750) took 1.06 [1.03, 1.12] (`ab`
  // at two workers): the stepping thread's passes then read columns the other core wrote.
  if (spread_) {
    update_separations_apart(states, slop, tasks);
  } else {
    any_deep_ = update_run_separations(runs_, batches_.data(), states.data(), slop, deep_.data());
  }
}

bool ContactBatches::separations_hold(float dt, float acceleration, float touching_travel) const {
  // Each of a point's two bodies may fall towards the other at `acceleration` from rest.
  const float fall = acceleration * dt * dt;
  return runs_hold_separations(runs_, batches_.data(), dt, fall, touching_travel);
}

void ContactBatches::update_separations_apart(std::span<const FxBodyState> states, float slop, const Tasks& tasks) {
  const auto count = static_cast<std::uint32_t>(batch_count_);
  // Each range writes only its own batches and marks; whether any is deep is read off the marks
  // afterwards, not gathered from the threads.
  tasks.for_each_range(count, tasks.per_worker(count, 1), min_parallel_batches, [&](std::uint32_t begin, std::uint32_t end) {
    BatchRun cut[max_runs];
    update_run_separations(cut_runs(runs_, static_cast<int>(begin), static_cast<int>(end), cut), batches_.data(),
                           states.data(), slop, deep_.data());
  });
  any_deep_ = std::find(deep_.begin(), deep_.end(), std::uint8_t{1}) != deep_.end();
}

int ContactBatches::first_projection_overlap(std::span<const FxBodyState> states, float slop) {
  mark_projection_overlaps(runs_, batches_.data(), states.data(), slop, projected_lanes_.data());
  int first = static_cast<int>(lanes_.size());
  for (int batch = 0; batch < batch_count_; ++batch) {
    const BatchMembers members = members_[batch];
    // Padding lanes hold no constraint.
    for (unsigned lanes = projected_lanes_[batch] & ((1u << members.count) - 1); lanes != 0; lanes &= lanes - 1) {
      first = std::min(first, members.first[std::countr_zero(lanes)]);
    }
  }
  return first;
}

void ContactBatches::resolve_velocities(std::span<FxBodyState> states, const ContactSolveParams& params,
                                        bool use_bias, PointOrder order, bool scalar, const Tasks& tasks) {
  sweep_by_colour(tasks, [&](std::span<const BatchRun> runs, bool shared) {
    if (use_bias) {
      solve_runs_biased(runs, batches_.data(), states.data(), params, order, scalar, shared);
    } else {
      solve_runs_relaxed(runs, batches_.data(), states.data(), params, order, scalar, shared);
    }
  });
}

}  // namespace fx2d::detail

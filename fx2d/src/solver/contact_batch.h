// ContactBatch: contact constraints transposed into columns of lane_count lanes, so that a
// velocity pass over one colour of the contact graph runs as plain loops the compiler vectorises
// (SSE, AVX2, NEON: the lane count of the machine does not matter, the loops are width-agnostic).
//
// Invariants:
// - lanes of one batch belong to one colour, so they share no movable body and may be solved at
//   once (as may the lanes of two batches of one colour, which the sweeps pair up); overflow
//   batches, whose lanes may share bodies, are solved lane by lane in order;
// - every lane of a batch has the same point count (one- and two-point manifolds are packed in
//   separate runs), and unused lanes point at the padding body's state with zero masses, so they change
//   nothing;
// - each row's Jacobian (lever arms, inverse mass and inertia times the direction) is worked out
//   once per step by pack(), so a pass only multiplies it by the bodies' velocities: the rows of
//   a two-point contact depend on each other, and every operation taken out of them shortens
//   the chain that bounds a pass;
// - the batches are the only home of the step's constraints: pack() works each one out from its
//   contact straight into its lane, and what runs contact by contact after the substeps
//   (contact_solver.cpp) reads it there;
// - the arithmetic of one lane is one function (contact_batch.cpp) used by both the batched and
//   the scalar path, and lanes are independent, so the two agree to the bit and the result does
//   not depend on the lane count;
// - with several workers, the batches of one colour are spread over them in ranges, colour after
//   colour with a wait between, and the overflow runs on the stepping thread alone. Batches of a
//   colour share no movable body, so they may run in any order on any thread and give the same
//   bits; they write back only the bodies that carry movable_flag, since the unchanged copies of a
//   static or kinematic body would otherwise be written from two threads at once.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "collision/collide.h"
#include "solver/contact_graph.h"
#include "solver/contact_solver.h"
#include "solver/lane_rows.h"
#include "world/tasks.h"

namespace fx2d::detail {

struct Bodies;
class ContactCache;

// The part of a body's solver state a velocity pass reads and writes, copied into locals.
struct LaneBody {
  float vx, vy, w;
};

inline constexpr std::int32_t round_side_a = 1;
inline constexpr std::int32_t round_side_b = 2;

struct ContactBatch;
// The arithmetic of one lane: one contact of a batch in one pass.
using LaneFn = void (*)(ContactBatch& batch, int lane, LaneBody& a, LaneBody& b, const ContactSolveParams& params);

// One manifold point of every lane of a batch. What the velocity passes read comes first; the
// anchors, read once per substep to update the separation, last.
struct PointColumns {
  // The anchors' lever arms about the normal and the tangent, cross(anchor, direction): how a
  // body's spin moves the point along that direction. Constant for the step, like the anchors.
  float arm_normal_a[lane_count];
  float arm_normal_b[lane_count];
  float arm_tangent_a[lane_count];
  float arm_tangent_b[lane_count];
  // The lever arms times the body's inverse inertia: the spin a unit impulse there gives it. Worked
  // out in every pass instead, from two columns of inverse inertias per batch (the same bits, a
  // seventh less to read per two-point contact), they cost more than they save (`ab`, sleeping off,
  // 800 bodies: stacks 1.022, pile 1.011, settling_boxes 1.004; settling_boxes 3000 0.996).
  float spin_normal_a[lane_count];
  float spin_normal_b[lane_count];
  float spin_tangent_a[lane_count];
  float spin_tangent_b[lane_count];
  // The change of this point's tangent row's relative speed per unit impulse on each point's
  // normal row (solve_lane).
  float tangent_from_normal[2][lane_count];
  float separation[lane_count];  // at the poses of the last position integration (update_separations)
  float normal_mass[lane_count];
  float tangent_mass[lane_count];
  float normal_impulse[lane_count];
  float tangent_impulse[lane_count];
  // The largest impulse a pass added along the normal this step; only restitution reads it. Not
  // recorded in the steps without a bouncing contact (0.4% fewer instructions), stacks 50 took
  // 0.953 of its step, but 1.003 with both builds' loops aligned to 64 bytes (`ab --a-cmake
  // --b-cmake -DCMAKE_CXX_FLAGS=-falign-loops=64`): the soft pass's speed moved with where its loops
  // fell, as -falign-loops=64 alone moves it to 0.82 on stacks 50 and 1.12 on pile 50.
  float max_normal_impulse[lane_count];
  // The impulse push() applied this substep to move an overlap apart, kept out of normal_impulse
  // because take_back_push() removes it again.
  float push_impulse[lane_count];
  float anchor_ax[lane_count];
  float anchor_ay[lane_count];
  float anchor_bx[lane_count];
  float anchor_by[lane_count];
  float adjusted_separation[lane_count];
};

struct alignas(32) ContactBatch {
  // Each lane's bodies, as the byte offsets of their states among the solver's states
  // (state_offset(): the passes address a state with no shift).
  std::uint32_t state_a[lane_count];
  std::uint32_t state_b[lane_count];
  float normal_x[lane_count];
  float normal_y[lane_count];
  // Each body's inverse mass times the normal: an impulse along the normal changes its velocity
  // by this much per unit (along the tangent, by the same numbers turned a quarter).
  float mass_normal_ax[lane_count];
  float mass_normal_ay[lane_count];
  float mass_normal_bx[lane_count];
  float mass_normal_by[lane_count];
  float friction[lane_count];
  // Couplings between the rows of a two-point contact: the change of the second row's relative
  // speed per unit impulse on the first (solve_lane).
  float normal1_from_normal0[lane_count];
  float tangent1_from_tangent0[lane_count];
  // The body the normal turns with when the separations are updated: a NormalFrame, as an int so
  // that the lane loop compares it in vector registers.
  std::int32_t normal_frame[lane_count];
  // Which bodies are circles (round_side_a, round_side_b), whose anchors turn with the normal, not
  // with the body: a circle's point facing the other body stays on the line of centres however it
  // spins. Turned with a rolling circle, the anchor would leave the surface and open a false gap
  // of (1 - cos turn) x radius, 7 mm for a 1 m ball rolling at 5 m/s, and the contact would let go.
  std::int32_t round_sides[lane_count];
  // Per manifold point, each point's columns together: a one-point batch never touches the
  // second point's, so its passes read half the cache lines.
  PointColumns point[2];
  // Read only after the substeps, contact by contact (contact_solver.cpp).
  float inv_mass_a[lane_count];
  float inv_mass_b[lane_count];
  float inv_inertia_a[lane_count];
  float inv_inertia_b[lane_count];
  float restitution[lane_count];
  float relative_velocity[2][lane_count];  // per point, the normal velocity before the step
};

// Consecutive batches of one colour (or of the overflow) with one point count.
struct BatchRun {
  int first = 0;        // first batch
  int count = 0;        // batches
  int point_count = 1;  // 1 or 2
  bool serial = false;  // overflow: lanes may share bodies
};

// The order in which a velocity pass solves a two-point contact's points. Gauss-Seidel favours
// the point it solves first: a box resting on two corners takes more of its load on one, and a
// symmetric stack leans. The substeps alternate the order, so the bias of one undoes the last's
// (at 6 substeps and 120 Hz a ten-box column leaned 4.9 mm in one order; at the default schedule
// the stacks' largest displacement fell from 2.64 to 2.29 mm with the alternation).
enum class PointOrder { first_to_last, last_to_first };

// The fewest batches the widest colour needs for the passes to be spread over the workers at all
// (measured: fx2d/src/README.md).
inline constexpr std::uint32_t min_parallel_batches = 256;

class ContactBatches {
 public:
  // Grows storage for this many constraints, so pack() does not allocate up to there.
  void reserve(std::size_t constraints);
  // Packs the constraints colour by colour, each worked out from its contact in `contacts` and
  // its bodies straight into its lane; the batches are built in ranges over `tasks` when there
  // are enough. `padding_body` indexes a state that is never read back (one past the last body).
  // Decides, for the step, whether the passes spread over `tasks` (never with `scalar`, the
  // lane-by-lane twin).
  void pack(std::span<const ConstraintSource> constraints, const ContactGraph& graph, const ContactCache& contacts,
            const Bodies& bodies, std::uint32_t padding_body, const Tasks& tasks, bool scalar);
  // With `scalar`, every batch is solved lane by lane (the scalar twin), on the stepping thread;
  // the result is the same. `tasks` spreads each colour's batches over the workers.
  void warm_start(std::span<FxBodyState> states, bool scalar, const Tasks& tasks);
  // Works out every point's separation at the current poses; the velocity passes read it. Poses
  // change only between substeps, so once after each position integration is enough. Also marks
  // the batches with a point deeper than `slop`, the only ones push() touches. It is some 70% of a
  // rigid pass's instructions. Done batch by batch just before the first rigid pass's rows instead
  // (the same bits), it saved 0.3% of stacks 200's instructions and took 1.04 times the time; on
  // settling_boxes 200, which measures every substep, `ab` gave the step 0.992 [0.988, 0.997] and
  // the relax stage 1.017 [1.007, 1.019]: the loop it saves is not what costs. Nor would skipping
  // the batches whose points all touch and rest at the step's start (a physics change) spare much:
  // at most 17% of settling_boxes 200's batches qualify, as most hold a speculative point. Nor the
  // step's first call, by pack() writing each point's separation and each batch's mark as it works
  // out the anchors (at the step's start the update's turn and displacement are zero: the same
  // bits): instructions 0.992-0.995 and colour_and_pack 0.92-0.94 of theirs, but the step 0.988
  // [0.985, 0.990] on stacks 50 and 0.989-0.996 on the box scenes and pile at 200 (`ab`, 12-16
  // rounds, sleeping off), inside the noise band.
  void update_separations(std::span<const FxBodyState> states, float slop, const Tasks& tasks);
  // True when, over a step of `dt`, no point apart can close its gap at its relative speed at the
  // step's start and `acceleration` for each of its bodies, and no touching point closes by more
  // than `touching_travel` (metres): step_schedule.h's rule for measuring separations once a step.
  bool separations_hold(float dt, float acceleration, float touching_travel) const;
  // Gives every point deeper than the slop the velocity that separates it at the soft contact's
  // rate, at most max_push_speed; take_back_push(), once the positions have moved, removes exactly
  // that velocity again, so overlaps are pushed apart in position and nothing is launched. Both
  // visit only the batches update_separations() marked deep, and nothing when none is: a resting
  // scene, whose overlaps stay within the slop, pays for neither. take_back_push() must run before
  // the next update_separations(), which moves the marks.
  void push(std::span<FxBodyState> states, const ContactSolveParams& params, bool scalar, const Tasks& tasks);
  void take_back_push(std::span<FxBodyState> states, bool scalar, const Tasks& tasks);
  // One pass over every contact, soft (use_bias) or rigid, a two-point contact's points in `order`.
  void resolve_velocities(std::span<FxBodyState> states, const ContactSolveParams& params, bool use_bias,
                          PointOrder order, bool scalar, const Tasks& tasks);
  // The first constraint (in pack()'s order) with a point that the position projection
  // (ContactSolver::project_positions) would push at `states`, or the constraint count: found
  // batch by batch in lanes, measured as that pass measures, to the bit.
  int first_projection_overlap(std::span<const FxBodyState> states, float slop);
  // Whether constraint `constraint` had such a point when first_projection_overlap() last measured.
  bool overlapped_at_start(int constraint) const {
    const int lane = lanes_[constraint];
    return ((projected_lanes_[lane / lane_count] >> (lane % lane_count)) & 1u) != 0;
  }
  // The batch and the lane that hold constraint `constraint` (an index into pack()'s constraints).
  ContactBatch& batch_holding(int constraint) { return batches_[lanes_[constraint] / lane_count]; }
  const ContactBatch& batch_holding(int constraint) const { return batches_[lanes_[constraint] / lane_count]; }
  int lane_holding(int constraint) const { return lanes_[constraint] % lane_count; }

 private:
  // The constraints packed into batch i: `count` of the graph's members from `first` on.
  struct BatchMembers {
    const int* first = nullptr;
    int count = 0;
  };

  // Lays out the runs of one colour (or of the overflow): which batch each member goes to.
  void add_runs(const ContactGraph& graph, int colour, bool serial);
  void build_batch(int index, std::span<const ConstraintSource> constraints, const ContactCache& contacts,
                   const Bodies& bodies, std::uint32_t padding_body);
  // Calls sweep(runs, shared) over every run: at once on this thread (shared false), or, when
  // pack() chose to spread, colour by colour over the workers on ranges of runs cut
  // to whole batches (shared true: only movable bodies may be written back), then the overflow on
  // this thread. The sweep over a colour's ranges returns before the next colour starts.
  template <class Sweep>
  void sweep_by_colour(const Tasks& tasks, const Sweep& sweep);
  // The spread halves of sweep_by_colour() and update_separations(), kept out of line so that
  // the one-thread path stays as short as it was before threads.
  template <class Sweep>
  [[gnu::noinline]] void sweep_colours_apart(const Tasks& tasks, const Sweep& sweep);
  [[gnu::noinline]] void update_separations_apart(std::span<const FxBodyState> states, float slop, const Tasks& tasks);

  // The first batch_count_ are this step's; the storage only grows, so that a batch is not
  // cleared before pack() writes every lane of it.
  std::vector<ContactBatch> batches_;
  int batch_count_ = 0;
  std::vector<BatchMembers> members_;  // per batch
  std::vector<int> lanes_;             // per constraint, batch * lane_count + lane
  std::vector<BatchRun> runs_;
  // Colour c's runs are runs_[first_run_[c], first_run_[c + 1]); the overflow's follow them.
  int first_run_[ContactGraph::max_colours + 1] = {};
  int colour_count_ = 0;
  bool spread_ = false;  // whether this step's passes spread over the workers
  // Per batch: whether a point of it was deeper than the slop at the last update_separations().
  std::vector<std::uint8_t> deep_;
  bool any_deep_ = false;
  // Per batch, scratch of first_projection_overlap(): its lanes that the projection would push.
  std::vector<std::uint8_t> projected_lanes_;
};

}  // namespace fx2d::detail

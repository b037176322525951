// JointBatches: the step's provided joints of one kind, revolute joints (pins) or distance joints
// (rods), in eight-lane batches, each colour's joints sharing no body that moves, so that a pass
// solves eight at once as one vectorised loop (joint_batches.cpp), as the contacts are
// (contact_batch.h). The arithmetic of a lane is its joint's own (joint_arithmetic.h); what changes
// is the Gauss-Seidel order: colour by colour, each colour's joints in the order they were added,
// the pins' colours before the rods', instead of every joint in the order added.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"
#include "solver/joint_arithmetic.h"
#include "solver/lane_rows.h"

namespace fx2d::detail {

// What a batch of either kind holds, a column per field. A padding lane names the padding state and
// has no mass, so its impulse is never solvable and it writes nothing.
struct JointBatchColumns {
  std::uint32_t state_a[lane_count];  // byte offsets of the bodies' states (BodyList::offsets)
  std::uint32_t state_b[lane_count];
  float inv_mass_a[lane_count], inv_inertia_a[lane_count], inv_mass_b[lane_count], inv_inertia_b[lane_count];
  // JointFrame: the anchors at the step's start, and anchor b minus anchor a then.
  float anchor_ax[lane_count], anchor_ay[lane_count], anchor_bx[lane_count], anchor_by[lane_count];
  float separation_x[lane_count], separation_y[lane_count];
  float within_limit[lane_count];  // impulse_surely_within_limit()
};

// Eight pins: their accumulated impulses.
struct PinBatch : JointBatchColumns {
  static constexpr JointKind kind = JointKind::revolute_joint;
  float impulse_x[lane_count], impulse_y[lane_count];
};

// Eight rods: their accumulated impulses along their axes, and their rest lengths.
struct RodBatch : JointBatchColumns {
  static constexpr JointKind kind = JointKind::distance_joint;
  float impulse[lane_count];
  float length[lane_count];
};

template <class Batch>
class JointBatches {
 public:
  // Colours the rows of `rows` of Batch's kind greedily in their order (a body without
  // movable_flag in `states` takes part in any number of a colour's joints) and packs each colour
  // into batches. Marks in `packed` (one entry per row) each row it packed: a joint that finds no
  // colour among the first max_colours, like every row of another kind, is left to the caller.
  // `padding_state` indexes a state never read back.
  void pack(std::span<const JointRow> rows, std::span<const FxBodyState> states, std::uint32_t padding_state,
            std::vector<std::uint8_t>& packed);
  // Every batch's kept impulses applied again; one pass, soft (use_bias) or rigid. With `scalar`,
  // lane by lane in the same order (the scalar twin; the same bits).
  void warm_start(std::span<FxBodyState> states, bool scalar);
  void solve(std::span<FxBodyState> states, const JointPassParams& params, bool use_bias, bool scalar);
  // The accumulated impulse of row `row` (an index into pack()'s rows), which pack() packed: a
  // pin's vector, a rod's along its axis as the row's x.
  FxVec2f impulse(std::size_t row) const;

  static constexpr int max_colours = 32;

 private:
  std::vector<Batch> batches_;
  int batch_count_ = 0;
  std::vector<int> lanes_;               // per row, batch * lane_count + lane, or -1
  std::vector<std::uint32_t> colours_;   // per state, a bit per colour that holds it (scratch)
  std::vector<std::uint8_t> colour_of_;  // per row (scratch)
};

using PinBatches = JointBatches<PinBatch>;
using RodBatches = JointBatches<RodBatch>;

}  // namespace fx2d::detail

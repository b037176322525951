// JointRows: the step's constraints in the order they were added. A joint Fx2D provides becomes a
// plain record, its bodies' state indices and inverse masses looked up once a step, so that a pass
// over it makes no virtual call and follows no pointer (through FxConstraintContext, each pass of
// a pin made seven calls and took about 390 instructions). A user's own constraint keeps its calls
// through the context, in its place in the order, so the passes solve in the same order as before.
//
// Measured and not kept (scenes/joints/, mean step or `ab`, the same bits unless said):
// - what depends on the poses alone (the turned anchors, K and its inverse, the bias) kept per row
//   once a substep, as those move only in the position integration: 0.84 of the instructions on
//   joint_grid and 0.76 on chain, but 1.12 and 1.05 times the time (`ab`). A pass is bound by the
//   chain of arithmetic from one body's velocity to the next, beside which the pose's arithmetic
//   ran for free, and storing it cost loads;
// - the rows ordered by colour (greedy, no two rows of a colour sharing a body that moves), so that
//   rows overlap in the core: chain 0.82, joint_grid 1.02, and every jointed result moves, since
//   the order is the Gauss-Seidel order;
// - each row solved on copies of its two states (which cannot alias), the velocities written back:
//   1.13 and 1.15 times the time, as the 32-byte copy of a state the row before has just written
//   waits for that store.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"
#include "solver/joint_arithmetic.h"
#include "world/bodies.h"

namespace fx2d::detail {

class JointRows {
 public:
  // The step's rows, built from `constraints`: a provided joint's from its definition and the
  // bodies at the step's start, its kept impulse scaled by the context's impulse_ratio; a user's
  // constraint by its own prepare(context). `context` must outlive the step's passes.
  void prepare(const Constraints& constraints, const Bodies& bodies, FxConstraintContext& context);
  // Per substep: every row's kept impulse applied again, in order.
  void warm_start(std::span<FxBodyState> states);
  // One pass over every row, in order: soft (use_bias) or rigid.
  void evaluate(std::span<FxBodyState> states, bool use_bias);
  // Hands each provided joint its accumulated impulse, for the next step's warm start.
  void store() const;

 private:
  enum class Kind : std::uint8_t { user, distance_joint, revolute_joint };
  struct Row {
    Kind kind;
    std::uint32_t a, b;  // states
    float inv_mass_a, inv_inertia_a, inv_mass_b, inv_inertia_b;
    JointFrame frame;
    FxVec2f impulse;  // a distance joint's in x
    float length;     // a distance joint's rest length
    float within_limit;  // impulse_surely_within_limit()
  };

  static JointBodies bodies_of(const Row& row, std::span<FxBodyState> states) {
    return {states[row.a],     states[row.b],  row.inv_mass_a,
            row.inv_inertia_a, row.inv_mass_b, row.inv_inertia_b};
  }

  std::vector<Row> rows_;
  std::vector<FxConstraint*> owners_;  // per row, the constraint it stands for
  FxConstraintContext* context_ = nullptr;
  JointPassParams params_{};
};

}  // namespace fx2d::detail

// JointRows: the step's constraints in the order they were added. A joint Fx2D provides becomes a
// plain record, its bodies' state indices and inverse masses looked up once a step, so that a pass
// over it makes no virtual call and follows no pointer (through FxConstraintContext, each pass of
// a pin made seven calls and took about 390 instructions). Each pass works out again what depends
// on the poses alone (the turned anchors, K and its inverse, the bias), though those move only in
// the position integration: kept per row once a substep instead, the passes ran 0.84 of the
// instructions on joint_grid and 0.76 on chain (scenes/joints/) but took 1.12 and 1.05 times as
// long (`ab`): a pass is bound by the chain of arithmetic from one body's velocity to the next,
// beside which the pose's arithmetic ran for free, and storing it cost loads. Ordered by colour
// (greedy, no two rows of a colour sharing a body that moves) so that rows overlap in the core,
// the chain's mean step took 0.82 of its time but joint_grid's 1.02 (`run`, 3 repeats), and the
// order is the Gauss-Seidel order, so every jointed result moves: not kept for the chain alone.
// Solved on copies of the two states (which cannot alias), their velocities written back, the
// mean step took 1.13 (joint_grid) and 1.15 (chain) times as long: the 32-byte copy of a state the
// row before has just written waits for that store. A user's own
// constraint keeps its calls through the context, in its place in the order, so the passes solve in the same
// order as before.
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

// JointRows: the step's constraints. A joint Fx2D provides becomes a plain record, its bodies' state
// indices and inverse masses looked up once a step, so that a pass over it makes no virtual call and
// follows no pointer (through FxConstraintContext, each pass of a pin made seven calls and took
// about 390 instructions). The pins (revolute joints), then the rods (distance joints), are then
// coloured and solved eight at a time in lanes (JointBatches), colour by colour; the other rows
// follow in the order they were added, a user's own constraint through its calls to the context.
//
// The pins' batches change the Gauss-Seidel order from the order added to colour by colour. That
// holds the pins as well: a 100-link chain released level opened 2.11 cm at worst either way, 200
// links 4.75 against 4.76 cm, the stability suite's chain_load boundary stays 939, and joint_grid
// sags 0.0371 m against 0.0369 (probe and `ab`). With the rows only reordered by colour, solved
// one by one, chain took 0.87 of the time and joint_grid 1.02; in lanes (`ab`, sleeping off): chain
// 0.62, joint_grid 0.69, a 200-link chain 0.56, 100 five-body ragdolls 0.81 (the same bits there:
// each ragdoll's pins keep their order, and the ragdolls share no body). The rods likewise: the
// 200-link rope (scenes/joints/rope.json) took 0.61 of the step, its worst stretch 5.507 cm against
// 5.505 (released level, 300 steps), and the ragdolls, one rod each, 0.93 (the same bits).
//
// Measured and not kept (scenes/joints/, mean step or `ab`, the same bits unless said):
// - what depends on the poses alone (the turned anchors, K and its inverse, the bias) kept per row
//   once a substep, as those move only in the position integration: 0.84 of the instructions on
//   joint_grid and 0.76 on chain, but 1.12 and 1.05 times the time (`ab`). A pass is bound by the
//   chain of arithmetic from one body's velocity to the next, beside which the pose's arithmetic
//   ran for free, and storing it cost loads;
// - each row solved on copies of its two states (which cannot alias), the velocities written back:
//   1.13 and 1.15 times the time, as the 32-byte copy of a state the row before has just written
//   waits for that store.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"
#include "solver/joint_arithmetic.h"
#include "solver/joint_batches.h"
#include "world/bodies.h"

namespace fx2d::detail {

class JointRows {
 public:
  // The step's rows, built from `constraints`: a provided joint's from its definition and the
  // bodies at the step's start, its kept impulse scaled by the context's impulse_ratio; a user's
  // constraint by its own prepare(context). `context` must outlive the step's passes.
  // The pins and the rods are packed into batches (JointBatches), coloured by the bodies `states`
  // flags as moving.
  void prepare(const Constraints& constraints, const Bodies& bodies, FxConstraintContext& context,
               std::span<const FxBodyState> states);
  // Per substep: every row's kept impulse applied again.
  void warm_start(std::span<FxBodyState> states, bool scalar);
  // One pass over every row, soft (use_bias) or rigid: the pins' batches colour by colour, the
  // rods' likewise, then the other rows in order. With `scalar`, the batches lane by lane (the same
  // bits).
  void evaluate(std::span<FxBodyState> states, bool use_bias, bool scalar);
  // Hands each provided joint its accumulated impulse, for the next step's warm start.
  void store() const;

 private:
  using Kind = JointKind;
  using Row = JointRow;

  static JointBodies bodies_of(const Row& row, std::span<FxBodyState> states) {
    return {states[row.a],     states[row.b],  row.inv_mass_a,
            row.inv_inertia_a, row.inv_mass_b, row.inv_inertia_b};
  }

  std::vector<Row> rows_;
  std::vector<FxConstraint*> owners_;  // per row, the constraint it stands for
  PinBatches pins_;
  RodBatches rods_;
  std::vector<std::uint8_t> packed_;  // per row, whether pins_ or rods_ solves it
  // The rows neither solves, ascending: the passes visit these alone, not every row to skip the
  // packed ones (a 200-link chain's scan of its packed pins was 7% of its step's instructions).
  std::vector<std::uint32_t> unpacked_;
  FxConstraintContext* context_ = nullptr;
  JointPassParams params_{};
};

}  // namespace fx2d::detail

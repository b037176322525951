// The step's joints as rows (joint_rows.h).
#include "solver/joint_rows.h"

namespace fx2d::detail {

void JointRows::prepare(const Constraints& constraints, const Bodies& bodies, FxConstraintContext& context,
                        std::span<const FxBodyState> states) {
  // Sized once and each row written in place. Built in a temporary and pushed, a row was copied in
  // wide loads that waited for the narrow stores that had just built it: on the 200-link chain this
  // loop took 10,900 cycles a step, against 4,000 so (an rdtsc probe).
  rows_.resize(constraints.size());
  owners_.resize(constraints.size());
  unpacked_.clear();
  context_ = &context;
  params_ = {context.softness, context.max_linear_speed, context.max_angular_speed};
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    FxConstraint& constraint = *constraints[i];
    owners_[i] = &constraint;
    Row& row = rows_[i];
    if (constraint.provided_ == FxConstraint::Provided::none) {
      constraint.prepare(context);
      row = Row{};
      continue;
    }
    const std::uint32_t a = constraint.entity_a()->packed_index();
    const std::uint32_t b = constraint.entity_b()->packed_index();
    const BodySim& sa = bodies.sims[a];
    const BodySim& sb = bodies.sims[b];
    row.a = a, row.b = b;
    row.inv_mass_a = sa.inv_mass, row.inv_inertia_a = sa.inv_inertia;
    row.inv_mass_b = sb.inv_mass, row.inv_inertia_b = sb.inv_inertia;
    const auto frame = [&](FxVec2f local_anchor_a, FxVec2f local_anchor_b) {
      return joint_frame(start_anchor(sa.rotation, sa.local_center, local_anchor_a),
                         start_anchor(sb.rotation, sb.local_center, local_anchor_b),
                         bodies.center_offset(a, b));
    };
    if (constraint.provided_ == FxConstraint::Provided::distance_joint) {
      const auto& joint = static_cast<const FxDistanceJoint&>(constraint);
      row.kind = Kind::distance_joint;
      row.frame = frame(joint.local_anchor_a_, joint.local_anchor_b_);
      row.impulse = {fx_carried_impulse(joint.impulse_, context.impulse_ratio), 0.0f};
      row.length = joint.length_;
    } else {
      const auto& joint = static_cast<const FxRevoluteJoint&>(constraint);
      row.kind = Kind::revolute_joint;
      row.frame = frame(joint.local_anchor_a_, joint.local_anchor_b_);
      row.impulse = {fx_carried_impulse(joint.impulse_.x, context.impulse_ratio),
                     fx_carried_impulse(joint.impulse_.y, context.impulse_ratio)};
      row.length = 0.0f;
    }
    row.within_limit = impulse_surely_within_limit(params_, sa.inv_mass + sb.inv_mass, row.frame);
  }
  const auto padding_state = static_cast<std::uint32_t>(states.size() - 1);
  packed_.assign(rows_.size(), 0);
  pins_.pack(rows_, states, padding_state, packed_);
  rods_.pack(rows_, states, padding_state, packed_);
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    if (!packed_[i]) unpacked_.push_back(static_cast<std::uint32_t>(i));
  }
}

// Invariant of both loops: unpacked_ is ascending, so the rows the batches leave run in the
// constraints' order, and a row's state indices hold for the whole step (no body is added or
// removed within it).
void JointRows::warm_start(std::span<FxBodyState> states, bool scalar) {
  pins_.warm_start(states, scalar);
  rods_.warm_start(states, scalar);
  for (const std::uint32_t i : unpacked_) {
    Row& row = rows_[i];
    switch (row.kind) {
      case Kind::distance_joint: {
        JointBodies bodies = bodies_of(row, states);
        warm_start_distance(bodies, row.frame, row.impulse.x);
        break;
      }
      case Kind::revolute_joint: {
        JointBodies bodies = bodies_of(row, states);
        warm_start_revolute(bodies, row.frame, row.impulse);
        break;
      }
      case Kind::user:
        owners_[i]->warm_start(*context_);
        break;
    }
  }
}

void JointRows::evaluate(std::span<FxBodyState> states, bool use_bias, bool scalar) {
  pins_.solve(states, params_, use_bias, scalar);
  rods_.solve(states, params_, use_bias, scalar);
  for (const std::uint32_t i : unpacked_) {
    Row& row = rows_[i];
    switch (row.kind) {
      case Kind::distance_joint: {
        JointBodies bodies = bodies_of(row, states);
        solve_distance(bodies, row.frame, row.length, row.impulse.x, params_, use_bias, row.within_limit);
        break;
      }
      case Kind::revolute_joint: {
        JointBodies bodies = bodies_of(row, states);
        solve_revolute(bodies, row.frame, row.impulse, params_, use_bias, row.within_limit);
        break;
      }
      case Kind::user:
        owners_[i]->evaluate(*context_, use_bias);
        break;
    }
  }
}

void JointRows::store() const {
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const Row& row = rows_[i];
    if (row.kind == Kind::distance_joint) {
      static_cast<FxDistanceJoint*>(owners_[i])->impulse_ = packed_[i] ? rods_.impulse(i).x : row.impulse.x;
    }
    if (row.kind == Kind::revolute_joint) {
      static_cast<FxRevoluteJoint*>(owners_[i])->impulse_ = packed_[i] ? pins_.impulse(i) : row.impulse;
    }
  }
}

}  // namespace fx2d::detail

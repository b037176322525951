// The step's joints as rows (joint_rows.h).
#include "solver/joint_rows.h"

namespace fx2d::detail {

void JointRows::prepare(const Constraints& constraints, const Bodies& bodies, FxConstraintContext& context,
                        std::span<const FxBodyState> states) {
  rows_.clear();
  owners_.clear();
  unpacked_.clear();
  context_ = &context;
  params_ = {context.softness, context.max_linear_speed, context.max_angular_speed};
  for (const auto& constraint : constraints) {
    owners_.push_back(constraint.get());
    if (constraint->provided_ == FxConstraint::Provided::none) {
      constraint->prepare(context);
      rows_.push_back({Kind::user, 0, 0, 0.0f, 0.0f, 0.0f, 0.0f, {}, {}, 0.0f, 0.0f});
      continue;
    }
    const std::uint32_t a = constraint->entity_a()->packed_index();
    const std::uint32_t b = constraint->entity_b()->packed_index();
    const BodySim& sa = bodies.sims[a];
    const BodySim& sb = bodies.sims[b];
    Row row{Kind::user, a, b, sa.inv_mass, sa.inv_inertia, sb.inv_mass, sb.inv_inertia, {}, {}, 0.0f, 0.0f};
    const auto frame = [&](FxVec2f local_anchor_a, FxVec2f local_anchor_b) {
      return joint_frame(start_anchor(sa.rotation, sa.local_center, local_anchor_a),
                         start_anchor(sb.rotation, sb.local_center, local_anchor_b),
                         bodies.center_offset(a, b));
    };
    if (constraint->provided_ == FxConstraint::Provided::distance_joint) {
      const auto& joint = static_cast<const FxDistanceJoint&>(*constraint);
      row.kind = Kind::distance_joint;
      row.frame = frame(joint.local_anchor_a_, joint.local_anchor_b_);
      row.impulse.x = fx_carried_impulse(joint.impulse_, context.impulse_ratio);
      row.length = joint.length_;
    } else {
      const auto& joint = static_cast<const FxRevoluteJoint&>(*constraint);
      row.kind = Kind::revolute_joint;
      row.frame = frame(joint.local_anchor_a_, joint.local_anchor_b_);
      row.impulse = {fx_carried_impulse(joint.impulse_.x, context.impulse_ratio),
                     fx_carried_impulse(joint.impulse_.y, context.impulse_ratio)};
    }
    row.within_limit = impulse_surely_within_limit(params_, sa.inv_mass + sb.inv_mass, row.frame);
    rows_.push_back(row);
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

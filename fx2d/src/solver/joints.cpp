// The constraint base and the two joints Fx2D provides, solved as soft constraints in the same
// passes as contacts: here through the FxConstraintContext a user's own solver gives them; the
// step solves them as joint rows (joint_rows.h), with the same arithmetic (joint_arithmetic.h).
#include <cmath>
#include <string>

#include "fx2d/Constraint.h"
#include "solver/joint_arithmetic.h"
#include "world/bodies.h"

namespace fx2d {
namespace {

// An anchor or pin as far out as a body may be placed, and no further: beyond that, sums of
// anchors and offsets overflow float.
bool within_world(FxVec2f point) {
  return is_finite(point) && std::fabs(point.x) <= detail::max_coordinate && std::fabs(point.y) <= detail::max_coordinate;
}

detail::JointBodies bodies_of(FxConstraintContext& context, const FxConstraint& joint) {
  const FxEntity& a = *joint.entity_a();
  const FxEntity& b = *joint.entity_b();
  return {context.state(a), context.state(b), context.inv_mass(a), context.inv_inertia(a), context.inv_mass(b),
          context.inv_inertia(b)};
}

detail::JointPassParams pass_params(const FxConstraintContext& context) {
  return {context.softness, context.max_linear_speed, context.max_angular_speed};
}

// The joint's frame at the step's start, its local anchors turned as its bodies stand then.
detail::JointFrame frame_of(FxConstraintContext& context, const FxConstraint& joint, FxVec2f local_anchor_a,
                            FxVec2f local_anchor_b) {
  const FxEntity& a = *joint.entity_a();
  const FxEntity& b = *joint.entity_b();
  return detail::joint_frame(
      detail::start_anchor(context.start_rotation(a), context.local_center(a), local_anchor_a),
      detail::start_anchor(context.start_rotation(b), context.local_center(b), local_anchor_b),
      context.center_offset(a, b));
}

// Keeps a frame in a joint's own members, which its warm_start() and evaluate() read.
void keep(const detail::JointFrame& frame, FxVec2f& anchor_a, FxVec2f& anchor_b, FxVec2f& separation0) {
  anchor_a = frame.anchor_a;
  anchor_b = frame.anchor_b;
  separation0 = frame.separation0;
}

FxVec2f world_point(const FxEntity& entity, FxVec2f local_point) {
  return entity.position() + rotate(entity.rotation(), local_point);
}

}  // namespace

FxSoftness make_softness(float hertz, float damping_ratio, float substep_dt) {
  const float omega = 2.0f * 3.14159265358979f * hertz;
  const float a1 = 2.0f * damping_ratio + substep_dt * omega;
  const float a2 = substep_dt * omega * a1;
  const float a3 = 1.0f / (1.0f + a2);
  return {omega / a1, a2 * a3, a3};
}

FxConstraint::FxConstraint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b)
    : FxConstraint(std::move(a), std::move(b), Provided::none) {}

FxConstraint::FxConstraint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b, Provided provided)
    : a_(std::move(a)), b_(std::move(b)), provided_(provided) {
  if (!a_ || !b_) throw FxInvalidArgument("FxConstraint: entities: expected two entities, got null");
  if (a_ == b_) throw FxInvalidArgument("FxConstraint: entities: expected two different entities");
  if (a_->type() != FxBodyType::dynamic && b_->type() != FxBodyType::dynamic) {
    throw FxInvalidArgument("FxConstraint: entities: expected at least one dynamic entity");
  }
}

FxDistanceJoint::FxDistanceJoint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b,
                                 FxVec2f local_anchor_a, FxVec2f local_anchor_b, float length)
    : FxConstraint(std::move(a), std::move(b), Provided::distance_joint),
      local_anchor_a_(local_anchor_a),
      local_anchor_b_(local_anchor_b),
      length_(length) {
  if (!within_world(local_anchor_a) || !within_world(local_anchor_b)) {
    throw FxInvalidArgument("FxDistanceJoint: local anchors: expected finite coordinates within 1e7 m");
  }
  if (!std::isfinite(length) || length > detail::max_coordinate) {
    throw FxInvalidArgument("FxDistanceJoint: length: expected a finite number <= 1e7 m");
  }
  if (length_ < 0.0f) length_ = current_length();
}

float FxDistanceJoint::current_length() const {
  return distance(world_point(*entity_a(), local_anchor_a_), world_point(*entity_b(), local_anchor_b_));
}

void FxDistanceJoint::prepare(FxConstraintContext& context) {
  impulse_ = fx_carried_impulse(impulse_, context.impulse_ratio);
  keep(frame_of(context, *this, local_anchor_a_, local_anchor_b_), anchor_a_, anchor_b_, separation0_);
}

void FxDistanceJoint::warm_start(FxConstraintContext& context) {
  detail::JointBodies bodies = bodies_of(context, *this);
  detail::warm_start_distance(bodies, {anchor_a_, anchor_b_, separation0_}, impulse_);
}

void FxDistanceJoint::evaluate(FxConstraintContext& context, bool use_bias) {
  detail::JointBodies bodies = bodies_of(context, *this);
  detail::solve_distance(bodies, {anchor_a_, anchor_b_, separation0_}, length_, impulse_,
                         pass_params(context), use_bias);
}

FxRevoluteJoint::FxRevoluteJoint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b,
                                 FxVec2f world_anchor)
    : FxConstraint(std::move(a), std::move(b), Provided::revolute_joint) {
  if (!within_world(world_anchor)) {
    throw FxInvalidArgument("FxRevoluteJoint: world_anchor: expected finite coordinates within 1e7 m");
  }
  local_anchor_a_ = inv_rotate(entity_a()->rotation(), world_anchor - entity_a()->position());
  local_anchor_b_ = inv_rotate(entity_b()->rotation(), world_anchor - entity_b()->position());
}

float FxRevoluteJoint::anchor_gap() const {
  return distance(world_point(*entity_a(), local_anchor_a_), world_point(*entity_b(), local_anchor_b_));
}

void FxRevoluteJoint::prepare(FxConstraintContext& context) {
  impulse_ = {fx_carried_impulse(impulse_.x, context.impulse_ratio),
              fx_carried_impulse(impulse_.y, context.impulse_ratio)};
  keep(frame_of(context, *this, local_anchor_a_, local_anchor_b_), anchor_a_, anchor_b_, separation0_);
}

void FxRevoluteJoint::warm_start(FxConstraintContext& context) {
  detail::JointBodies bodies = bodies_of(context, *this);
  detail::warm_start_revolute(bodies, {anchor_a_, anchor_b_, separation0_}, impulse_);
}

void FxRevoluteJoint::evaluate(FxConstraintContext& context, bool use_bias) {
  detail::JointBodies bodies = bodies_of(context, *this);
  detail::solve_revolute(bodies, {anchor_a_, anchor_b_, separation0_}, impulse_, pass_params(context),
                         use_bias);
}

}  // namespace fx2d

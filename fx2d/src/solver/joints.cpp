// The constraint base and the two joints Fx2D provides, solved as soft constraints in the same
// passes as contacts. Each joint keeps its anchors relative to the centres of mass at the step's
// start and recovers its current error from the bodies' displacement since then, like contacts.
#include <cmath>
#include <string>

#include "fx2d/Constraint.h"
#include "world/bodies.h"

namespace fx2d {
namespace {

// An anchor or pin as far out as a body may be placed, and no further: beyond that, sums of
// anchors and offsets overflow float.
bool within_world(FxVec2f point) {
  return is_finite(point) && std::fabs(point.x) <= detail::max_coordinate && std::fabs(point.y) <= detail::max_coordinate;
}

struct JointBodies {
  FxBodyState& a;
  FxBodyState& b;
  float inv_mass_a, inv_inertia_a, inv_mass_b, inv_inertia_b;
};

JointBodies bodies_of(FxConstraintContext& context, const FxConstraint& joint) {
  const FxEntity& a = *joint.entity_a();
  const FxEntity& b = *joint.entity_b();
  return {context.state(a), context.state(b), context.inv_mass(a), context.inv_inertia(a), context.inv_mass(b),
          context.inv_inertia(b)};
}

void apply(JointBodies& bodies, FxVec2f anchor_a, FxVec2f anchor_b, FxVec2f impulse) {
  bodies.a.linear_velocity -= bodies.inv_mass_a * impulse;
  bodies.a.angular_velocity -= bodies.inv_inertia_a * cross(anchor_a, impulse);
  bodies.b.linear_velocity += bodies.inv_mass_b * impulse;
  bodies.b.angular_velocity += bodies.inv_inertia_b * cross(anchor_b, impulse);
}

FxVec2f relative_velocity(const JointBodies& bodies, FxVec2f anchor_a, FxVec2f anchor_b) {
  return (bodies.b.linear_velocity + cross(bodies.b.angular_velocity, anchor_b)) -
         (bodies.a.linear_velocity + cross(bodies.a.angular_velocity, anchor_a));
}

// Anchor b minus anchor a now, from where they were at the step's start and how far each body
// moved and turned since.
FxVec2f current_separation(const JointBodies& bodies, FxVec2f separation0, FxVec2f anchor_a0, FxVec2f anchor_b0,
                           FxVec2f anchor_a, FxVec2f anchor_b) {
  return separation0 + (bodies.b.delta_position - bodies.a.delta_position) + (anchor_b - anchor_b0) -
         (anchor_a - anchor_a0);
}

// Anchor offset from the centre of mass, world-aligned, at the step's start.
FxVec2f start_anchor(FxConstraintContext& context, const FxEntity& entity, FxVec2f local_anchor) {
  return rotate(context.start_rotation(entity), local_anchor - context.local_center(entity));
}

// The largest impulse a joint may accumulate: what stops its anchors closing at the fastest speeds
// the bodies may have (K >= ma + mb in every direction, so no rigid solve needs more). Redundant
// joints, such as two pins between one pair of bodies, otherwise trade impulse between themselves
// without limit; once the lever arms turn, that internal impulse becomes real torque and grows
// geometrically from substep to substep.
float max_joint_impulse(const FxConstraintContext& context, const JointBodies& bodies, FxVec2f anchor_a, FxVec2f anchor_b) {
  const float anchor_speed = 2.0f * context.max_linear_speed + context.max_angular_speed * (length(anchor_a) + length(anchor_b));
  return anchor_speed / (bodies.inv_mass_a + bodies.inv_mass_b);
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

FxConstraint::FxConstraint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b) : a_(std::move(a)), b_(std::move(b)) {
  if (!a_ || !b_) throw FxInvalidArgument("FxConstraint: entities: expected two entities, got null");
  if (a_ == b_) throw FxInvalidArgument("FxConstraint: entities: expected two different entities");
  if (a_->type() != FxBodyType::dynamic && b_->type() != FxBodyType::dynamic) {
    throw FxInvalidArgument("FxConstraint: entities: expected at least one dynamic entity");
  }
}

FxDistanceJoint::FxDistanceJoint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b, FxVec2f local_anchor_a,
                                 FxVec2f local_anchor_b, float length)
    : FxConstraint(std::move(a), std::move(b)), local_anchor_a_(local_anchor_a), local_anchor_b_(local_anchor_b), length_(length) {
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
  anchor_a_ = start_anchor(context, *entity_a(), local_anchor_a_);
  anchor_b_ = start_anchor(context, *entity_b(), local_anchor_b_);
  separation0_ = context.center_offset(*entity_a(), *entity_b()) + anchor_b_ - anchor_a_;
}

void FxDistanceJoint::warm_start(FxConstraintContext& context) {
  JointBodies bodies = bodies_of(context, *this);
  const FxVec2f ra = rotate(bodies.a.delta_rotation, anchor_a_);
  const FxVec2f rb = rotate(bodies.b.delta_rotation, anchor_b_);
  const FxVec2f axis = normalize(current_separation(bodies, separation0_, anchor_a_, anchor_b_, ra, rb));
  apply(bodies, ra, rb, impulse_ * axis);
}

void FxDistanceJoint::evaluate(FxConstraintContext& context, bool use_bias) {
  JointBodies bodies = bodies_of(context, *this);
  const FxVec2f ra = rotate(bodies.a.delta_rotation, anchor_a_);
  const FxVec2f rb = rotate(bodies.b.delta_rotation, anchor_b_);
  const FxVec2f separation = current_separation(bodies, separation0_, anchor_a_, anchor_b_, ra, rb);
  const FxVec2f axis = normalize(separation);
  const float cra = cross(ra, axis);
  const float crb = cross(rb, axis);
  const float k = bodies.inv_mass_a + bodies.inv_mass_b + bodies.inv_inertia_a * cra * cra + bodies.inv_inertia_b * crb * crb;
  // No finite effective mass (both ends immovable, or an inverse mass so large that K overflowed):
  // this joint cannot move its bodies, and an impulse from 1/k would not be finite.
  if (!(k > 0.0f && std::isfinite(k))) return;
  float bias = 0.0f;
  float mass_scale = 1.0f;
  float impulse_scale = 0.0f;
  if (use_bias) {
    // Unlike a contact's push-out, a joint's correction is not capped at a speed: its error is the
    // load it carries, and a capped pull lets a chain under a heavy load yield without end. What
    // two joints that cannot both hold do to a body stays bounded by max_joint_impulse and the
    // speed limits.
    const float error = fx2d::length(separation) - length_;
    bias = context.softness.bias_rate * error;
    mass_scale = context.softness.mass_scale;
    impulse_scale = context.softness.impulse_scale;
  }
  const float cdot = dot(relative_velocity(bodies, ra, rb), axis);
  float impulse = -(mass_scale / k) * (cdot + bias) - impulse_scale * impulse_;
  const float max_impulse = max_joint_impulse(context, bodies, ra, rb);
  const float total = impulse_ + impulse;
  if (std::fabs(total) > max_impulse) impulse = std::copysign(max_impulse, total) - impulse_;
  impulse_ += impulse;
  apply(bodies, ra, rb, impulse * axis);
}

FxRevoluteJoint::FxRevoluteJoint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b, FxVec2f world_anchor)
    : FxConstraint(std::move(a), std::move(b)) {
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
  anchor_a_ = start_anchor(context, *entity_a(), local_anchor_a_);
  anchor_b_ = start_anchor(context, *entity_b(), local_anchor_b_);
  separation0_ = context.center_offset(*entity_a(), *entity_b()) + anchor_b_ - anchor_a_;
}

void FxRevoluteJoint::warm_start(FxConstraintContext& context) {
  JointBodies bodies = bodies_of(context, *this);
  apply(bodies, rotate(bodies.a.delta_rotation, anchor_a_), rotate(bodies.b.delta_rotation, anchor_b_), impulse_);
}

void FxRevoluteJoint::evaluate(FxConstraintContext& context, bool use_bias) {
  JointBodies bodies = bodies_of(context, *this);
  const FxVec2f ra = rotate(bodies.a.delta_rotation, anchor_a_);
  const FxVec2f rb = rotate(bodies.b.delta_rotation, anchor_b_);
  FxVec2f bias;
  float mass_scale = 1.0f;
  float impulse_scale = 0.0f;
  if (use_bias) {
    // Not capped at a speed, like the distance joint.
    bias = context.softness.bias_rate * current_separation(bodies, separation0_, anchor_a_, anchor_b_, ra, rb);
    mass_scale = context.softness.mass_scale;
    impulse_scale = context.softness.impulse_scale;
  }
  // The point constraint's 2x2 effective-mass matrix K = J M^-1 J^T = m I + ia u u^T + ib v v^T,
  // with m = ma + mb, u and v the anchors turned a quarter. Its determinant is taken in the form
  // m^2 + m (ia |u|^2 + ib |v|^2) + ia ib (u x v)^2, a sum of non-negative terms: the textbook
  // k00 k11 - k01^2 cancels catastrophically for a pin far from a light body, and a determinant
  // made of rounding noise inverts into impulses that feed energy in.
  const float ma = bodies.inv_mass_a, mb = bodies.inv_mass_b, ia = bodies.inv_inertia_a, ib = bodies.inv_inertia_b;
  const float m = ma + mb;
  const float k00 = m + ra.y * ra.y * ia + rb.y * rb.y * ib;
  const float k01 = -ra.y * ra.x * ia - rb.y * rb.x * ib;
  const float k11 = m + ra.x * ra.x * ia + rb.x * rb.x * ib;
  const float anchors_cross = cross(ra, rb);
  const float determinant = m * m + m * (ia * length_squared(ra) + ib * length_squared(rb)) + ia * ib * anchors_cross * anchors_cross;
  // No finite impulse exists when K is singular or overflowed: this pass leaves the bodies alone.
  if (!(determinant > 0.0f && std::isfinite(determinant))) return;
  const FxVec2f cdot = relative_velocity(bodies, ra, rb) + bias;
  const float inv_determinant = 1.0f / determinant;
  const FxVec2f solved = {inv_determinant * (k11 * cdot.x - k01 * cdot.y), inv_determinant * (k00 * cdot.y - k01 * cdot.x)};
  FxVec2f impulse = -mass_scale * solved - impulse_scale * impulse_;
  const float max_impulse = max_joint_impulse(context, bodies, ra, rb);
  const FxVec2f total = impulse_ + impulse;
  const float total_length = length(total);
  if (total_length > max_impulse) impulse = (max_impulse / total_length) * total - impulse_;
  impulse_ += impulse;
  apply(bodies, ra, rb, impulse);
}

}  // namespace fx2d

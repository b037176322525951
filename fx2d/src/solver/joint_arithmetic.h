// The arithmetic of the two joints Fx2D provides, one function per joint and pass: the public
// classes (joints.cpp), which reach their bodies through an FxConstraintContext, and the step's
// joint rows (joint_rows.h), which reach them by index, both call these, so the two agree to the
// bit. Each joint keeps its anchors relative to the centres of mass at the step's start and
// recovers its current error from the bodies' displacement since then, like contacts.
#pragma once

#include <cmath>
#include <cstdint>

#include "fx2d/Constraint.h"

namespace fx2d::detail {

// A joint's two bodies: their solver states and their inverse masses.
struct JointBodies {
  FxBodyState& a;
  FxBodyState& b;
  float inv_mass_a, inv_inertia_a, inv_mass_b, inv_inertia_b;
};

// What a pass needs besides the joint and its bodies.
struct JointPassParams {
  FxSoftness softness;
  float max_linear_speed;   // m/s
  float max_angular_speed;  // rad/s
};

// Where a joint stands at the step's start: its anchors relative to the centres of mass,
// world-aligned, and anchor b minus anchor a.
struct JointFrame {
  FxVec2f anchor_a, anchor_b;
  FxVec2f separation0;
};

// A body-local anchor as an offset from the centre of mass, world-aligned, at the step's start.
inline FxVec2f start_anchor(FxRot start_rotation, FxVec2f local_center, FxVec2f local_anchor) {
  return rotate(start_rotation, local_anchor - local_center);
}

inline JointFrame joint_frame(FxVec2f anchor_a, FxVec2f anchor_b, FxVec2f center_offset) {
  return {anchor_a, anchor_b, center_offset + anchor_b - anchor_a};
}

// One of the step's constraints as JointRows keeps it: a joint Fx2D provides as a plain record of
// its bodies' state indices and inverse masses, its frame and its impulse; a user's by kind alone.
enum class JointKind : std::uint8_t { user, distance_joint, revolute_joint };
struct JointRow {
  JointKind kind;
  std::uint32_t a, b;  // states
  float inv_mass_a, inv_inertia_a, inv_mass_b, inv_inertia_b;
  JointFrame frame;
  FxVec2f impulse;     // a distance joint's in x
  float length;        // a distance joint's rest length
  float within_limit;  // impulse_surely_within_limit()
};

inline void apply_joint_impulse(JointBodies& bodies, FxVec2f anchor_a, FxVec2f anchor_b, FxVec2f impulse) {
  bodies.a.linear_velocity -= bodies.inv_mass_a * impulse;
  bodies.a.angular_velocity -= bodies.inv_inertia_a * cross(anchor_a, impulse);
  bodies.b.linear_velocity += bodies.inv_mass_b * impulse;
  bodies.b.angular_velocity += bodies.inv_inertia_b * cross(anchor_b, impulse);
}

inline FxVec2f anchors_relative_velocity(const JointBodies& bodies, FxVec2f anchor_a, FxVec2f anchor_b) {
  return (bodies.b.linear_velocity + cross(bodies.b.angular_velocity, anchor_b)) -
         (bodies.a.linear_velocity + cross(bodies.a.angular_velocity, anchor_a));
}

// Anchor b minus anchor a now, from where they were at the step's start and how far each body
// moved and turned since.
inline FxVec2f current_separation(const JointBodies& bodies, const JointFrame& frame, FxVec2f anchor_a,
                                  FxVec2f anchor_b) {
  return frame.separation0 + (bodies.b.delta_position - bodies.a.delta_position) +
         (anchor_b - frame.anchor_b) - (anchor_a - frame.anchor_a);
}

// The fastest a joint's anchors may close at, given the speed limits. A joint's accumulated impulse
// is held within this speed over ma + mb, what stops them (K >= ma + mb in every direction, so no
// rigid solve needs more). Redundant joints, such as two pins between one pair of bodies, otherwise
// trade impulse between themselves without limit; once the lever arms turn, that internal impulse
// becomes real torque and grows geometrically from substep to substep.
inline float max_anchor_speed(const JointPassParams& params, FxVec2f anchor_a, FxVec2f anchor_b) {
  return 2.0f * params.max_linear_speed + params.max_angular_speed * (length(anchor_a) + length(anchor_b));
}

// An accumulated impulse below which that limit surely does not bind for the whole step, or
// 0: the anchors turn within the step but keep their lengths to rounding, and a thousandth under
// the limit at their lengths at the step's start covers that. Below it the clamp is skipped, with
// its three square roots and a division, and the bits are those of taking it.
inline float impulse_surely_within_limit(const JointPassParams& params, float inv_mass_sum,
                                         const JointFrame& frame) {
  return 0.999f * (max_anchor_speed(params, frame.anchor_a, frame.anchor_b) / inv_mass_sum);
}

// The unit axis from anchor a to anchor b (normalize(), branch-free: zero where the anchors nearly
// coincide) and the distance between them.
struct RodAxis {
  FxVec2f axis;
  float length;
};

inline RodAxis rod_axis(FxVec2f separation) {
  const float distance = length(separation);
  const float inverse = 1.0f / distance;
  const bool apart = !(distance < 1.0e-12f);
  // Chosen coordinate by coordinate: a choice of whole vectors is one Clang's loop vectoriser refuses.
  return {{apart ? inverse * separation.x : 0.0f, apart ? inverse * separation.y : 0.0f}, distance};
}

inline void warm_start_distance(JointBodies& bodies, const JointFrame& frame, float impulse) {
  const FxVec2f ra = rotate(bodies.a.delta_rotation, frame.anchor_a);
  const FxVec2f rb = rotate(bodies.b.delta_rotation, frame.anchor_b);
  const FxVec2f axis = rod_axis(current_separation(bodies, frame, ra, rb)).axis;
  apply_joint_impulse(bodies, ra, rb, impulse * axis);
}

// A rod's effective mass K along its axis (as 1/K it turns a closing speed into an impulse), and
// whether K is finite: both ends immovable, or an inverse mass so large that K overflowed, leave
// none, and an impulse from 1/K would not be finite. Branch-free, so that a loop over eight rods
// vectorises (joint_batches.cpp).
inline float rod_mass(FxVec2f ra, FxVec2f rb, FxVec2f axis, float ma, float mb, float ia, float ib) {
  const float cra = cross(ra, axis);
  const float crb = cross(rb, axis);
  return ma + mb + ia * cra * cra + ib * crb * crb;
}

inline bool rod_solvable(float k) { return (k > 0.0f) & (k <= 3.40282347e+38f); }

// The impulse along a rod's axis that takes the anchors' closing speed `cdot` plus `bias` to zero,
// softened, before it is clamped.
inline float rod_impulse(float k, float cdot, float bias, float mass_scale, float impulse_scale,
                         float accumulated) {
  return -(mass_scale / k) * (cdot + bias) - impulse_scale * accumulated;
}

// The impulse a rod applies once its accumulated total is held within max_anchor_speed over
// ma + mb.
inline float clamped_rod_impulse(float impulse, float accumulated, float anchor_speed, float inv_mass_sum) {
  const float total = accumulated + impulse;
  const float max_impulse = anchor_speed / inv_mass_sum;
  return std::fabs(total) > max_impulse ? std::copysign(max_impulse, total) - accumulated : impulse;
}

// One pass of a rod of `rest_length` between the anchors: soft (use_bias) or rigid.
inline void solve_distance(JointBodies& bodies, const JointFrame& frame, float rest_length,
                           float& accumulated, const JointPassParams& params, bool use_bias,
                           float within_limit = 0.0f) {
  const FxVec2f ra = rotate(bodies.a.delta_rotation, frame.anchor_a);
  const FxVec2f rb = rotate(bodies.b.delta_rotation, frame.anchor_b);
  const RodAxis rod = rod_axis(current_separation(bodies, frame, ra, rb));
  float bias = 0.0f;
  float mass_scale = 1.0f;
  float impulse_scale = 0.0f;
  if (use_bias) {
    // Unlike a contact's push-out, a joint's correction is not capped at a speed: its error is the
    // load it carries, and a capped pull lets a chain under a heavy load yield without end. What
    // two joints that cannot both hold do to a body stays bounded by the clamp and the speed limits.
    bias = params.softness.bias_rate * (rod.length - rest_length);
    mass_scale = params.softness.mass_scale;
    impulse_scale = params.softness.impulse_scale;
  }
  const float k = rod_mass(ra, rb, rod.axis, bodies.inv_mass_a, bodies.inv_mass_b, bodies.inv_inertia_a,
                           bodies.inv_inertia_b);
  // This pass leaves the bodies alone.
  if (!rod_solvable(k)) return;
  float impulse = rod_impulse(k, dot(anchors_relative_velocity(bodies, ra, rb), rod.axis), bias, mass_scale,
                              impulse_scale, accumulated);
  if (!(std::fabs(accumulated + impulse) < within_limit)) {
    impulse = clamped_rod_impulse(impulse, accumulated, max_anchor_speed(params, ra, rb),
                                  bodies.inv_mass_a + bodies.inv_mass_b);
  }
  accumulated += impulse;
  apply_joint_impulse(bodies, ra, rb, impulse * rod.axis);
}

inline void warm_start_revolute(JointBodies& bodies, const JointFrame& frame, FxVec2f impulse) {
  apply_joint_impulse(bodies, rotate(bodies.a.delta_rotation, frame.anchor_a),
                      rotate(bodies.b.delta_rotation, frame.anchor_b), impulse);
}

// What one pass of a pin works out before its impulse is clamped and applied: the impulse that
// takes the anchors' relative velocity `cdot` (bias included) to zero through the point
// constraint's 2x2 effective-mass matrix, softened, and whether that matrix could be inverted.
// Branch-free, so that a loop over eight pins vectorises (joint_batches.cpp).
struct PinImpulse {
  FxVec2f impulse;
  bool solvable;
};

inline PinImpulse pin_impulse(FxVec2f ra, FxVec2f rb, float ma, float mb, float ia, float ib, FxVec2f cdot,
                              float mass_scale, float impulse_scale, FxVec2f accumulated) {
  // K = J M^-1 J^T = m I + ia u u^T + ib v v^T, with m = ma + mb, u and v the anchors turned a
  // quarter. Its determinant is taken in the form m^2 + m (ia |u|^2 + ib |v|^2) + ia ib (u x v)^2,
  // a sum of non-negative terms: the textbook k00 k11 - k01^2 cancels catastrophically for a pin
  // far from a light body, and a determinant made of rounding noise inverts into impulses that
  // feed energy in.
  const float m = ma + mb;
  const float k00 = m + ra.y * ra.y * ia + rb.y * rb.y * ib;
  const float k01 = -ra.y * ra.x * ia - rb.y * rb.x * ib;
  const float k11 = m + ra.x * ra.x * ia + rb.x * rb.x * ib;
  const float anchors_cross = cross(ra, rb);
  const float determinant = m * m + m * (ia * length_squared(ra) + ib * length_squared(rb)) +
                            ia * ib * anchors_cross * anchors_cross;
  // No finite impulse exists when K is singular or overflowed (> FLT_MAX is infinite).
  // Both comparisons taken, so that a lane loop needs no branch.
  const bool solvable = (determinant > 0.0f) & (determinant <= 3.40282347e+38f);
  const float inv_determinant = 1.0f / determinant;
  const FxVec2f solved = {inv_determinant * (k11 * cdot.x - k01 * cdot.y),
                          inv_determinant * (k00 * cdot.y - k01 * cdot.x)};
  return {-mass_scale * solved - impulse_scale * accumulated, solvable};
}

// The impulse a pin applies once its accumulated total is held within the speed its anchors may
// close at, `anchor_speed` (max_anchor_speed()), over ma + mb.
inline FxVec2f clamped_pin_impulse(FxVec2f impulse, FxVec2f accumulated, float anchor_speed,
                                   float inv_mass_sum) {
  const FxVec2f total = accumulated + impulse;
  const float max_impulse = anchor_speed / inv_mass_sum;
  const float total_length = length(total);
  return total_length > max_impulse ? (max_impulse / total_length) * total - accumulated : impulse;
}

// One pass of a pin between the anchors: soft (use_bias) or rigid.
inline void solve_revolute(JointBodies& bodies, const JointFrame& frame, FxVec2f& accumulated,
                           const JointPassParams& params, bool use_bias, float within_limit = 0.0f) {
  const FxVec2f ra = rotate(bodies.a.delta_rotation, frame.anchor_a);
  const FxVec2f rb = rotate(bodies.b.delta_rotation, frame.anchor_b);
  FxVec2f bias;
  float mass_scale = 1.0f;
  float impulse_scale = 0.0f;
  if (use_bias) {
    // Not capped at a speed, like the distance joint.
    bias = params.softness.bias_rate * current_separation(bodies, frame, ra, rb);
    mass_scale = params.softness.mass_scale;
    impulse_scale = params.softness.impulse_scale;
  }
  const PinImpulse pin =
      pin_impulse(ra, rb, bodies.inv_mass_a, bodies.inv_mass_b, bodies.inv_inertia_a, bodies.inv_inertia_b,
                  anchors_relative_velocity(bodies, ra, rb) + bias, mass_scale, impulse_scale, accumulated);
  // This pass leaves the bodies alone.
  if (!pin.solvable) return;
  FxVec2f impulse = pin.impulse;
  if (!(length_squared(accumulated + impulse) < within_limit * within_limit)) {
    impulse = clamped_pin_impulse(impulse, accumulated, max_anchor_speed(params, ra, rb),
                                  bodies.inv_mass_a + bodies.inv_mass_b);
  }
  accumulated += impulse;
  apply_joint_impulse(bodies, ra, rb, impulse);
}

}  // namespace fx2d::detail

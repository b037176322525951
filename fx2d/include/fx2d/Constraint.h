// User constraints between two entities, solved in the same passes as the contacts.
//
// A constraint sees the bodies through FxConstraintContext, which exposes the solver's own body
// state: velocities, and the position and rotation moved since the step began. Positions are kept
// relative within a step so that constraints between bodies far from the origin lose no
// precision. For a user's own constraint the solver calls, per step: prepare() once (where a
// constraint that warm starts scales its kept impulse by the context's impulse_ratio); then per
// substep warm_start() once and evaluate() once per velocity pass with use_bias (correct position
// error) and once without it in each of the first FxSceneSettings::joint_relax_passes relaxation
// passes. The joints Fx2D provides it solves itself, with the same arithmetic, making no virtual
// call per pass: the revolute joints first, coloured so that no two of a colour share a moving
// body and solved eight at a time, colour by colour; then the distance joints likewise; then the
// user's constraints (and any joint beyond 32 colours around one body) in the order they were
// added. Their own prepare(), warm_start() and evaluate() serve a user's solver, or a constraint of
// the user's that hands its calls on to one of them.
//
// Two entities joined by a constraint never collide with each other.
//
// Subclass FxConstraint for a new joint; FxDistanceJoint and FxRevoluteJoint are provided.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>

#include "fx2d/Entity.h"
#include "fx2d/Math.h"

namespace fx2d {
namespace detail {
class JointRows;
}

// The solver's per-body state during a step. Hot: every velocity pass reads and writes it. Aligned
// to its size, so that each state lies in one cache line: from the 16-byte alignment malloc gives,
// every other state straddled two wherever the array happened to start 16 bytes off, and two
// builds of the same code differed by that alone (the relax stage 0.81-0.83 of the time once
// aligned, settling_boxes and stacks at 50 bodies).
struct alignas(32) FxBodyState {
  FxVec2f linear_velocity;   // m/s of the centre of mass
  float angular_velocity = 0.0f;
  std::uint32_t flags = 0;   // reserved for the solver
  FxVec2f delta_position;    // centre-of-mass displacement since the step began (metres)
  FxRot delta_rotation;      // rotation since the step began
};
static_assert(sizeof(FxBodyState) == 32, "FxBodyState is the hot record: keep it at 32 bytes");

// Softness of a constraint: how a position error is fed back as velocity (see Catto, "Solver2D",
// 2024: soft step). Derived from a stiffness in hertz and a damping ratio for the substep.
struct FxSoftness {
  float bias_rate = 0.0f;      // 1/s: velocity bias per metre of error
  float mass_scale = 1.0f;     // scales the effective mass
  float impulse_scale = 0.0f;  // feeds back the accumulated impulse
};
FxSoftness make_softness(float hertz, float damping_ratio, float substep_dt);

// An impulse kept from the last step for warm starting, as a substep impulse_ratio times as long
// needs it (FxConstraintContext::impulse_ratio): scaled, or 0 where scaling overflows.
inline float fx_carried_impulse(float impulse, float impulse_ratio) {
  const float carried = impulse * impulse_ratio;
  return std::isfinite(carried) ? carried : 0.0f;
}

class FxConstraintContext {
 public:
  virtual ~FxConstraintContext() = default;
  virtual FxBodyState& state(const FxEntity& entity) = 0;
  virtual float inv_mass(const FxEntity& entity) const = 0;
  virtual float inv_inertia(const FxEntity& entity) const = 0;
  // Rotation at the start of the step (current rotation: mul(state.delta_rotation, this)).
  virtual FxRot start_rotation(const FxEntity& entity) const = 0;
  // b's centre of mass minus a's at the start of the step, computed to twice float precision.
  virtual FxVec2f center_offset(const FxEntity& a, const FxEntity& b) const = 0;
  virtual FxVec2f local_center(const FxEntity& entity) const = 0;

  float substep_dt = 0.0f;      // seconds
  // substep_dt over the last step's (1 for the first step, and while dt and substeps stay): an
  // impulse kept from the last step for warm starting was a substep's, and is scaled by it in
  // prepare() (fx_carried_impulse), so that a joint bearing a load bears it through a change of the
  // substep length.
  float impulse_ratio = 1.0f;
  float inv_substep_dt = 0.0f;  // 1/s
  FxSoftness softness;          // joint softness for this substep
  float max_linear_speed = 0.0f;   // m/s, the scene's speed limit for any body
  float max_angular_speed = 0.0f;  // rad/s, the scene's spin limit for any body
};

class FxConstraint {
 public:
  // Both entities must be in the same scene and at least one must be dynamic.
  FxConstraint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b);
  virtual ~FxConstraint() = default;

  virtual void prepare(FxConstraintContext& context) = 0;
  virtual void warm_start(FxConstraintContext& context) = 0;
  virtual void evaluate(FxConstraintContext& context, bool use_bias) = 0;

  const std::shared_ptr<FxEntity>& entity_a() const { return a_; }
  const std::shared_ptr<FxEntity>& entity_b() const { return b_; }

 private:
  friend class FxDistanceJoint;
  friend class FxRevoluteJoint;
  friend class detail::JointRows;
  // Which joint Fx2D provides this is, if any: the step solves those itself, with no virtual call
  // per pass, and calls prepare(), warm_start() and evaluate() only on a user's own constraints.
  enum class Provided : std::uint8_t { none, distance_joint, revolute_joint };
  FxConstraint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b, Provided provided);

  std::shared_ptr<FxEntity> a_;
  std::shared_ptr<FxEntity> b_;
  Provided provided_;
};

// Keeps two anchor points at a fixed distance (a rigid rod).
class FxDistanceJoint final : public FxConstraint {
 public:
  // Anchors are body-local metres; length (metres, >= 0) < 0 means "the current distance".
  FxDistanceJoint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b, FxVec2f local_anchor_a,
                  FxVec2f local_anchor_b, float length = -1.0f);
  float length() const { return length_; }
  // Distance between the anchors now (metres).
  float current_length() const;

  void prepare(FxConstraintContext& context) override;
  void warm_start(FxConstraintContext& context) override;
  void evaluate(FxConstraintContext& context, bool use_bias) override;

 private:
  friend class detail::JointRows;
  FxVec2f local_anchor_a_, local_anchor_b_;
  float length_;
  // Per-step solver data.
  FxVec2f anchor_a_, anchor_b_;   // anchors relative to the centres of mass, world-aligned
  FxVec2f separation0_;           // anchor b minus anchor a at the start of the step
  float impulse_ = 0.0f;
};

// Pins two bodies together at a shared point; they may rotate freely about it.
class FxRevoluteJoint final : public FxConstraint {
 public:
  // world_anchor: the pin, world metres, taken at construction.
  FxRevoluteJoint(std::shared_ptr<FxEntity> a, std::shared_ptr<FxEntity> b, FxVec2f world_anchor);
  // Distance between the two bodies' copies of the pin (metres): 0 for a perfect joint.
  float anchor_gap() const;

  void prepare(FxConstraintContext& context) override;
  void warm_start(FxConstraintContext& context) override;
  void evaluate(FxConstraintContext& context, bool use_bias) override;

 private:
  friend class detail::JointRows;
  FxVec2f local_anchor_a_, local_anchor_b_;
  FxVec2f anchor_a_, anchor_b_;
  FxVec2f separation0_;
  FxVec2f impulse_;
};

}  // namespace fx2d

// The scene's bodies, stored packed in creation order and split by who reads them: BodyRecord is
// cold (what the organiser needs: type, shape, material, proxy, contact list, sleep state) and
// BodySim is warm (pose and velocity between steps, what integration and the narrow phase read).
// The hot 32-byte FxBodyState the velocity passes touch is gathered per step by the solver
// (solver_stages.h).
//
// Invariant: records and sims are indexed by packed index and have one entry per body; removal
// compacts both in one pass, preserving order, and remaps every stored index (entity.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "collision/aabb_tree.h"
#include "fx2d/Constraint.h"
#include "fx2d/Entity.h"
#include "world/speed_limits.h"

namespace fx2d::detail {

// Its fields that every step scans (type, flags, proxy, contact list) first, in the record's first
// cache line ahead of the 152-byte shape, changed nothing: settling_boxes 800's step 1.003
// [0.992, 1.008] (`ab`, sleeping off; every stage within 0.5%). Nor did the narrow phase reading,
// per pair, a compact row per body (its fat box and whether it is active) copied once a step from
// the records and the tree: collide 1.037 [1.022, 1.046] on settling_boxes 800, 1.056 on pile 800.
struct BodyRecord {
  std::shared_ptr<FxEntity> handle;
  FxShape shape;
  FxMaterial material;
  FxBodyType type = FxBodyType::dynamic;
  bool can_sleep = true;
  bool awake = true;
  bool moved = false;          // its proxy moved this step: search it for new pairs
  bool bullet = false;         // swept against fast dynamic bodies too (continuous.h)
  float mass = 0.0f;
  float rotational_inertia = 0.0f;
  float linear_damping = 0.0f;
  float angular_damping = 0.0f;
  float sleep_time = 0.0f;     // seconds it has been resting
  float rest_start_speed = 0.0f;  // m/s, its speed when it began to rest (body_integration.cpp)
  int proxy = AabbTree::null_node;
  int fixed_proxy = AabbTree::null_node;  // a static or kinematic body's proxy in BroadPhase::fixed_tree
  int contact_head = -1;       // first contact edge touching this body (contact_cache.h)
  int sleep_island = -1;       // while asleep: the packed index that named its island
};

struct BodySim {
  FxVec2f origin;              // body origin; the precise value is origin - carry
  FxVec2f carry;
  FxRot rotation;
  FxVec2f local_center;        // centre of mass in the body frame
  FxVec2f linear_velocity;     // of the centre of mass
  float angular_velocity = 0.0f;
  float inv_mass = 0.0f;
  float inv_inertia = 0.0f;
  FxVec2f force;               // accumulated by apply_force(), cleared by the step
  FxAABB aabb;                 // tight bounds at the current pose
  // For the continuous stage, which reads them for every moving body each step (continuous.h):
  // how far the body's farthest point lies from its centre of mass, and the motion in a step
  // beyond which it is swept (infinite for a body that never is: a kinematic one).
  float reach = 0.0f;
  float fast_motion = 0.0f;
  // The radius of the circle about the centre of mass that holds the shape: the narrow phase's
  // test of pairs apart (narrow_phase.cpp) reads it with the pose, rather than the record's shape.
  float enclosing_radius = 0.0f;
};

// What a removed entity's handle keeps of its body.
struct Snapshot {
  BodyRecord record;
  BodySim sim;
};

struct Bodies {
  std::vector<BodyRecord> records;
  std::vector<BodySim> sims;
  // How many records are awake (a static body never is): at zero, a step skips every per-pair and
  // per-body loop (the broad phase's too, once it has taken the last awake step's moves: its
  // may_have_moved). Kept where `awake` changes: creation, removal, sleep.cpp.
  std::uint32_t awake_count = 0;

  std::uint32_t count() const { return static_cast<std::uint32_t>(records.size()); }

  // b's origin minus a's, to twice float precision (the carries included).
  FxVec2f origin_offset(std::uint32_t a, std::uint32_t b) const {
    const BodySim& sa = sims[a];
    const BodySim& sb = sims[b];
    return (sb.origin - sa.origin) - (sb.carry - sa.carry);
  }
  // b's centre of mass minus a's, to twice float precision.
  FxVec2f center_offset(std::uint32_t a, std::uint32_t b) const {
    const BodySim& sa = sims[a];
    const BodySim& sb = sims[b];
    return origin_offset(a, b) + rotate(sb.rotation, sb.local_center) - rotate(sa.rotation, sa.local_center);
  }
};

// The user constraints (joints) between bodies, in the order they were added.
using Constraints = std::vector<std::shared_ptr<FxConstraint>>;

// Positions beyond this (metres) are refused: float spacing there is already a metre.
inline constexpr float max_coordinate = 1.0e7f;

// Clamps a body's velocity to the speed limits.
inline void clamp_velocity(SpeedLimits limits, BodySim& sim) {
  sim.linear_velocity = limited_speed(sim.linear_velocity, limits.max_speed);
  sim.angular_velocity = limited_spin(sim.angular_velocity, limits.max_spin);
}
// Clamps a body's velocity to the scene's linear and angular speed limits.
inline void clamp_velocity(const FxSceneSettings& settings, BodySim& sim) {
  clamp_velocity(SpeedLimits{settings.max_linear_speed, max_angular_speed(settings)}, sim);
}

}  // namespace fx2d::detail

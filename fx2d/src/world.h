// The scene's storage and the step's stages.
//
// Bodies are stored packed, in creation order, split by who reads them: BodyRecord is cold (what
// the organiser needs: type, shape, material, proxy, contact list, sleep state), BodySim is warm
// (pose and velocity between steps, what integration and the narrow phase read), and FxBodyState
// is the hot 32-byte record the velocity passes touch, gathered once per step into `states`
// (which has one extra, always-zero slot that padding lanes of contact batches point at).
// Invariant: every body array is indexed by packed index and has entity_count() entries; removal
// compacts them all in one pass, preserving order, and remaps every stored index.
//
// The step is a fixed sequence of stage functions (scene.cpp); each is timed as one FxStage.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "aabb_tree.h"
#include "body_integration.h"
#include "contact_batch.h"
#include "contact_cache.h"
#include "contact_graph.h"
#include "contact_solver.h"
#include "fx2d/Constraint.h"
#include "fx2d/Entity.h"
#include "fx2d/Profile.h"
#include "fx2d/Scene.h"
#include "profile_timer.h"

namespace fx2d::detail {

struct StepContext;

struct BodyRecord {
  std::shared_ptr<FxEntity> handle;
  FxShape shape;
  FxMaterial material;
  FxBodyType type = FxBodyType::dynamic;
  bool can_sleep = true;
  bool awake = true;
  bool moved = false;          // its proxy moved this step: search it for new pairs
  float mass = 0.0f;
  float rotational_inertia = 0.0f;
  float linear_damping = 0.0f;
  float angular_damping = 0.0f;
  float sleep_time = 0.0f;     // seconds it has been resting
  int proxy = AabbTree::null_node;
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
};

struct Snapshot {
  BodyRecord record;
  BodySim sim;
};

// How fast two bodies could close within the step, for their speculative margin (narrow_phase.cpp).
struct PairMotion {
  FxVec2f velocity_a, velocity_b;
  float spin_speed;  // what the spins add at the shapes' extents
  float fastest_closing() const;                 // along any direction
  float closing_along(FxVec2f normal) const;     // along `normal`, from A towards B
};

class World final {
 public:
  explicit World(const FxSceneSettings& settings);
  ~World();

  // Entities.
  std::shared_ptr<FxEntity> create_entity(const FxEntityDef& def);
  void remove_entity(std::uint32_t index);
  void wake_body(std::uint32_t index);
  void refresh_aabb(std::uint32_t index);
  void reserve_scratch();
  std::uint32_t index_of(const FxEntity& entity) const;

  // Constraints.
  void add_constraint(std::shared_ptr<FxConstraint> constraint);
  void remove_constraint(const FxConstraint& constraint);

  void step();

  // Step stages, in order.
  void update_broad_phase();
  void rebuild_jointed_pairs();
  void create_contact(std::uint32_t a, std::uint32_t b);
  bool jointed(std::uint32_t a, std::uint32_t b) const;
  void update_contacts();
  void prepare_solver(const StepContext& step);
  void solve_substeps(const StepContext& step);
  void solve_positions();
  void finalize_bodies();
  void update_sleep();

  PairMotion pair_motion(std::uint32_t a, std::uint32_t b) const;
  // b's origin minus a's, to twice float precision (the carries included).
  FxVec2f origin_offset(std::uint32_t a, std::uint32_t b) const;
  FxVec2f center_offset(std::uint32_t a, std::uint32_t b) const;

  FxSceneSettings settings;
  std::vector<BodyRecord> records;
  std::vector<BodySim> sims;
  std::vector<FxBodyState> states;
  std::vector<std::shared_ptr<FxConstraint>> constraints;
  // Pairs (a << 32 | b, a < b) joined by a constraint, sorted: they never collide.
  std::vector<std::uint64_t> jointed_pairs;
  bool jointed_pairs_dirty = false;

  AabbTree tree;
  std::vector<std::uint32_t> body_of_proxy;  // proxy id -> packed index
  ContactCache contacts;
  ContactSolver solver;
  FxContactGraph contact_graph;
  ContactBatches contact_batches;
  std::vector<std::uint8_t> movable;  // per body (and the padding slot): can a contact change its state?

  std::function<void(FxScene&)> step_callback;
  FxScene* owner = nullptr;
  FxProfile profile;
  std::uint64_t step_index = 0;
  bool stepping = false;

  // Scratch reused every step, so a step allocates nothing once these have grown.
  std::vector<std::uint32_t> moved_bodies;
  std::vector<std::uint64_t> new_pairs;  // (moved body << 32 | other body) of each pair found this step
  BodyIntegration integration;  // the awake moving bodies, for the substep loops
  std::vector<int> island_parent;
  std::vector<float> island_min_sleep_time;
  std::size_t reserved_bodies = 0;
};

// Positions beyond this (metres) are refused: float spacing there is already a metre.
inline constexpr float max_coordinate = 1.0e7f;

// A quarter turn per substep: faster spin cannot be represented by the rotation integration.
inline float max_angular_speed(const FxSceneSettings& settings) {
  return 0.25f * 3.14159265f * static_cast<float>(settings.substeps) / settings.dt;
}

// The rare case of limited_speed: `v` is faster than `max_speed`, or overflowed, or NaN.
FxVec2f slowed_to(FxVec2f v, float max_speed);

// `v` scaled down to `max_speed` when it is faster; finite whatever `v` is, even infinite or NaN.
// Inline, with the rare case out of line: the substep loops call it for every body twice.
inline FxVec2f limited_speed(FxVec2f v, float max_speed) {
  return length_squared(v) <= max_speed * max_speed ? v : slowed_to(v, max_speed);
}

// `w` clamped to +-max_spin; a NaN spin becomes 0.
inline float limited_spin(float w, float max_spin) { return std::isnan(w) ? 0.0f : std::clamp(w, -max_spin, max_spin); }

// Clamps a body's velocity to the scene's linear and angular speed limits, so that no push,
// however large, can turn a finite state into an infinite one.
void clamp_velocity(const FxSceneSettings& settings, BodySim& sim);

// A proxy's fat box: the tight box enlarged by a margin and swept by one step's displacement.
FxAABB fat_box_for(const FxAABB& tight, FxVec2f displacement);

// Throws FxInvalidArgument unless every setting is in range.
void validate_settings(const FxSceneSettings& settings);

}  // namespace fx2d::detail

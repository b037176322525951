// Contact constraints for one step: soft sequential impulses on the normal and friction rows.
//
// prepare() copies everything a velocity pass needs (body indices, inverse masses, anchors,
// effective masses, the resolved friction) into one contiguous array, so that the substep loop
// touches no body record and no cache entry. Anchors are taken relative to the centres of mass
// at the step's start, and the current separation is recovered from the bodies' displacement
// since then, so contacts are solved without re-running collision in every substep (Catto,
// "Solver2D", 2024: soft step with relaxation). That separation is measured along the normal as
// turned with the body whose face it is (NormalFrame): a box that turns 0.2 rad within the step
// tilts its face under the other body's corner, and measured along the normal fixed at the step's
// start that corner sank 17 mm in (solver_test's BoxSpinningOntoABoxDoesNotSinkItsCornerIn).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "collision/collide.h"
#include "fx2d/Constraint.h"
#include "world/tasks.h"

namespace fx2d::detail {

struct Bodies;
class ContactCache;

struct ContactPointConstraint {
  FxVec2f anchor_a;               // contact point minus centre of mass a, at the step's start
  FxVec2f anchor_b;
  float adjusted_separation = 0;  // separation less the anchors' offset along the normal
  float normal_mass = 0;
  float tangent_mass = 0;
  float normal_impulse = 0;
  float tangent_impulse = 0;
  float max_normal_impulse = 0;   // largest impulse of the step: did this point ever push?
  float relative_velocity = 0;    // normal velocity before the step, for restitution
};

struct ContactConstraint {
  std::uint32_t body_a = 0;
  std::uint32_t body_b = 0;
  int cache_id = 0;
  int point_count = 0;
  FxVec2f normal;
  NormalFrame normal_frame = NormalFrame::world;  // the body the normal turns with
  float inv_mass_a = 0, inv_inertia_a = 0;
  float inv_mass_b = 0, inv_inertia_b = 0;
  float friction = 0;
  float restitution = 0;
  ContactPointConstraint points[2];
};

struct ContactSolveParams {
  FxSoftness softness;
  float inv_substep_dt = 0;
  float max_push_speed = 0;
  // The fastest the soft passes' spring pushes an overlap apart through the velocities; push()
  // moves what lies deeper than linear_slop apart through the positions, at up to max_push_speed.
  float max_spring_speed = 0;
  float linear_slop = 0;
};

// Constraints per range of a prepare() spread over the workers, and the fewest touching contacts
// worth spreading it for (measured: see fx2d/src/README.md).
inline constexpr std::uint32_t constraints_per_block = 64;
inline constexpr std::uint32_t min_parallel_constraints = 128;

class ContactSolver {
 public:
  // Grows storage for this many constraints, so prepare() does not allocate up to there.
  void reserve(std::size_t constraint_count);
  // Builds one constraint per touching contact that has an awake body, in contact cache order;
  // the constraints' arithmetic spread over `tasks` when there are enough.
  void prepare(const ContactCache& contacts, const Bodies& bodies, const Tasks& tasks);
  // After the substeps: bounce where an approaching point pushed and restitution is > 0.
  void apply_restitution(std::span<FxBodyState> states, float threshold);
  // Non-linear Gauss-Seidel projection of overlaps deeper than the slop, on positions only.
  void project_positions(std::span<FxBodyState> states, float linear_slop) const;
  void store_impulses(ContactCache& cache) const;

  std::vector<ContactConstraint> constraints;

 private:
  std::vector<int> sources_;  // per constraint, its contact's cache id (a spread prepare() only)
};

}  // namespace fx2d::detail

// Contact constraints for one step: soft sequential impulses on the normal and friction rows.
//
// prepare() lists the contacts that become constraints this step (ConstraintSource), in contact
// cache order; the constraints' values are then worked out straight into their lanes of the
// eight-lane batches (ContactBatches::pack, contact_packing.cpp), which hold them for the whole
// step, so that the substep loop touches no body record and no cache entry. Anchors are taken
// relative to the centres of mass at the step's start, and the current separation is recovered
// from the bodies' displacement since then, so contacts are solved without re-running collision
// in every substep (Catto, "Solver2D", 2024: soft step with relaxation). That separation is measured
// along the normal as turned with the body whose face it is (NormalFrame): a box that turns 0.2 rad
// within the step tilts its face under the other body's corner, and measured along the normal fixed
// at the step's start that corner sank 17 mm in (solver_test's BoxSpinningOntoABoxDoesNotSinkItsCornerIn).
// What is solved contact by
// contact, in constraint order (restitution, the position projection), reads each constraint in
// its lane.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"

namespace fx2d::detail {

struct Bodies;
class ContactBatches;
class ContactCache;

// A contact that is a constraint this step: what the colouring and the packing need to place it.
struct ConstraintSource {
  std::uint32_t body_a = 0;
  std::uint32_t body_b = 0;
  int cache_id = 0;
  int point_count = 1;  // 1 or 2
};

// Calls visit(a, b) with the two bodies of every contact in `contacts`, then of every joint in
// `joints`: the links that join bodies into islands (sleep.h) and support chains (step_schedule.h).
template <typename Joints, typename Visit>
void for_each_link(std::span<const ConstraintSource> contacts, const Joints& joints, Visit visit) {
  for (const ConstraintSource& contact : contacts) visit(contact.body_a, contact.body_b);
  for (const auto& joint : joints)
    visit(joint->entity_a()->packed_index(), joint->entity_b()->packed_index());
}

struct ContactSolveParams {
  FxSoftness softness;
  float inv_substep_dt = 0;
  float max_push_speed = 0;
  // The fastest the soft passes' spring pushes an overlap apart through the velocities; push()
  // moves what lies deeper than linear_slop apart through the positions, at up to max_push_speed.
  float max_spring_speed = 0;
  float linear_slop = 0;
};

// Constraints per range of a pack() spread over the workers, and the fewest worth spreading it for
// (measured: see fx2d/src/README.md).
inline constexpr std::uint32_t constraints_per_block = 64;
inline constexpr std::uint32_t min_parallel_constraints = 128;

class ContactSolver {
 public:
  // Grows storage for this many constraints and bodies, so prepare() and project_positions() do
  // not allocate up to there.
  void reserve(std::size_t constraint_count, std::size_t body_count);
  // Lists one constraint per touching contact that has an awake body, in contact cache order.
  void prepare(const ContactCache& contacts, const Bodies& bodies);
  // Lists none: a world asleep.
  void clear();
  // After the substeps: bounce where an approaching point pushed and restitution is > 0.
  void apply_restitution(ContactBatches& batches, std::span<FxBodyState> states, float threshold) const;
  // Non-linear Gauss-Seidel projection of overlaps deeper than the slop, on positions only.
  void project_positions(ContactBatches& batches, std::span<FxBodyState> states, float linear_slop);
  void store_impulses(const ContactBatches& batches, ContactCache& cache) const;

  std::span<const ConstraintSource> sources() const { return sources_; }

 private:
  std::vector<ConstraintSource> sources_;
  std::vector<int> bouncing_;  // the constraints whose restitution is > 0, in order
  std::vector<std::uint8_t> projected_;  // per body: 1 once project_positions() has moved it
};

}  // namespace fx2d::detail

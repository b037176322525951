// How many passes a step's substeps take (FxSceneSettings::rest_schedule, shallow_schedule,
// impact_schedule_travel): the settings', one soft and one rigid pass for a step that needs no more,
// or more soft passes for a step of hard impacts. What the extra passes converge is what a step's
// motion and its load paths bring: an impact's momentum shared down a row of bodies, and a load
// carried down a tall column, about one body further per pass. A step whose contacts close slowly
// and whose bodies stand on short chains has neither. A contact that closes by much of its
// bodies' size within one substep leaves its points far from agreeing after one soft pass, and
// the body turns before a second one would have settled it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "collision/contact_cache.h"
#include "fx2d/Constraint.h"
#include "solver/contact_solver.h"
#include "world/bodies.h"

namespace fx2d::detail {

struct PassCounts {
  int velocity = 0;
  int relax = 0;
};
inline constexpr PassCounts light_schedule_passes{1, 1};

// How fast the step's contacts close: each contact's bodies' approach along its normal, plus what
// their spins add at their farthest points.
struct Closing {
  float fastest = 0.0f;  // m/s; 0 with no contact
  // Whether a contact closes faster than `impact_rate` (1/s) times the smaller of its two bodies'
  // fast_motion (the motion past which continuous collision sweeps a body: half its inner extent;
  // infinite for one not dynamic).
  bool impact = false;
};
Closing closing_speeds(std::span<const ConstraintSource> contacts, const ContactCache& cache,
                       const Bodies& bodies, float impact_rate);

// Whether a step at rest (every awake body has rested) measures its contacts' separations once,
// at its start, rather than after each substep's position integration (SolverData::
// separations_once): when no contact point moves within the step by enough to matter
// (ContactBatches::separations_hold).
// - A point apart must not close its gap: its relative speed along the normal at the step's start,
//   plus what the largest acceleration of an awake body adds over the step (for both of its
//   bodies), covers less than its separation.
// - A touching point must not close by more than resting_rebound / the contacts' bias rate: the
//   soft spring pushes against the separation it was given, so a point pressed deeper than that is
//   pushed back out at the bias rate times the difference, a speed the rigid passes do not take back.
// Resting stacks close at micrometres a second; a box that creeps into a wall below the sleep speed
// does not qualify (RestSchedule tests).
inline constexpr float resting_rebound = 0.001f;  // m/s: a fiftieth of the default sleep speed

// The support chains of a step: each movable body's fewest links (touching contacts and joints
// between movable bodies) down to a body that does not move with the solve (static, kinematic or
// asleep). A body on no such chain, as in free fall, is held by none.
class SupportChains {
 public:
  void reserve(std::size_t bodies, std::size_t links);
  // True when no movable body's chain holds more than `max_bodies` bodies. `states` flags the
  // movable bodies (movable_flag).
  bool all_within(std::span<const ConstraintSource> contacts, const Constraints& joints,
                  std::span<const FxBodyState> states, int max_bodies);

 private:
  struct Pair {
    std::uint32_t a, b;
  };
  std::vector<Pair> pairs_;                // the links between two movable bodies
  std::vector<std::uint32_t> first_link_;  // body -> its first entry in linked_; one past the end last
  std::vector<std::uint32_t> linked_;      // the movable bodies each body is linked to
  std::vector<std::uint32_t> depth_;       // body -> bodies on its chain, itself included; 0 unreached
  std::vector<std::uint32_t> frontier_;    // breadth-first queue
};

}  // namespace fx2d::detail

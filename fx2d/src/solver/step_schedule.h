// How many passes a step's substeps take (FxSceneSettings::rest_schedule, shallow_schedule): the
// settings', or one soft and one rigid pass for a step that needs no more. What the extra passes
// converge is what a step's motion and its load paths bring: an impact's momentum shared down a
// row of bodies, and a load carried down a tall column, about one body further per pass. A step whose
// contacts close slowly and whose bodies stand on short chains has neither.
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

// The fastest any touching contact closes: the bodies' approach along its normal, plus what their
// spins add at their farthest points (m/s; 0 with no contact).
float fastest_closing(std::span<const ConstraintSource> contacts, const ContactCache& cache,
                      const Bodies& bodies);

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

// Sleeping: resting islands sleep as a whole and wake together (sleep.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "world/bodies.h"
#include "solver/contact_solver.h"

namespace fx2d::detail {

struct StepContext;

// The union-find's scratch, reused every step.
struct SleepScratch {
  std::vector<int> island_parent;
  std::vector<std::uint8_t> rest_class;  // per body: RestClass
  // Per rested body: an unrested body touches it; then, on each group's root, that one of the
  // group's bodies is so touched, and the group stays awake.
  std::vector<std::uint8_t> held_awake;

  void reserve(std::size_t bodies);
};

// Stage: puts to sleep every island of `moving` bodies whose bodies all rested time_to_sleep. The
// islands are joined by the step's contact constraints, `touching` (the touching contacts with an
// awake body), and the user constraints.
void update_sleep(const StepContext& step, SleepScratch& scratch, Bodies& bodies,
                  std::span<const ConstraintSource> touching, const Constraints& constraints,
                  std::span<const std::uint32_t> moving);

// Wakes the island of body `index` (nothing for an awake or static body).
void wake_body(Bodies& bodies, std::uint32_t index);

}  // namespace fx2d::detail

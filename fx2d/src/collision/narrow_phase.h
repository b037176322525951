// Narrow phase: refreshes the manifold of every cached pair with an awake body (narrow_phase.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "collision/aabb_tree.h"
#include "world/bodies.h"
#include "collision/contact_cache.h"

namespace fx2d::detail {

struct StepContext;

// What the parallel collision of one pair left for the serial pass to do, per contact slot: a pair
// collided whose touching did not change leaves it nothing, and the pass does not read its record.
enum class PairUpdate : std::uint8_t { skipped, separated, collided, began_touching, stopped_touching };

struct NarrowPhaseScratch {
  std::vector<PairUpdate> pair_updates;  // per contact slot, reused every step
  void reserve(std::size_t contacts) { pair_updates.reserve(contacts); }
};

// Stage: collides every cached pair with an awake body, destroys the pairs whose fat boxes
// separated and wakes a sleeping body that a pair begins to touch. With several workers the
// pairs are collided in parallel, then destroyed and woken in slot order on this thread, so the
// result is the serial one's.
void update_contacts(const StepContext& step, NarrowPhaseScratch& scratch, ContactCache& contacts, Bodies& bodies,
                     const AabbTree& tree);

}  // namespace fx2d::detail

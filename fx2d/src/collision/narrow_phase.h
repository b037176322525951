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

// A body as the narrow phase's test of pairs apart sees it at the step's start: the circle about its
// centre of mass that holds its shape (in world coordinates), and how fast any point of it moves.
struct BodyReach {
  FxVec2f centre;
  float radius;
  float speed;  // |linear velocity| + |angular velocity| x radius
};

// How far two polygons may move relative to each other, after a full collision gave them points,
// before they are collided afresh; until then they keep that collision's features and have only
// their separations measured. A point the full collision left out was at least 2 cm apart, so none
// comes into contact unseen. A kept point's place along its face is stale by at most this
// distance, and the lever arm of a thin body standing on its end errs by half of it: so it is a
// fiftieth of the shorter shape's shortest edge, and at most 8 mm. Resolved once, as the pair is made.
float manifold_reuse_distance(const FxShape& a, const FxShape& b);

// A body's BodyReach at its sim's pose and velocities.
BodyReach reach_of(const BodySim& sim);

// True when two bodies lie further apart than the speculative margin any collision of them this
// step could take, so that collide() would keep no point of theirs: a kept point's separation
// bounds how far apart the shapes are, and they are at least as far apart as their circles. The
// margin is 0.02 m plus a step's closing at most at the largest of their relative and their own
// speeds, with the spins at the shapes' extents (which the circles' radii bound): at most the
// two speeds' sum. The allowance covers the rounding of these few operations and of collide()'s,
// relative to the coordinates and sizes involved. The narrow phase skips a pair apart at its last
// collision that this holds for; collide() would have left its record as it was, bar the face it
// tries first, which decides no result.
bool surely_apart(const BodyReach& a, const BodyReach& b, float dt);

struct NarrowPhaseScratch {
  std::vector<PairUpdate> pair_updates;  // per contact slot, reused every step
  std::vector<BodyReach> reach;          // per body, refreshed every step
  void reserve(std::size_t bodies, std::size_t contacts) {
    reach.reserve(bodies);
    pair_updates.reserve(contacts);
  }
};

// Stage: collides every cached pair with an awake body, destroys the pairs whose fat boxes
// separated and wakes a sleeping body that a pair begins to touch. With several workers the
// pairs are collided in parallel, then destroyed and woken in slot order on this thread, so the
// result is the serial one's.
void update_contacts(const StepContext& step, NarrowPhaseScratch& scratch, ContactCache& contacts, Bodies& bodies,
                     const AabbTree& tree);

}  // namespace fx2d::detail

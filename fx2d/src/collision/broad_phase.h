// Broad phase: each body's proxy in the AABB tree, and the search for pairs whose fat boxes begin
// to overlap (broad_phase.cpp). The stage owns the tree and its scratch; the other stages only
// read the fat boxes.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "collision/aabb_tree.h"
#include "world/bodies.h"
#include "collision/contact_cache.h"

namespace fx2d::detail {

struct StepContext;

// `box` stretched to cover itself moved by `displacement`: std::min(d, 0) added to its lower corner
// and std::max(d, 0) to its upper, -0 and NaN alike, as one four-lane select. refresh() runs for
// every moving body every step, and the signs of a heap's velocities are a coin toss: written per
// coordinate, the baseline (SSE2) build branched on two of them, and the box refresh of finalize
// took 1.7 times as long as in an x86-64-v3 build.
inline FxAABB swept(FxAABB box, FxVec2f displacement) {
  using Row = float __attribute__((vector_size(16)));
  using RowMask = std::int32_t __attribute__((vector_size(16)));
  static_assert(sizeof(FxAABB) == sizeof(Row), "a box is four floats: lower, then upper");
  const Row d = {displacement.x, displacement.y, displacement.x, displacement.y};
  // A lower lane drops a displacement > 0, an upper lane one < 0 (-d > 0).
  const Row toward_dropped = {1.0f, 1.0f, -1.0f, -1.0f};
  const RowMask dropped = d * toward_dropped > Row{};
  const Row kept = reinterpret_cast<Row>(reinterpret_cast<RowMask>(d) & ~dropped);
  Row row;
  std::memcpy(&row, &box, sizeof row);
  row += kept;
  std::memcpy(static_cast<void*>(&box), &row, sizeof box);
  return box;
}

struct BroadPhase {
  AabbTree tree;
  std::vector<std::uint32_t> body_of_proxy;  // proxy id -> packed index
  // The static and kinematic bodies again, with the same fat boxes: what continuous collision
  // sweeps a fast body against (continuous.h). Searched in `tree`, each fast body's sweep walked
  // down through the crowd of dynamic bodies around it, only to skip them.
  AabbTree fixed_tree;
  std::vector<std::uint32_t> body_of_fixed_proxy;  // fixed_tree's proxy id -> packed index
  // proxy id -> 1 while its body's `moved` is set, during the search: read per leaf a query
  // visits, where the body's record would be a cache miss.
  std::vector<std::uint8_t> proxy_moved;
  // Pairs (a << 32 | b, a < b) joined by a constraint, sorted: they never collide.
  std::vector<std::uint64_t> jointed_pairs;
  bool jointed_pairs_dirty = false;
  // Whether a body may have been marked moved since the last update: by the step that just ran
  // (its bodies were awake) or by a body created or placed. A world asleep with nothing placed skips
  // the walk over every body.
  bool may_have_moved = true;
  // Scratch reused every step.
  std::vector<std::uint32_t> moved_bodies;
  std::vector<std::uint64_t> new_pairs;  // (moved body << 32 | other body) of each pair found this step
  // The pairs found from each block of moved_bodies, on whichever thread searched that block.
  std::vector<std::vector<std::uint64_t>> new_pairs_by_block;

  void reserve(std::size_t bodies);
  // Gives body `index` its proxies (record.proxy, and record.fixed_proxy unless it is dynamic) for
  // its tight box `aabb`.
  void add_body(BodyRecord& record, const FxAABB& aabb, std::uint32_t index);
  // Takes a body's proxies out of the trees.
  void remove_body(const BodyRecord& record);
  // Points a body's proxies at its new packed index `index`.
  void renumber(const BodyRecord& record, std::uint32_t index);
  // True when a constraint joins bodies a and b: such a pair never collides.
  bool jointed(std::uint32_t a, std::uint32_t b) const;
  // Marks the body moved when its tight box (sim.aabb), swept by the motion its velocity gives it over
  // the next step of `dt`, has left its proxy's fat box. The tight box alone would let two bodies that sped up inside
  // their fat boxes (struck by a third) close on each other unsearched: no pair, no speculative
  // point, and they overlap by what they close within the step (in a collapsing pile of circles,
  // 99 mm). Inline: it runs for every moving body every step.
  void refresh(BodyRecord& record, const BodySim& sim, float dt) const {
    if (!tree.fat_box(record.proxy).contains(swept(sim.aabb, dt * sim.linear_velocity))) record.moved = true;
  }
};

// Stage: moves the proxies of the bodies that left their fat boxes and creates a contact for each
// new overlapping pair, in the order of the bodies' indices.
void update_broad_phase(const StepContext& step, BroadPhase& broad, Bodies& bodies, ContactCache& contacts,
                        const Constraints& constraints);

}  // namespace fx2d::detail

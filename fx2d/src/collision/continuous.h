// Continuous collision: the stage that stops a fast body where its motion over the step would
// first have touched something, so that it cannot pass through a thin or small body between two
// poses. It runs after the step's poses are final (finalize_bodies) and looks only at bodies
// whose motion this step is large against their own size; other scenes pay one comparison per
// moving body.
//
// Every fast dynamic body is swept against static and kinematic bodies; a bullet (FxEntityDef::
// bullet) is also swept, afterwards, against the dynamic bodies that are not bullets, along their
// motion of the step as the first pass left it. Each fast body reads only bodies that the pass it
// is in does not move, so the result does not depend on the order the fast bodies are taken in.
// A body stopped at a first impact keeps its velocity: the next step's contact stops it. A body
// stopped by what it already touched at the step's start (it turned about the point it touched)
// loses its centre's approach along the normal there: that contact already had its step. If what
// it touched is static, it then slides on along it for the rest of the step, swept again.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "world/bodies.h"
#include "collision/broad_phase.h"
#include "fx2d/Constraint.h"

namespace fx2d::detail {

struct StepContext;

// The fast bodies of the step, kept between steps so that a step does not allocate.
struct ContinuousScratch {
  // A fast body, and how far its farthest point moved in the step (as the walk that found it measured).
  struct FastBody {
    std::uint32_t body;
    float motion;
  };
  std::vector<FastBody> fast_bodies;

  void reserve(std::size_t bodies) { fast_bodies.reserve(bodies); }
};

// Sets sim.reach and sim.fast_motion for a body of this type and shape, whose sim's local_center
// is set: a dynamic body is fast when some point of it moves farther in a step than half its inner
// extent, the least distance from its shape's centroid to its surface.
void set_continuous_extents(BodySim& sim, FxBodyType type, const FxShape& shape);

// Stage: moves each fast body in `moving` back to its pose at its first time of impact, if any,
// linear_slop short of touching (or, if it began within that, linear_slop closer than it began;
// then, against a static body, on along it as far as nothing stops it), and rewrites its
// displacement in `states` to the motion it kept.
void solve_continuous(const StepContext& step, ContinuousScratch& scratch, std::span<FxBodyState> states,
                      std::span<const std::uint32_t> moving, Bodies& bodies, const BroadPhase& broad);

}  // namespace fx2d::detail

// The substep's two body loops, eight bodies at a time: velocity integration (gravity, forces,
// damping, and in a later substep the warm start the impulses carry over) of the awake dynamic
// bodies, and position integration of every awake moving body, each with the speed limits applied
// first; and, at the step's end, the write-back of every awake moving body's pose and velocity to
// its sim, eight at a time too.
//
// Invariants:
// - both body lists are padded to whole groups of eight with the padding body, whose state is
//   zero and stays zero (no acceleration, factor one), so every group is gathered, solved as one
//   vectorisable loop and scattered whole;
// - a body appears once in a list, except the padding body, whose lanes compute equal values and
//   lie in the last group alone, so groups can be integrated on several threads at once;
// - the arithmetic of a lane is the scalar arithmetic of one body, and the rare lane over the
//   speed limit is slowed by the scalar slowed_to(), so the result does not depend on the lanes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fx2d/Constraint.h"
#include "fx2d/Math.h"
#include "world/bodies.h"
#include "world/speed_limits.h"
#include "world/tasks.h"

namespace fx2d::detail {

// The fewest bodies worth waking the workers for: two workers took 0.78-0.81 of one's integration
// at 800 and 1200 bodies, 0.98 at 300 (fx2d/src/README.md). The parallel body loops give each
// worker one range of whole groups of eight (Tasks::per_worker), the same share in every loop of
// the step, so that a body's state stays in the cache of the core that integrates it.
inline constexpr std::uint32_t min_parallel_bodies = 512;

// The step's end for a block of `bodies` (each once; states, sims and records indexed alike): the
// sim's rotation becomes the state's rotation times it, normalised, and its origin (with its carry)
// moves with the state's displacement of the centre of mass; its velocity becomes the state's,
// limited; and the record's rest time counts on while the body rests (body_integration.cpp).
// Writes those bodies' sims and records alone, so blocks are written back on several threads.
void write_back_bodies(std::span<const std::uint32_t> bodies, const FxBodyState* states, BodySim* sims,
                       BodyRecord* records, SpeedLimits limits, const FxSceneSettings& settings);

class BodyIntegration {
 public:
  // Grows storage for this many bodies, so a step does not allocate up to there.
  void reserve(std::size_t bodies);
  // Starts the step's lists for up to `body_count` bodies; `padding_body` indexes a zero state
  // that nothing reads back.
  void clear(std::uint32_t padding_body, std::size_t body_count);
  // An awake body that moves: kinematic or dynamic.
  void add_moving(std::uint32_t body) { moving_[moving_size_++] = body; }
  // An awake dynamic body (also added with add_moving), with what its velocity integration reads.
  void add_dynamic(std::uint32_t body, FxVec2f acceleration, float linear_factor, float angular_factor) {
    dynamic_[dynamic_size_] = body;
    entry_of_body_[body] = static_cast<std::uint32_t>(dynamic_size_);
    acceleration_x_[dynamic_size_] = acceleration.x;
    acceleration_y_[dynamic_size_] = acceleration.y;
    linear_factor_[dynamic_size_] = linear_factor;
    angular_factor_[dynamic_size_] = angular_factor;
    ++dynamic_size_;
  }
  // Pads both lists to whole groups; call once, after the last add.
  void finish();
  // A bound on the largest acceleration of a dynamic body added this step (m/s^2): the sum of its
  // components' magnitudes, which needs no square root.
  float largest_acceleration() const;
  // The awake moving bodies added this step, in order, without the padding.
  std::span<const std::uint32_t> moving_bodies() const { return {moving_.data(), moving_count_}; }

  // v <- limited(linear_factor * (v + h * acceleration)), w <- limited(angular_factor * w), kept as
  // the body's integrated velocity. With `carry_impulses`, each body then also gets again what the
  // constraints changed its velocity by since its last integration: the impulses they have
  // accumulated, when they are contacts alone, whose rows stay the same for the whole step. That
  // is their warm start, without a sweep over them (Substep::carries_warm_start).
  void integrate_velocities(std::span<FxBodyState> states, float h, SpeedLimits limits, bool carry_impulses,
                            const Tasks& tasks);
  // v, w <- limited(v, w); then displacement and rotation advance by h.
  void integrate_positions(std::span<FxBodyState> states, float h, SpeedLimits limits, const Tasks& tasks);

 private:
  std::uint32_t padding_body_ = 0;
  // The lists are sized by clear() for every body and the padding, and filled by index: the first
  // moving_size_ and dynamic_size_ entries are this step's, padding included.
  std::size_t moving_count_ = 0;  // moving_ before its padding
  std::size_t moving_size_ = 0;
  std::size_t dynamic_size_ = 0;
  std::vector<std::uint32_t> moving_;
  std::vector<std::uint32_t> dynamic_;
  // Per entry of dynamic_:
  std::vector<float> acceleration_x_, acceleration_y_, linear_factor_, angular_factor_;
  // Per entry of dynamic_, the velocity its last integration gave it, before any impulse, and
  // with whatever the speed limits have taken off since, which no impulse applied either.
  std::vector<float> integrated_x_, integrated_y_, integrated_w_;
  std::vector<std::uint32_t> entry_of_body_;  // per body, its entry in dynamic_ (awake dynamic bodies)
};

}  // namespace fx2d::detail

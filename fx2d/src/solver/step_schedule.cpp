// The step's schedule (step_schedule.h): the closing speed of its contacts and the depth of its
// support chains, found breadth first from the bodies that rest on something the solve does not move.
#include "solver/step_schedule.h"

#include <algorithm>
#include <cmath>

#include "solver/lane_rows.h"

namespace fx2d::detail {

Closing closing_speeds(std::span<const ConstraintSource> contacts, const ContactCache& cache,
                       const Bodies& bodies, float impact_rate) {
  Closing closing;
  for (const ConstraintSource& contact : contacts) {
    const BodySim& a = bodies.sims[contact.body_a];
    const BodySim& b = bodies.sims[contact.body_b];
    const FxVec2f normal = cache.slots[contact.cache_id].manifold.normal;
    const float spin = std::fabs(a.angular_velocity) * a.reach + std::fabs(b.angular_velocity) * b.reach;
    const float speed = dot(a.linear_velocity - b.linear_velocity, normal) + spin;
    closing.fastest = std::max(closing.fastest, speed);
    closing.impact |= speed > impact_rate * std::min(a.fast_motion, b.fast_motion);
  }
  return closing;
}

void SupportChains::reserve(std::size_t bodies, std::size_t links) {
  first_link_.reserve(bodies + 2);
  pairs_.reserve(links);
  linked_.reserve(2 * links);
  depth_.reserve(bodies + 1);
  frontier_.reserve(bodies + 1);
}

bool SupportChains::all_within(std::span<const ConstraintSource> contacts, const Constraints& joints,
                               std::span<const FxBodyState> states, int max_bodies) {
  // A chain of more than max_bodies bodies needs more links than that.
  if (contacts.size() + joints.size() <= static_cast<std::size_t>(max_bodies)) return true;
  const std::size_t body_count = states.size();
  first_link_.assign(body_count + 1, 0);
  depth_.assign(body_count, 0);
  pairs_.clear();
  frontier_.clear();
  // One look at each link: a link between movable bodies is kept and counted for both, and a
  // movable body linked to a support starts a chain of one.
  const auto add_link = [&](std::uint32_t a, std::uint32_t b) {
    const bool movable_a = (states[a].flags & movable_flag) != 0;
    const bool movable_b = (states[b].flags & movable_flag) != 0;
    if (movable_a && movable_b) {
      pairs_.push_back({a, b});
      ++first_link_[a + 1], ++first_link_[b + 1];
    } else if (movable_a || movable_b) {
      const std::uint32_t held = movable_a ? a : b;
      if (depth_[held] == 0) depth_[held] = 1, frontier_.push_back(held);
    }
  };
  for_each_link(contacts, joints, add_link);
  // A body on a support stands on a chain of one.
  if (max_bodies < 1 && !frontier_.empty()) return false;
  // Each body's links, listed from first_link_[body]: counted above, placed here, the starts
  // advanced as they fill and then put back.
  for (std::size_t i = 1; i <= body_count; ++i) first_link_[i] += first_link_[i - 1];
  linked_.resize(2 * pairs_.size());
  for (const auto& [a, b] : pairs_) linked_[first_link_[a]++] = b, linked_[first_link_[b]++] = a;
  for (std::size_t i = body_count; i > 0; --i) first_link_[i] = first_link_[i - 1];
  first_link_[0] = 0;
  // Breadth first, so each body's depth is its shortest chain's.
  for (std::size_t next = 0; next < frontier_.size(); ++next) {
    const std::uint32_t body = frontier_[next];
    const std::uint32_t depth = depth_[body] + 1;
    for (std::uint32_t k = first_link_[body]; k < first_link_[body + 1]; ++k) {
      const std::uint32_t other = linked_[k];
      if (depth_[other] != 0) continue;
      if (depth > static_cast<std::uint32_t>(max_bodies)) return false;
      depth_[other] = depth;
      frontier_.push_back(other);
    }
  }
  return true;
}

}  // namespace fx2d::detail

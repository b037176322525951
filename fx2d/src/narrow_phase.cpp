// Narrow phase: refresh the manifold of every cached pair that has an awake body, once per step.
// Pairs whose fat boxes separated are destroyed; a pair that begins touching a sleeping body
// wakes it. Each pair is collided in a frame centred on body a's origin, built from the precise
// (carried) positions, so coordinates stay small however far the pair is from the world origin.
#include <algorithm>
#include <cmath>

#include "world.h"

namespace fx2d::detail {
namespace {

// Points closer than this are kept as speculative contacts (metres), plus however far the pair
// can close in one step, so a fast body is stopped at the surface instead of passing through.
constexpr float base_speculative_distance = 0.02f;
constexpr float max_speculative_distance = 2.0f;

}  // namespace

float World::speculative_distance(std::uint32_t a, std::uint32_t b) const {
  const BodySim& sa = sims[a];
  const BodySim& sb = sims[b];
  const float closing_speed = length(sb.linear_velocity - sa.linear_velocity) +
                              std::fabs(sa.angular_velocity) * records[a].shape.extent() +
                              std::fabs(sb.angular_velocity) * records[b].shape.extent();
  return std::min(base_speculative_distance + settings.dt * closing_speed, max_speculative_distance);
}

void World::update_contacts() {
  Manifold manifold;
  for (int id = 0; id < static_cast<int>(contacts.slots.size()); ++id) {
    CachedContact& contact = contacts.slots[id];
    if (!contact.alive) continue;
    const std::uint32_t a = contact.body_a;
    const std::uint32_t b = contact.body_b;
    BodyRecord& ra = records[a];
    BodyRecord& rb = records[b];
    const bool active_a = ra.awake && ra.type != FxBodyType::static_body;
    const bool active_b = rb.awake && rb.type != FxBodyType::static_body;
    if (!active_a && !active_b) continue;
    if (!overlaps(tree.fat_box(ra.proxy), tree.fat_box(rb.proxy))) {
      contacts.destroy(id, ra.contact_head, rb.contact_head);
      continue;
    }
    const BodySim& sa = sims[a];
    const BodySim& sb = sims[b];
    collide(ra.shape, FxTransform{{}, sa.rotation}, rb.shape, FxTransform{origin_offset(a, b), sb.rotation},
            speculative_distance(a, b), manifold);
    const bool was_touching = contact.touching;
    contacts.update_manifold(contact, manifold);
    if (contact.touching && !was_touching) {
      if (!ra.awake && active_b) wake_body(a);
      if (!rb.awake && active_a) wake_body(b);
    }
  }
}

}  // namespace fx2d::detail

// Narrow phase: refresh the manifold of every cached pair that has an awake body, once per step.
// Pairs whose fat boxes separated are destroyed; a pair that begins touching a sleeping body
// wakes it. Each pair is collided in a frame centred on body a's origin, built from the precise
// (carried) positions, so coordinates stay small however far the pair is from the world origin.
#include "collision/narrow_phase.h"

#include <algorithm>
#include <cmath>

#include "world/sleep.h"
#include "world/step_context.h"

namespace fx2d::detail {
namespace {

// Points closer than this are kept as speculative contacts (metres), plus however far the pair
// can close in one step, so a fast body is stopped at the surface instead of passing through.
constexpr float base_speculative_distance = 0.02f;
constexpr float max_speculative_distance = 2.0f;

float speculative_distance(float dt, float closing_speed) {
  return std::min(base_speculative_distance + dt * closing_speed, max_speculative_distance);
}

// Drops the points farther apart than `distance`, keeping the others in order.
void keep_points_within(Manifold& manifold, float distance) {
  int kept = 0;
  for (int i = 0; i < manifold.point_count; ++i) {
    if (manifold.points[i].separation < distance) manifold.points[kept++] = manifold.points[i];
  }
  manifold.point_count = kept;
}

}  // namespace

// Along a normal n from A to B, a pair closes at up to its relative speed, or at A's or B's own
// speed towards the other: either may stop against a third body mid-step while the other keeps
// going. A column falling in unison has no relative speed, yet its lowest body lands first and
// the next one closes on it at full speed. Spins add their speed at the shapes' extents.
PairMotion pair_motion(const Bodies& bodies, std::uint32_t a, std::uint32_t b) {
  const BodySim& sa = bodies.sims[a];
  const BodySim& sb = bodies.sims[b];
  return {sa.linear_velocity, sb.linear_velocity,
          std::fabs(sa.angular_velocity) * bodies.records[a].shape.extent() +
              std::fabs(sb.angular_velocity) * bodies.records[b].shape.extent()};
}

float PairMotion::fastest_closing() const {
  // The largest of |v_b - v_a|, |v_a| and |v_b|: one square root of the largest square, which is
  // the same float (sqrt is monotonic and correctly rounded).
  const FxVec2f relative = velocity_b - velocity_a;
  return std::sqrt(std::max({dot(relative, relative), dot(velocity_a, velocity_a), dot(velocity_b, velocity_b)})) +
         spin_speed;
}

float PairMotion::closing_along(FxVec2f normal) const {
  return std::max({length(velocity_b - velocity_a), dot(velocity_a, normal), -dot(velocity_b, normal)}) + spin_speed;
}

void update_contacts(const StepContext& step, ContactCache& contacts, Bodies& bodies, const AabbTree& tree) {
  Manifold manifold;
  for (int id = 0; id < static_cast<int>(contacts.slots.size()); ++id) {
    CachedContact& contact = contacts.slots[id];
    if (!contact.alive) continue;
    const std::uint32_t a = contact.body_a;
    const std::uint32_t b = contact.body_b;
    BodyRecord& ra = bodies.records[a];
    BodyRecord& rb = bodies.records[b];
    const bool active_a = ra.awake && ra.type != FxBodyType::static_body;
    const bool active_b = rb.awake && rb.type != FxBodyType::static_body;
    if (!active_a && !active_b) continue;
    if (!overlaps(tree.fat_box(ra.proxy), tree.fat_box(rb.proxy))) {
      contacts.destroy(id, ra.contact_head, rb.contact_head);
      continue;
    }
    const BodySim& sa = bodies.sims[a];
    const BodySim& sb = bodies.sims[b];
    // Collided at the widest margin any normal could need, then trimmed to the one it found.
    const PairMotion motion = pair_motion(bodies, a, b);
    collide(ra.shape, FxTransform{{}, sa.rotation}, rb.shape, FxTransform{bodies.origin_offset(a, b), sb.rotation},
            speculative_distance(step.settings.dt, motion.fastest_closing()), manifold);
    keep_points_within(manifold, speculative_distance(step.settings.dt, motion.closing_along(manifold.normal)));
    const bool was_touching = contact.touching;
    contacts.update_manifold(contact, manifold);
    if (contact.touching && !was_touching) {
      if (!ra.awake && active_b) wake_body(bodies, a);
      if (!rb.awake && active_a) wake_body(bodies, b);
    }
  }
}

}  // namespace fx2d::detail

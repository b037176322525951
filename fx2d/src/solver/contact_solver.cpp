// Which contacts become the step's constraints, and the parts solved contact by contact
// (contact_solver.h): restitution after the substeps, the position projection, and the storage of
// impulses for the next step's warm start, each reading the constraint in its batch's lane.
#include "solver/contact_solver.h"

#include <algorithm>

#include "world/bodies.h"
#include "collision/contact_cache.h"
#include "solver/contact_batch.h"

namespace fx2d::detail {
namespace {

// The position projection corrects this fraction of the excess overlap per pass, and at most
// max_projection metres, so that a deep overlap is resolved over several steps, not in one jump.
constexpr float projection_fraction = 0.2f;
constexpr float max_projection = 0.2f;

// One constraint as the contact-by-contact passes see it: its lane, and the bodies' inverse masses.
struct LaneConstraint {
  const ContactBatch& k;
  int lane;

  FxVec2f normal() const { return {k.normal_x[lane], k.normal_y[lane]}; }
  FxVec2f anchor_a(int point) const { return {k.point[point].anchor_ax[lane], k.point[point].anchor_ay[lane]}; }
  FxVec2f anchor_b(int point) const { return {k.point[point].anchor_bx[lane], k.point[point].anchor_by[lane]}; }
  float inv_mass_a() const { return k.inv_mass_a[lane]; }
  float inv_mass_b() const { return k.inv_mass_b[lane]; }
  float inv_inertia_a() const { return k.inv_inertia_a[lane]; }
  float inv_inertia_b() const { return k.inv_inertia_b[lane]; }

  float effective_mass(FxVec2f arm_a, FxVec2f arm_b, FxVec2f direction) const {
    const float ra = cross(arm_a, direction);
    const float rb = cross(arm_b, direction);
    const float mass = inv_mass_a() + inv_mass_b() + inv_inertia_a() * ra * ra + inv_inertia_b() * rb * rb;
    return mass > 0.0f ? 1.0f / mass : 0.0f;
  }

  // An impulse at point `point`'s anchors: A loses and B gains.
  void apply_impulse(FxBodyState& a, FxBodyState& b, int point, FxVec2f impulse) const {
    a.linear_velocity -= inv_mass_a() * impulse;
    a.angular_velocity -= inv_inertia_a() * cross(anchor_a(point), impulse);
    b.linear_velocity += inv_mass_b() * impulse;
    b.angular_velocity += inv_inertia_b() * cross(anchor_b(point), impulse);
  }

  // How each body's anchors have turned since the step began: as the body has, but against the
  // step's normal, which these passes do not turn, a circle's not at all (ContactBatch::round_sides).
  FxRot anchor_turn_a(const FxBodyState& a) const {
    return (k.round_sides[lane] & round_side_a) != 0 ? FxRot{} : a.delta_rotation;
  }
  FxRot anchor_turn_b(const FxBodyState& b) const {
    return (k.round_sides[lane] & round_side_b) != 0 ? FxRot{} : b.delta_rotation;
  }

  // Point `point`'s separation now, from the displacement of both bodies since the step began and
  // its anchors as turned since. ContactBatches::first_projection_overlap() measures the same in
  // lanes, in the same operations, to find where project_positions() starts: change both.
  float current_separation(const FxBodyState& a, const FxBodyState& b, FxVec2f moved_a, FxVec2f moved_b,
                           int point) const {
    const FxVec2f gap = (b.delta_position - a.delta_position) + (moved_b - moved_a);
    return dot(gap, normal()) + k.point[point].adjusted_separation[lane];
  }
};

FxVec2f point_velocity(const FxBodyState& state, FxVec2f anchor) {
  return state.linear_velocity + cross(state.angular_velocity, anchor);
}

// Whether a contact becomes a constraint this step: touching, with an awake body. Which slots
// touch looks like a coin toss, but listing them without a branch (each slot written at the
// list's end, the length grown by whether it is active) made prepare 1.05-1.22 times as long.
bool is_active(const CachedContact& contact, const Bodies& bodies) {
  return contact.touching && (bodies.records[contact.body_a].awake || bodies.records[contact.body_b].awake);
}

}  // namespace

void ContactSolver::reserve(std::size_t constraint_count, std::size_t body_count) {
  sources_.reserve(constraint_count);
  bouncing_.reserve(constraint_count);
  projected_.reserve(body_count);
}

void ContactSolver::prepare(const ContactCache& contacts, const Bodies& bodies) {
  clear();
  for (int id = 0; id < static_cast<int>(contacts.slots.size()); ++id) {
    const CachedContact& contact = contacts.slots[id];
    if (!is_active(contact, bodies)) continue;
    if (contact.restitution != 0.0f) bouncing_.push_back(static_cast<int>(sources_.size()));
    sources_.push_back({contact.body_a, contact.body_b, id, contact.manifold.point_count});
  }
}

void ContactSolver::clear() {
  sources_.clear();
  bouncing_.clear();
}

void ContactSolver::apply_restitution(ContactBatches& batches, std::span<FxBodyState> states, float threshold) const {
  for (const int i : bouncing_) {
    const ConstraintSource& source = sources_[i];
    ContactBatch& k = batches.batch_holding(i);
    const LaneConstraint c{k, batches.lane_holding(i)};
    const int lane = c.lane;
    const float restitution = k.restitution[lane];
    FxBodyState& a = states[source.body_a];
    FxBodyState& b = states[source.body_b];
    for (int p = 0; p < source.point_count; ++p) {
      PointColumns& point = k.point[p];
      const float relative_velocity = k.relative_velocity[p][lane];
      if (relative_velocity > -threshold || point.max_normal_impulse[lane] == 0.0f) continue;
      const float vn = dot(point_velocity(b, c.anchor_b(p)) - point_velocity(a, c.anchor_a(p)), c.normal());
      const float delta = -point.normal_mass[lane] * (vn + restitution * relative_velocity);
      const float accumulated = std::max(point.normal_impulse[lane] + delta, 0.0f);
      const float applied = accumulated - point.normal_impulse[lane];
      point.normal_impulse[lane] = accumulated;
      c.apply_impulse(a, b, p, applied * c.normal());
    }
  }
}

void ContactSolver::project_positions(ContactBatches& batches, std::span<FxBodyState> states,
                                      float linear_slop) {
  // Contact by contact, each seeing what the ones before moved. Up to the first contact that
  // overlaps deeper than the slop at the start, none moves anything: the pass starts there, and
  // a step that left no such overlap, as most do, skips it. After it, a contact that was no deeper
  // than the slop at the start, and neither of whose bodies a contact before it has moved, measures
  // just that again and moves nothing: it is passed over. The same bits.
  const int first = batches.first_projection_overlap(states, linear_slop);
  if (first == static_cast<int>(sources_.size())) return;
  projected_.assign(states.size(), 0);
  for (int i = first; i < static_cast<int>(sources_.size()); ++i) {
    const ConstraintSource& source = sources_[i];
    if (projected_[source.body_a] == 0 && projected_[source.body_b] == 0 && !batches.overlapped_at_start(i))
      continue;
    const LaneConstraint c{batches.batch_holding(i), batches.lane_holding(i)};
    FxBodyState& a = states[source.body_a];
    FxBodyState& b = states[source.body_b];
    for (int p = 0; p < source.point_count; ++p) {
      const FxVec2f moved_a = rotate(c.anchor_turn_a(a), c.anchor_a(p));
      const FxVec2f moved_b = rotate(c.anchor_turn_b(b), c.anchor_b(p));
      const float separation = c.current_separation(a, b, moved_a, moved_b, p);
      const float correction = std::clamp(projection_fraction * (separation + linear_slop), -max_projection, 0.0f);
      if (correction == 0.0f) continue;
      const float mass = c.effective_mass(moved_a, moved_b, c.normal());
      const FxVec2f impulse = (-correction * mass) * c.normal();
      a.delta_position -= c.inv_mass_a() * impulse;
      a.delta_rotation = integrate_rotation(a.delta_rotation, -c.inv_inertia_a() * cross(moved_a, impulse));
      b.delta_position += c.inv_mass_b() * impulse;
      b.delta_rotation = integrate_rotation(b.delta_rotation, c.inv_inertia_b() * cross(moved_b, impulse));
      // Only a movable body moves (a static one's inverse masses are zero), and one that does not
      // leaves its other contacts as they were.
      projected_[source.body_a] |= static_cast<std::uint8_t>(a.flags & movable_flag);
      projected_[source.body_b] |= static_cast<std::uint8_t>(b.flags & movable_flag);
    }
  }
}

void ContactSolver::store_impulses(const ContactBatches& batches, ContactCache& cache) const {
  for (int i = 0; i < static_cast<int>(sources_.size()); ++i) {
    const ConstraintSource& source = sources_[i];
    const ContactBatch& k = batches.batch_holding(i);
    const int lane = batches.lane_holding(i);
    CachedContact& contact = cache.slots[source.cache_id];
    for (int p = 0; p < source.point_count; ++p) {
      contact.normal_impulse[p] = k.point[p].normal_impulse[lane];
      contact.tangent_impulse[p] = k.point[p].tangent_impulse[lane];
    }
  }
}

}  // namespace fx2d::detail

// Contact constraints built from the cache for one step, and the parts solved contact by contact
// (contact_solver.h): restitution after the substeps, the position projection, and the storage of
// impulses for the next step's warm start.
#include "solver/contact_solver.h"

#include <algorithm>
#include <cmath>

#include "world/bodies.h"
#include "collision/contact_cache.h"

namespace fx2d::detail {
namespace {

// Below this tangential speed (m/s) a contact counts as sticking and static friction applies.
constexpr float sticking_speed = 0.01f;
// The position projection corrects this fraction of the excess overlap per pass, and at most
// max_projection metres, so that a deep overlap is resolved over several steps, not in one jump.
constexpr float projection_fraction = 0.2f;
constexpr float max_projection = 0.2f;

FxVec2f point_velocity(const FxBodyState& state, FxVec2f anchor) {
  return state.linear_velocity + cross(state.angular_velocity, anchor);
}

float effective_mass(const ContactConstraint& c, FxVec2f anchor_a, FxVec2f anchor_b, FxVec2f direction) {
  const float ra = cross(anchor_a, direction);
  const float rb = cross(anchor_b, direction);
  const float k = c.inv_mass_a + c.inv_mass_b + c.inv_inertia_a * ra * ra + c.inv_inertia_b * rb * rb;
  return k > 0.0f ? 1.0f / k : 0.0f;
}

void apply_impulse(FxBodyState& a, FxBodyState& b, const ContactConstraint& c, const ContactPointConstraint& p,
                   FxVec2f impulse) {
  a.linear_velocity -= c.inv_mass_a * impulse;
  a.angular_velocity -= c.inv_inertia_a * cross(p.anchor_a, impulse);
  b.linear_velocity += c.inv_mass_b * impulse;
  b.angular_velocity += c.inv_inertia_b * cross(p.anchor_b, impulse);
}

// Separation now, from the displacement and rotation of both bodies since the step began.
float current_separation(const FxBodyState& a, const FxBodyState& b, FxVec2f normal, const ContactPointConstraint& p) {
  const FxVec2f moved_a = rotate(a.delta_rotation, p.anchor_a);
  const FxVec2f moved_b = rotate(b.delta_rotation, p.anchor_b);
  const FxVec2f gap = (b.delta_position - a.delta_position) + (moved_b - moved_a);
  return dot(gap, normal) + p.adjusted_separation;
}

// Whether a contact becomes a constraint this step: touching, with an awake body.
bool is_active(const CachedContact& contact, const Bodies& bodies) {
  return contact.touching && (bodies.records[contact.body_a].awake || bodies.records[contact.body_b].awake);
}

// The constraint of one active contact: reads the contact and its bodies, writes `c` alone.
void build_constraint(ContactConstraint& c, int id, const CachedContact& contact, const Bodies& bodies) {
  const BodySim& sim_a = bodies.sims[contact.body_a];
  const BodySim& sim_b = bodies.sims[contact.body_b];
  c.body_a = contact.body_a;
  c.body_b = contact.body_b;
  c.cache_id = id;
  c.point_count = contact.manifold.point_count;
  c.normal = contact.manifold.normal;
  c.normal_frame = contact.manifold.normal_frame;
  c.inv_mass_a = sim_a.inv_mass;
  c.inv_inertia_a = sim_a.inv_inertia;
  c.inv_mass_b = sim_b.inv_mass;
  c.inv_inertia_b = sim_b.inv_inertia;
  c.restitution = contact.restitution;

  // The manifold is in a frame centred on body a's origin; move it to the centres of mass.
  const FxVec2f center_a = rotate(sim_a.rotation, sim_a.local_center);
  const FxVec2f center_b = bodies.center_offset(contact.body_a, contact.body_b) + center_a;
  const FxVec2f tangent = right_perp(c.normal);
  float sliding_speed = 0.0f;
  for (int i = 0; i < c.point_count; ++i) {
    const ManifoldPoint& mp = contact.manifold.points[i];
    ContactPointConstraint& p = c.points[i];
    p.anchor_a = mp.point - center_a;
    p.anchor_b = mp.point - center_b;
    p.adjusted_separation = mp.separation - dot(p.anchor_b - p.anchor_a, c.normal);
    p.normal_mass = effective_mass(c, p.anchor_a, p.anchor_b, c.normal);
    p.tangent_mass = effective_mass(c, p.anchor_a, p.anchor_b, tangent);
    p.normal_impulse = contact.normal_impulse[i];
    p.tangent_impulse = contact.tangent_impulse[i];
    p.max_normal_impulse = 0.0f;
    const FxVec2f dv = (sim_b.linear_velocity + cross(sim_b.angular_velocity, p.anchor_b)) -
                       (sim_a.linear_velocity + cross(sim_a.angular_velocity, p.anchor_a));
    p.relative_velocity = dot(dv, c.normal);
    sliding_speed = std::max(sliding_speed, std::fabs(dot(dv, tangent)));
  }
  c.friction = sliding_speed > sticking_speed ? contact.dynamic_friction : contact.static_friction;
}

}  // namespace

void ContactSolver::reserve(std::size_t constraint_count) {
  constraints.reserve(constraint_count);
  sources_.reserve(constraint_count);
}

void ContactSolver::prepare(const ContactCache& contacts, const Bodies& bodies, const Tasks& tasks) {
  constraints.clear();
  if (!tasks.runs_in_parallel(static_cast<std::uint32_t>(contacts.touching_count), min_parallel_constraints)) {
    for (int id = 0; id < static_cast<int>(contacts.slots.size()); ++id) {
      const CachedContact& contact = contacts.slots[id];
      if (is_active(contact, bodies)) build_constraint(constraints.emplace_back(), id, contact, bodies);
    }
    return;
  }
  // Which contacts become constraints, in cache order, on this thread; then each constraint in
  // ranges, each writing only its own.
  sources_.clear();
  for (int id = 0; id < static_cast<int>(contacts.slots.size()); ++id) {
    if (is_active(contacts.slots[id], bodies)) sources_.push_back(id);
  }
  constraints.resize(sources_.size());
  tasks.for_each_range(static_cast<std::uint32_t>(sources_.size()), constraints_per_block, min_parallel_constraints,
                       [&](std::uint32_t first, std::uint32_t last) {
                         for (std::uint32_t i = first; i < last; ++i) {
                           build_constraint(constraints[i], sources_[i], contacts.slots[sources_[i]], bodies);
                         }
                       });
}

void ContactSolver::apply_restitution(std::span<FxBodyState> states, float threshold) {
  for (ContactConstraint& c : constraints) {
    if (c.restitution == 0.0f) continue;
    FxBodyState& a = states[c.body_a];
    FxBodyState& b = states[c.body_b];
    for (int i = 0; i < c.point_count; ++i) {
      ContactPointConstraint& p = c.points[i];
      if (p.relative_velocity > -threshold || p.max_normal_impulse == 0.0f) continue;
      const float vn = dot(point_velocity(b, p.anchor_b) - point_velocity(a, p.anchor_a), c.normal);
      const float delta = -p.normal_mass * (vn + c.restitution * p.relative_velocity);
      const float accumulated = std::max(p.normal_impulse + delta, 0.0f);
      const float applied = accumulated - p.normal_impulse;
      p.normal_impulse = accumulated;
      apply_impulse(a, b, c, p, applied * c.normal);
    }
  }
}

void ContactSolver::project_positions(std::span<FxBodyState> states, float linear_slop) const {
  for (const ContactConstraint& c : constraints) {
    FxBodyState& a = states[c.body_a];
    FxBodyState& b = states[c.body_b];
    for (int i = 0; i < c.point_count; ++i) {
      const ContactPointConstraint& p = c.points[i];
      const float separation = current_separation(a, b, c.normal, p);
      const float correction = std::clamp(projection_fraction * (separation + linear_slop), -max_projection, 0.0f);
      if (correction == 0.0f) continue;
      const FxVec2f moved_a = rotate(a.delta_rotation, p.anchor_a);
      const FxVec2f moved_b = rotate(b.delta_rotation, p.anchor_b);
      const float mass = effective_mass(c, moved_a, moved_b, c.normal);
      const FxVec2f impulse = (-correction * mass) * c.normal;
      a.delta_position -= c.inv_mass_a * impulse;
      a.delta_rotation = integrate_rotation(a.delta_rotation, -c.inv_inertia_a * cross(moved_a, impulse));
      b.delta_position += c.inv_mass_b * impulse;
      b.delta_rotation = integrate_rotation(b.delta_rotation, c.inv_inertia_b * cross(moved_b, impulse));
    }
  }
}

void ContactSolver::store_impulses(ContactCache& cache) const {
  for (const ContactConstraint& c : constraints) {
    CachedContact& contact = cache.slots[c.cache_id];
    for (int i = 0; i < c.point_count; ++i) {
      contact.normal_impulse[i] = c.points[i].normal_impulse;
      contact.tangent_impulse[i] = c.points[i].tangent_impulse;
    }
  }
}

}  // namespace fx2d::detail

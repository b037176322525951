// Building the step's contact constraints into the batches' columns (contact_batch.h): pack()
// lays each colour's constraints, then the overflow's, into eight-lane batches by point count,
// then works each constraint out from its contact straight into its lane, with the per-lane
// couplings between a batch's rows. The passes over the batches are contact_batch.cpp.
#include <algorithm>
#include <cmath>

#include "collision/contact_cache.h"
#include "solver/contact_batch.h"
#include "world/bodies.h"

namespace fx2d::detail {
namespace {

// Below this tangential speed (m/s) a contact counts as sticking and static friction applies.
constexpr float sticking_speed = 0.01f;

// Batches are built in ranges of as many batches as hold constraints_per_block constraints, and
// spread from as many as hold min_parallel_constraints.
constexpr std::uint32_t batches_per_block = constraints_per_block / lane_count;
constexpr std::uint32_t min_parallel_batch_builds = min_parallel_constraints / lane_count;

// Row s's lever arms times row r's spins, arm_a(s) spin_a(r) + arm_b(s) spin_b(r), in one lane.
float arms_times_spins(const float* arm_a, const float* arm_b, const float* spin_a, const float* spin_b,
                       int lane) {
  return arm_a[lane] * spin_a[lane] + arm_b[lane] * spin_b[lane];
}

// How much row s's relative speed changes per unit impulse on row r: J_s M^-1 J_r^T, that is
// (m_a + m_b) (d_s . d_r) + arm_a(s) spin_a(r) + arm_b(s) spin_b(r). Normal and tangent are
// perpendicular, so the mass term appears only between rows of one direction.
void add_couplings(ContactBatch& k, int lane, int points, float mass_sum) {
  PointColumns* p = k.point;
  for (int s = 0; s < points; ++s) {
    for (int r = 0; r < points; ++r) {
      p[s].tangent_from_normal[r][lane] = arms_times_spins(p[s].arm_tangent_a, p[s].arm_tangent_b,
                                                           p[r].spin_normal_a, p[r].spin_normal_b, lane);
    }
  }
  if (points == 2) {
    k.normal1_from_normal0[lane] = mass_sum + arms_times_spins(p[1].arm_normal_a, p[1].arm_normal_b,
                                                               p[0].spin_normal_a, p[0].spin_normal_b, lane);
    k.tangent1_from_tangent0[lane] =
        mass_sum + arms_times_spins(p[1].arm_tangent_a, p[1].arm_tangent_b, p[0].spin_tangent_a,
                                    p[0].spin_tangent_b, lane);
  }
}

// The mass a row's impulse acts on, from its effective inverse mass: zero when nothing can move.
float mass_of(float inverse_mass) { return inverse_mass > 0.0f ? 1.0f / inverse_mass : 0.0f; }

// One row of a point along `direction`: the anchors' lever arms about it and the spins a unit
// impulse there gives each body.
struct Row {
  float arm_a, arm_b, spin_a, spin_b;
};

Row row_of(FxVec2f anchor_a, FxVec2f anchor_b, FxVec2f direction, float inv_inertia_a, float inv_inertia_b) {
  const float arm_a = cross(anchor_a, direction);
  const float arm_b = cross(anchor_b, direction);
  return {arm_a, arm_b, inv_inertia_a * arm_a, inv_inertia_b * arm_b};
}

// The constraint of one active contact, worked out into lane `lane` of `k`: reads the contact and
// its bodies, writes that lane alone.
void build_lane(ContactBatch& k, int lane, const ConstraintSource& source, const CachedContact& contact,
                const Bodies& bodies) {
  const BodySim& sim_a = bodies.sims[source.body_a];
  const BodySim& sim_b = bodies.sims[source.body_b];
  const FxVec2f normal = contact.manifold.normal;
  const FxVec2f tangent = right_perp(normal);
  const float inv_inertia_a = sim_a.inv_inertia, inv_inertia_b = sim_b.inv_inertia;
  const float mass_sum = sim_a.inv_mass + sim_b.inv_mass;
  k.body_a[lane] = source.body_a;
  k.body_b[lane] = source.body_b;
  k.normal_x[lane] = normal.x;
  k.normal_y[lane] = normal.y;
  k.mass_normal_ax[lane] = sim_a.inv_mass * normal.x;
  k.mass_normal_ay[lane] = sim_a.inv_mass * normal.y;
  k.mass_normal_bx[lane] = sim_b.inv_mass * normal.x;
  k.mass_normal_by[lane] = sim_b.inv_mass * normal.y;
  k.inv_mass_a[lane] = sim_a.inv_mass;
  k.inv_mass_b[lane] = sim_b.inv_mass;
  k.inv_inertia_a[lane] = inv_inertia_a;
  k.inv_inertia_b[lane] = inv_inertia_b;
  k.restitution[lane] = contact.restitution;

  // The manifold is in a frame centred on body a's origin; move it to the centres of mass.
  const FxVec2f center_a = rotate(sim_a.rotation, sim_a.local_center);
  const FxVec2f center_b = bodies.center_offset(source.body_a, source.body_b) + center_a;
  float sliding_speed = 0.0f;
  for (int i = 0; i < source.point_count; ++i) {
    const ManifoldPoint& mp = contact.manifold.points[i];
    PointColumns& column = k.point[i];
    const FxVec2f anchor_a = mp.point - center_a;
    const FxVec2f anchor_b = mp.point - center_b;
    column.anchor_ax[lane] = anchor_a.x;
    column.anchor_ay[lane] = anchor_a.y;
    column.anchor_bx[lane] = anchor_b.x;
    column.anchor_by[lane] = anchor_b.y;
    column.adjusted_separation[lane] = mp.separation - dot(anchor_b - anchor_a, normal);
    const Row along_normal = row_of(anchor_a, anchor_b, normal, inv_inertia_a, inv_inertia_b);
    const Row along_tangent = row_of(anchor_a, anchor_b, tangent, inv_inertia_a, inv_inertia_b);
    column.arm_normal_a[lane] = along_normal.arm_a;
    column.arm_normal_b[lane] = along_normal.arm_b;
    column.arm_tangent_a[lane] = along_tangent.arm_a;
    column.arm_tangent_b[lane] = along_tangent.arm_b;
    column.spin_normal_a[lane] = along_normal.spin_a;
    column.spin_normal_b[lane] = along_normal.spin_b;
    column.spin_tangent_a[lane] = along_tangent.spin_a;
    column.spin_tangent_b[lane] = along_tangent.spin_b;
    // 1 / (J M^-1 J^T): m_a + m_b, plus each lever arm times the spin it gives.
    column.normal_mass[lane] =
        mass_of(mass_sum + along_normal.spin_a * along_normal.arm_a + along_normal.spin_b * along_normal.arm_b);
    column.tangent_mass[lane] =
        mass_of(mass_sum + along_tangent.spin_a * along_tangent.arm_a + along_tangent.spin_b * along_tangent.arm_b);
    column.normal_impulse[lane] = contact.normal_impulse[i];
    column.tangent_impulse[lane] = contact.tangent_impulse[i];
    column.max_normal_impulse[lane] = 0.0f;
    const FxVec2f dv = (sim_b.linear_velocity + cross(sim_b.angular_velocity, anchor_b)) -
                       (sim_a.linear_velocity + cross(sim_a.angular_velocity, anchor_a));
    k.relative_velocity[i][lane] = dot(dv, normal);
    sliding_speed = std::max(sliding_speed, std::fabs(dot(dv, tangent)));
  }
  k.friction[lane] = sliding_speed > sticking_speed ? contact.dynamic_friction : contact.static_friction;
  add_couplings(k, lane, source.point_count, mass_sum);
}

}  // namespace

void ContactBatches::add_runs(const ContactGraph& graph, int colour, bool serial) {
  for (int points = 1; points <= 2; ++points) {
    const std::span<const int> members = graph.members(colour, points);
    const int count = static_cast<int>((members.size() + lane_count - 1) / lane_count);
    if (count == 0) continue;
    runs_.push_back({static_cast<int>(members_.size()), count, points, serial});
    for (std::size_t first = 0; first < members.size(); first += lane_count) {
      members_.push_back({members.data() + first, static_cast<int>(std::min<std::size_t>(lane_count, members.size() - first))});
    }
  }
}

void ContactBatches::build_batch(int index, std::span<const ConstraintSource> constraints,
                                 const ContactCache& contacts, const Bodies& bodies, std::uint32_t padding_body) {
  ContactBatch& k = batches_[index];
  const BatchMembers members = members_[index];
  // Padding lanes point at the padding body with every value zero, so they change nothing.
  if (members.count < lane_count) {
    k = ContactBatch{};
    std::fill(std::begin(k.body_a) + members.count, std::end(k.body_a), padding_body);
    std::fill(std::begin(k.body_b) + members.count, std::end(k.body_b), padding_body);
  }
  for (int lane = 0; lane < members.count; ++lane) {
    const int constraint = members.first[lane];
    const ConstraintSource& source = constraints[constraint];
    build_lane(k, lane, source, contacts.slots[source.cache_id], bodies);
    lanes_[constraint] = index * lane_count + lane;
  }
}

void ContactBatches::reserve(std::size_t constraints) {
  // Full batches, plus one partly filled batch per run: two runs per colour and two for overflow.
  batches_.reserve(constraints / lane_count + 2 * (ContactGraph::max_colours + 1));
  members_.reserve(batches_.capacity());
  deep_.reserve(batches_.capacity());
  lanes_.reserve(constraints);
  runs_.reserve(2 * (ContactGraph::max_colours + 1));
}

void ContactBatches::pack(std::span<const ConstraintSource> constraints, const ContactGraph& graph,
                          const ContactCache& contacts, const Bodies& bodies, std::uint32_t padding_body,
                          const Tasks& tasks, bool scalar) {
  members_.clear();
  runs_.clear();
  colour_count_ = graph.colour_count();
  std::uint32_t widest_colour = 0;
  for (int colour = 0; colour < colour_count_; ++colour) {
    first_run_[colour] = static_cast<int>(runs_.size());
    const auto first_batch = members_.size();
    add_runs(graph, colour, false);
    widest_colour = std::max(widest_colour, static_cast<std::uint32_t>(members_.size() - first_batch));
  }
  first_run_[colour_count_] = static_cast<int>(runs_.size());
  add_runs(graph, ContactGraph::overflow, true);
  batch_count_ = static_cast<int>(members_.size());
  if (batches_.size() < members_.size()) batches_.resize(members_.size());
  lanes_.resize(constraints.size());
  // Each range builds only its own batches and the lane indices of their constraints.
  tasks.for_each_range(static_cast<std::uint32_t>(batch_count_), batches_per_block, min_parallel_batch_builds,
                       [&](std::uint32_t first, std::uint32_t last) {
                         for (std::uint32_t i = first; i < last; ++i) {
                           build_batch(static_cast<int>(i), constraints, contacts, bodies, padding_body);
                         }
                       });
  // The scalar twin is a check of the lanes' arithmetic, and its lane-by-lane write-back of a
  // shared static body would race: it stays on one thread.
  spread_ = !scalar && tasks.runs_in_parallel(widest_colour, min_parallel_batches);
  // Every mark is written by update_separations() before a pass reads it.
  deep_.resize(members_.size());
  any_deep_ = false;
}

}  // namespace fx2d::detail

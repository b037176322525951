// Building the step's contact constraints into the batches' columns (contact_batch.h): pack()
// lays each colour's constraints, then the overflow's, into eight-lane batches by point count,
// then copies what each contact and its bodies bring, one lane at a time, and works out what
// follows from it (anchors, separations, velocities before the step, friction, lever arms,
// effective masses, the couplings between a batch's rows) for all eight lanes at once (done lane by
// lane, that arithmetic cost 1.6 times the instructions of the rest of the packing). The passes
// over the batches are contact_batch.cpp.
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

// The mass a row's impulse acts on, from its effective inverse mass: zero when nothing can move.
FX2D_LANE_INLINE float mass_of(float inverse_mass) {
  return inverse_mass > 0.0f ? 1.0f / inverse_mass : 0.0f;
}

// What the lanes of a batch work out together from what their contacts and bodies bring
// (derive_points): each lane's bodies' poses, centres of mass and velocities, its points and
// frictions. Copied here (the bodies' as whole rows, gather_bodies()), so that the arithmetic runs
// on all eight lanes at once.
struct LaneInputs {
  // Per body: rotation, centre of mass in the body frame, origin and its carry, velocities.
  float rotation_ac[lane_count], rotation_as[lane_count], rotation_bc[lane_count], rotation_bs[lane_count];
  float local_center_ax[lane_count], local_center_ay[lane_count];
  float local_center_bx[lane_count], local_center_by[lane_count];
  float origin_ax[lane_count], origin_ay[lane_count], origin_bx[lane_count], origin_by[lane_count];
  float carry_ax[lane_count], carry_ay[lane_count], carry_bx[lane_count], carry_by[lane_count];
  float velocity_ax[lane_count], velocity_ay[lane_count], velocity_bx[lane_count], velocity_by[lane_count];
  float spin_a[lane_count], spin_b[lane_count];
  float static_friction[lane_count], dynamic_friction[lane_count];
  // Per manifold point, in the frame centred on body a's origin.
  float point_x[2][lane_count], point_y[2][lane_count];
  float separation[2][lane_count];
};

// What one contact brings to its lane, besides its bodies' rows: what the passes read of it as it
// is (bodies, normal, inverse inertias, restitution, impulses) straight into the batch; what is
// worked out from it into `in`. Writes that lane alone. `Points` is the contact's point count,
// the batch's.
template <int Points>
void gather_lane(ContactBatch& k, LaneInputs& in, int lane, const ConstraintSource& source,
                 const CachedContact& contact, const Bodies& bodies) {
  k.state_a[lane] = state_offset(source.body_a);
  k.state_b[lane] = state_offset(source.body_b);
  k.normal_x[lane] = contact.manifold.normal.x;
  k.normal_y[lane] = contact.manifold.normal.y;
  k.normal_frame[lane] = static_cast<std::int32_t>(contact.manifold.normal_frame);
  k.round_sides[lane] = (contact.round_a ? round_side_a : 0) | (contact.round_b ? round_side_b : 0);
  k.inv_inertia_a[lane] = bodies.sims[source.body_a].inv_inertia;
  k.inv_inertia_b[lane] = bodies.sims[source.body_b].inv_inertia;
  k.restitution[lane] = contact.restitution;
  in.static_friction[lane] = contact.static_friction;
  in.dynamic_friction[lane] = contact.dynamic_friction;
  for (int i = 0; i < Points; ++i) {
    const ManifoldPoint& mp = contact.manifold.points[i];
    in.point_x[i][lane] = mp.point.x;
    in.point_y[i][lane] = mp.point.y;
    in.separation[i][lane] = mp.separation;
    k.point[i].normal_impulse[lane] = contact.normal_impulse[i];
    k.point[i].tangent_impulse[lane] = contact.tangent_impulse[i];
    k.point[i].max_normal_impulse[lane] = 0.0f;
  }
}

// Zeroes the lanes from `count` on: padding lanes, whose sims gather_bodies() read from lane 0's
// body, must bring zeros (derive_points).
FX2D_LANE_INLINE void clear_padding(LaneColumns& c, int count) {
  using LaneMask = std::int32_t __attribute__((vector_size(32)));
  const LaneMask lane = {0, 1, 2, 3, 4, 5, 6, 7};
  const LaneMask keep = lane < count;
  c.c0 = reinterpret_cast<LaneColumn>(reinterpret_cast<LaneMask>(c.c0) & keep);
  c.c1 = reinterpret_cast<LaneColumn>(reinterpret_cast<LaneMask>(c.c1) & keep);
  c.c2 = reinterpret_cast<LaneColumn>(reinterpret_cast<LaneMask>(c.c2) & keep);
  c.c3 = reinterpret_cast<LaneColumn>(reinterpret_cast<LaneMask>(c.c3) & keep);
}

// Where gather_side() puts one side's columns: LaneInputs' for that side, and the batch's inverse
// masses.
struct SideInputs {
  float* rotation_c;
  float* rotation_s;
  float* local_center_x;
  float* local_center_y;
  float* origin_x;
  float* origin_y;
  float* carry_x;
  float* carry_y;
  float* velocity_x;
  float* velocity_y;
  float* spin;
  float* inv_mass;
};

// One side's bodies (`batch_state`, `count` of them; lane 0's stands in for the padding body, which
// has no sim) as rows of their sims turned into columns: three row gathers instead of eleven
// single-float copies per lane.
FX2D_LANE_INLINE void gather_side(const BodySim* __restrict sims, const std::uint32_t* batch_state, int count,
                                  const SideInputs& side) {
  std::uint32_t body[lane_count];
  for (int lane = 0; lane < lane_count; ++lane)
    body[lane] = state_index(batch_state[lane < count ? lane : 0]);
  LaneColumns place, turn, velocity;
  gather_columns<sim_place_row>(sims, body, place);
  gather_columns<sim_turn_row>(sims, body, turn);
  gather_columns<sim_velocity_row>(sims, body, velocity);
  if (count < lane_count) {
    clear_padding(place, count);
    clear_padding(turn, count);
    clear_padding(velocity, count);
  }
  to_lanes(place.c0, side.origin_x), to_lanes(place.c1, side.origin_y);
  to_lanes(place.c2, side.carry_x), to_lanes(place.c3, side.carry_y);
  to_lanes(turn.c0, side.rotation_c), to_lanes(turn.c1, side.rotation_s);
  to_lanes(turn.c2, side.local_center_x), to_lanes(turn.c3, side.local_center_y);
  to_lanes(velocity.c0, side.velocity_x), to_lanes(velocity.c1, side.velocity_y);
  to_lanes(velocity.c2, side.spin), to_lanes(velocity.c3, side.inv_mass);
}

// Both sides' bodies of the first `count` lanes, whose bodies gather_lane() wrote into `k`. A lane
// kernel of its own: in the baseline (SSE2) build the eight-lane shuffles cost more than the
// single-float copies they replace, and inside derive_batch() Clang no longer vectorises
// derive_points().
FX2D_LANE_KERNEL void gather_bodies(ContactBatch& __restrict k, LaneInputs& __restrict in, int count,
                                    const BodySim* __restrict sims) {
  gather_side(
      sims, k.state_a, count,
      {in.rotation_ac, in.rotation_as, in.local_center_ax, in.local_center_ay, in.origin_ax, in.origin_ay,
       in.carry_ax, in.carry_ay, in.velocity_ax, in.velocity_ay, in.spin_a, k.inv_mass_a});
  gather_side(
      sims, k.state_b, count,
      {in.rotation_bc, in.rotation_bs, in.local_center_bx, in.local_center_by, in.origin_bx, in.origin_by,
       in.carry_bx, in.carry_by, in.velocity_bx, in.velocity_by, in.spin_b, k.inv_mass_b});
}

// Per lane, from the inputs gather_lane() wrote: the anchors (the points moved from body a's
// origin to each body's centre of mass, as Bodies::center_offset() does it), the separation at
// the centres, what restitution and friction need from the velocities before the step, and the
// friction that applies (static below sticking_speed). The operations are those of the vector
// helpers in Math.h, in their order, so every lane gets the bits a scalar version would.
template <int Points>
FX2D_LANE_INLINE void derive_points(ContactBatch& __restrict k, const LaneInputs& __restrict in) {
  // check-vectorized(2): the lane loop below, for one and two points, must be vectorised. Padding
  // lanes, whose inputs are all zero, come out zero.
  for (int lane = 0; lane < lane_count; ++lane) {
    const float nx = k.normal_x[lane], ny = k.normal_y[lane];
    const float ac = in.rotation_ac[lane], as = in.rotation_as[lane];
    const float bc = in.rotation_bc[lane], bs = in.rotation_bs[lane];
    const float lax = in.local_center_ax[lane], lay = in.local_center_ay[lane];
    const float lbx = in.local_center_bx[lane], lby = in.local_center_by[lane];
    // rotate(rotation_a, local_center_a), and center_offset(a, b) + that.
    const float center_ax = ac * lax - as * lay, center_ay = as * lax + ac * lay;
    const float origin_offset_x =
        (in.origin_bx[lane] - in.origin_ax[lane]) - (in.carry_bx[lane] - in.carry_ax[lane]);
    const float origin_offset_y =
        (in.origin_by[lane] - in.origin_ay[lane]) - (in.carry_by[lane] - in.carry_ay[lane]);
    const float center_bx = ((origin_offset_x + (bc * lbx - bs * lby)) - center_ax) + center_ax;
    const float center_by = ((origin_offset_y + (bs * lbx + bc * lby)) - center_ay) + center_ay;
    const float wa = in.spin_a[lane], wb = in.spin_b[lane];
    // Whether a point slides faster than sticking_speed: what max(|tangent speeds|) >
    // sticking_speed says, but as |=, which the SSE2 clone vectorises and a select chain is not.
    bool sliding = false;
    for (int i = 0; i < Points; ++i) {
      PointColumns& p = k.point[i];
      const float ax = in.point_x[i][lane] - center_ax, ay = in.point_y[i][lane] - center_ay;
      const float bx = in.point_x[i][lane] - center_bx, by = in.point_y[i][lane] - center_by;
      p.anchor_ax[lane] = ax;
      p.anchor_ay[lane] = ay;
      p.anchor_bx[lane] = bx;
      p.anchor_by[lane] = by;
      p.adjusted_separation[lane] = in.separation[i][lane] - ((bx - ax) * nx + (by - ay) * ny);
      // (v_b + cross(w_b, anchor_b)) - (v_a + cross(w_a, anchor_a)), along the normal and the
      // tangent right_perp(normal) = (ny, -nx).
      const float dvx = (in.velocity_bx[lane] + -wb * by) - (in.velocity_ax[lane] + -wa * ay);
      const float dvy = (in.velocity_by[lane] + wb * bx) - (in.velocity_ay[lane] + wa * ax);
      k.relative_velocity[i][lane] = dvx * nx + dvy * ny;
      sliding |= std::fabs(dvx * ny + dvy * -nx) > sticking_speed;
    }
    // Both read before the choice: a choice between two loads is not vectorised in the SSE2 clone.
    const float dynamic_friction = in.dynamic_friction[lane], static_friction = in.static_friction[lane];
    k.friction[lane] = sliding ? dynamic_friction : static_friction;
  }
}

// The rows of every lane of a batch, from the normals and inverse masses gather_lane() wrote and
// the anchors derive_points() worked out: each body's inverse mass times the normal; per point
// the lever arms about the normal and the tangent right_perp(normal) = (ny, -nx), the spins a
// unit impulse there gives, the effective masses 1 / (J M^-1 J^T); and the couplings between rows,
// J_s M^-1 J_r^T, that is
// (m_a + m_b) (d_s . d_r) + arm_a(s) spin_a(r) + arm_b(s) spin_b(r): normal and tangent are
// perpendicular, so the mass term appears only between rows of one direction.
template <int Points>
FX2D_LANE_INLINE void derive_rows(ContactBatch& __restrict k) {
  // check-vectorized(2): the lane loop below, for one and two points, must be vectorised. Lanes
  // are independent and padding lanes, all zero, come out zero.
  for (int lane = 0; lane < lane_count; ++lane) {
    const float nx = k.normal_x[lane], ny = k.normal_y[lane];
    const float inv_mass_a = k.inv_mass_a[lane], inv_mass_b = k.inv_mass_b[lane];
    const float inv_inertia_a = k.inv_inertia_a[lane], inv_inertia_b = k.inv_inertia_b[lane];
    k.mass_normal_ax[lane] = inv_mass_a * nx;
    k.mass_normal_ay[lane] = inv_mass_a * ny;
    k.mass_normal_bx[lane] = inv_mass_b * nx;
    k.mass_normal_by[lane] = inv_mass_b * ny;
    const float mass_sum = inv_mass_a + inv_mass_b;
    float arm_na[Points], arm_nb[Points], arm_ta[Points], arm_tb[Points];
    float spin_na[Points], spin_nb[Points], spin_ta[Points], spin_tb[Points];
    for (int i = 0; i < Points; ++i) {
      PointColumns& p = k.point[i];
      const float ax = p.anchor_ax[lane], ay = p.anchor_ay[lane], bx = p.anchor_bx[lane], by = p.anchor_by[lane];
      arm_na[i] = ax * ny - ay * nx;
      arm_nb[i] = bx * ny - by * nx;
      arm_ta[i] = ax * -nx - ay * ny;
      arm_tb[i] = bx * -nx - by * ny;
      spin_na[i] = inv_inertia_a * arm_na[i];
      spin_nb[i] = inv_inertia_b * arm_nb[i];
      spin_ta[i] = inv_inertia_a * arm_ta[i];
      spin_tb[i] = inv_inertia_b * arm_tb[i];
      p.arm_normal_a[lane] = arm_na[i];
      p.arm_normal_b[lane] = arm_nb[i];
      p.arm_tangent_a[lane] = arm_ta[i];
      p.arm_tangent_b[lane] = arm_tb[i];
      p.spin_normal_a[lane] = spin_na[i];
      p.spin_normal_b[lane] = spin_nb[i];
      p.spin_tangent_a[lane] = spin_ta[i];
      p.spin_tangent_b[lane] = spin_tb[i];
      p.normal_mass[lane] = mass_of(mass_sum + spin_na[i] * arm_na[i] + spin_nb[i] * arm_nb[i]);
      p.tangent_mass[lane] = mass_of(mass_sum + spin_ta[i] * arm_ta[i] + spin_tb[i] * arm_tb[i]);
    }
    for (int s = 0; s < Points; ++s) {
      for (int r = 0; r < Points; ++r) {
        k.point[s].tangent_from_normal[r][lane] = arm_ta[s] * spin_na[r] + arm_tb[s] * spin_nb[r];
      }
    }
    if constexpr (Points == 2) {
      k.normal1_from_normal0[lane] = mass_sum + (arm_na[1] * spin_na[0] + arm_nb[1] * spin_nb[0]);
      k.tangent1_from_tangent0[lane] = mass_sum + (arm_ta[1] * spin_ta[0] + arm_tb[1] * spin_tb[0]);
    }
  }
}

FX2D_LANE_KERNEL void derive_batch(ContactBatch& __restrict k, const LaneInputs& __restrict in, int points) {
  if (points == 1) {
    derive_points<1>(k, in);
    derive_rows<1>(k);
  } else {
    derive_points<2>(k, in);
    derive_rows<2>(k);
  }
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
  LaneInputs inputs;
  // Padding lanes point at the padding body with every value zero, so they change nothing.
  if (members.count < lane_count) {
    k = ContactBatch{};
    inputs = LaneInputs{};
    std::fill(std::begin(k.state_a) + members.count, std::end(k.state_a), state_offset(padding_body));
    std::fill(std::begin(k.state_b) + members.count, std::end(k.state_b), state_offset(padding_body));
  }
  const int points = constraints[members.first[0]].point_count;
  for (int lane = 0; lane < members.count; ++lane) {
    const int constraint = members.first[lane];
    const ConstraintSource& source = constraints[constraint];
    const CachedContact& contact = contacts.slots[source.cache_id];
    if (points == 1) {
      gather_lane<1>(k, inputs, lane, source, contact, bodies);
    } else {
      gather_lane<2>(k, inputs, lane, source, contact, bodies);
    }
    lanes_[constraint] = index * lane_count + lane;
  }
  gather_bodies(k, inputs, members.count, bodies.sims.data());
  derive_batch(k, inputs, points);
}

void ContactBatches::reserve(std::size_t constraints) {
  // Full batches, plus one partly filled batch per run: two runs per colour and two for overflow.
  batches_.reserve(constraints / lane_count + 2 * (ContactGraph::max_colours + 1));
  members_.reserve(batches_.capacity());
  deep_.reserve(batches_.capacity());
  projected_lanes_.reserve(batches_.capacity());
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
  projected_lanes_.resize(members_.size());
}

}  // namespace fx2d::detail

// Moving contact constraints in and out of the batches' columns (contact_batch.h): pack() lays
// each colour's constraints, then the overflow's, into eight-lane batches by point count, with
// the per-lane couplings between a batch's rows worked out once; unpack() copies the impulses
// back for the next step's warm start. The passes over the batches are contact_batch.cpp.
#include "solver/contact_batch.h"

#include <algorithm>

namespace fx2d::detail {
namespace {

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

}  // namespace

void ContactBatches::add_runs(std::span<const ContactConstraint> constraints, std::span<const int> members, bool serial,
                              std::uint32_t padding_body) {
  for (int points = 1; points <= 2; ++points) {
    BatchRun run{static_cast<int>(batches_.size()), 0, points, serial};
    int lane = lane_count;
    for (const int index : members) {
      const ContactConstraint& c = constraints[index];
      if (c.point_count != points) continue;
      if (lane == lane_count) {
        ContactBatch& fresh = batches_.emplace_back();
        fresh = ContactBatch{};
        std::fill(std::begin(fresh.body_a), std::end(fresh.body_a), padding_body);
        std::fill(std::begin(fresh.body_b), std::end(fresh.body_b), padding_body);
        std::fill(std::begin(fresh.constraint), std::end(fresh.constraint), -1);
        ++run.count;
        lane = 0;
      }
      ContactBatch& k = batches_.back();
      k.body_a[lane] = c.body_a;
      k.body_b[lane] = c.body_b;
      k.normal_x[lane] = c.normal.x;
      k.normal_y[lane] = c.normal.y;
      k.normal_frame[lane] = static_cast<std::int32_t>(c.normal_frame);
      k.mass_normal_ax[lane] = c.inv_mass_a * c.normal.x;
      k.mass_normal_ay[lane] = c.inv_mass_a * c.normal.y;
      k.mass_normal_bx[lane] = c.inv_mass_b * c.normal.x;
      k.mass_normal_by[lane] = c.inv_mass_b * c.normal.y;
      k.friction[lane] = c.friction;
      k.constraint[lane] = index;
      const FxVec2f tangent = right_perp(c.normal);
      for (int i = 0; i < points; ++i) {
        const ContactPointConstraint& cp = c.points[i];
        PointColumns& column = k.point[i];
        column.anchor_ax[lane] = cp.anchor_a.x;
        column.anchor_ay[lane] = cp.anchor_a.y;
        column.anchor_bx[lane] = cp.anchor_b.x;
        column.anchor_by[lane] = cp.anchor_b.y;
        column.adjusted_separation[lane] = cp.adjusted_separation;
        column.normal_mass[lane] = cp.normal_mass;
        column.tangent_mass[lane] = cp.tangent_mass;
        column.normal_impulse[lane] = cp.normal_impulse;
        column.tangent_impulse[lane] = cp.tangent_impulse;
        column.max_normal_impulse[lane] = 0.0f;
        column.arm_normal_a[lane] = cross(cp.anchor_a, c.normal);
        column.arm_normal_b[lane] = cross(cp.anchor_b, c.normal);
        column.arm_tangent_a[lane] = cross(cp.anchor_a, tangent);
        column.arm_tangent_b[lane] = cross(cp.anchor_b, tangent);
        column.spin_normal_a[lane] = c.inv_inertia_a * column.arm_normal_a[lane];
        column.spin_normal_b[lane] = c.inv_inertia_b * column.arm_normal_b[lane];
        column.spin_tangent_a[lane] = c.inv_inertia_a * column.arm_tangent_a[lane];
        column.spin_tangent_b[lane] = c.inv_inertia_b * column.arm_tangent_b[lane];
      }
      add_couplings(k, lane, points, c.inv_mass_a + c.inv_mass_b);
      ++lane;
    }
    if (run.count > 0) runs_.push_back(run);
  }
}

void ContactBatches::reserve(std::size_t constraints) {
  // Full batches, plus one partly filled batch per run: two runs per colour and two for overflow.
  batches_.reserve(constraints / lane_count + 2 * (ContactGraph::max_colours + 1));
  deep_.reserve(batches_.capacity());
  runs_.reserve(2 * (ContactGraph::max_colours + 1));
}

void ContactBatches::pack(std::span<const ContactConstraint> constraints, const ContactGraph& graph,
                          std::uint32_t padding_body, const Tasks& tasks, bool scalar) {
  batches_.clear();
  runs_.clear();
  colour_count_ = graph.colour_count();
  std::uint32_t widest_colour = 0;
  for (int colour = 0; colour < colour_count_; ++colour) {
    first_run_[colour] = static_cast<int>(runs_.size());
    const auto first_batch = batches_.size();
    add_runs(constraints, graph.members(colour), false, padding_body);
    widest_colour = std::max(widest_colour, static_cast<std::uint32_t>(batches_.size() - first_batch));
  }
  first_run_[colour_count_] = static_cast<int>(runs_.size());
  add_runs(constraints, graph.members(ContactGraph::overflow), true, padding_body);
  // The scalar twin is a check of the lanes' arithmetic, and its lane-by-lane write-back of a
  // shared static body would race: it stays on one thread.
  spread_ = !scalar && tasks.runs_in_parallel(widest_colour, min_parallel_batches);
  deep_.assign(batches_.size(), 0);
  any_deep_ = false;
}

void ContactBatches::unpack(std::span<ContactConstraint> constraints) const {
  for (const BatchRun& run : runs_) {
    for (int i = run.first; i < run.first + run.count; ++i) {
      const ContactBatch& k = batches_[i];
      for (int lane = 0; lane < lane_count; ++lane) {
        if (k.constraint[lane] < 0) continue;
        ContactConstraint& c = constraints[k.constraint[lane]];
        for (int p = 0; p < run.point_count; ++p) {
          c.points[p].normal_impulse = k.point[p].normal_impulse[lane];
          c.points[p].tangent_impulse = k.point[p].tangent_impulse[lane];
          c.points[p].max_normal_impulse = k.point[p].max_normal_impulse[lane];
        }
      }
    }
  }
}

}  // namespace fx2d::detail

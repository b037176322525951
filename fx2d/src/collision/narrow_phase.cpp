// Narrow phase: refresh the manifold of every cached pair that has an awake body, once per step.
// Pairs whose fat boxes separated are destroyed; a pair that begins touching a sleeping body
// wakes it. Each pair is collided in a frame centred on body a's origin, built from the precise
// (carried) positions, so coordinates stay small however far the pair is from the world origin.
#include "collision/narrow_phase.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

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

// True when a point of `manifold` is closer than `distance`.
bool any_point_within(const Manifold& manifold, float distance) {
  for (int i = 0; i < manifold.point_count; ++i) {
    if (manifold.points[i].separation < distance) return true;
  }
  return false;
}

// manifold_reuse_distance()'s bounds: at most this (metres), and this share of the shortest edge.
// Below base_speculative_distance, so that a point the full collision left out stays apart. Against
// 2 mm for every pair, 4 mm for 1 m boxes made settling_boxes 200's step 0.937 (collide 0.890,
// instructions 0.952), and 8 mm 0.971 of that again (collide 0.960); the median peak penetration
// over 7 runs with gravity perturbed went 1.73 -> 1.71 -> 1.73 mm (800: 5.52 -> 5.27 -> 5.10,
// 3000: 46.4 -> 43.8 -> 46.0), and every stability boundary stayed.
constexpr float max_manifold_reuse_distance = 0.008f;
constexpr float manifold_reuse_share_of_edge = 0.02f;

// The length of a polygon's shortest edge; infinite for a circle, whose pairs keep no frame.
float shortest_edge(const FxShape& shape) {
  if (shape.type() != FxShapeType::polygon) return std::numeric_limits<float>::infinity();
  const std::span<const FxVec2f> vertices = shape.vertices();
  float shortest_squared = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    shortest_squared =
        std::min(shortest_squared, length_squared(vertices[(i + 1) % vertices.size()] - vertices[i]));
  }
  return std::sqrt(shortest_squared);
}

// Records where the pair stood when `manifold` was collided (contact_cache.h's ManifoldFrame).
ManifoldFrame frame_of(const Manifold& manifold, const FxTransform& xf_a, const FxTransform& xf_b) {
  ManifoldFrame frame;
  frame.b_in_a = inv_mul(xf_a, xf_b);
  frame.normal_in_a = inv_rotate(xf_a.q, manifold.normal);
  for (int i = 0; i < manifold.point_count; ++i) {
    const ManifoldPoint& point = manifold.points[i];
    const FxVec2f half_gap = (0.5f * point.separation) * manifold.normal;
    frame.on_a[i] = inv_transform_point(xf_a, point.point - half_gap);
    frame.on_b[i] = inv_transform_point(xf_b, point.point + half_gap);
  }
  frame.valid = manifold.point_count > 0;
  return frame;
}

// True when no point of B, seen from A, has moved more than `reuse_distance` since `frame`: the
// shift of B's origin plus the chord its turn sweeps at B's farthest point from that origin.
bool barely_moved(const ManifoldFrame& frame, const FxTransform& b_in_a, const FxShape& b,
                  float reuse_distance) {
  const FxRot turn = inv_mul(frame.b_in_a.q, b_in_a.q);
  const float chord = length(FxVec2f{turn.c - 1.0f, turn.s}) * (length(b.centroid()) + b.extent());
  return length(b_in_a.p - frame.b_in_a.p) + chord <= reuse_distance;
}

// Moves point i of `manifold` with the pair: midway between its two surface points as they are now,
// its separation measured between them along the manifold's normal.
void move_point(const ManifoldFrame& frame, const FxTransform& xf_a, const FxTransform& xf_b, int i,
                Manifold& manifold) {
  const FxVec2f on_a = transform_point(xf_a, frame.on_a[i]);
  const FxVec2f on_b = transform_point(xf_b, frame.on_b[i]);
  manifold.points[i].point = 0.5f * (on_a + on_b);
  manifold.points[i].separation = dot(on_b - on_a, manifold.normal);
}

// Moves `manifold`, the one `frame` recorded, to where the pair stands now: the same points, the
// normal turned with A, and each separation measured between the two surface points as they are now.
// Its feature ids, point count and separating face stay as they were. A frame is only made of a
// manifold with points, so the first is there; the second is written out rather than looped over,
// which the compiler vectorised for any count at twice the instructions.
void move_manifold(const ManifoldFrame& frame, const FxTransform& xf_a, const FxTransform& xf_b, Manifold& manifold) {
  manifold.normal = rotate(xf_a.q, frame.normal_in_a);
  move_point(frame, xf_a, xf_b, 0, manifold);
  if (manifold.point_count > 1) move_point(frame, xf_a, xf_b, 1, manifold);
}

// How fast two bodies could close within the step, for their speculative margin.
struct PairMotion {
  FxVec2f velocity_a, velocity_b;
  float spin_speed;  // what the spins add at the shapes' extents
  float fastest_closing() const;                 // along any direction
  float closing_along(FxVec2f normal) const;     // along `normal`, from A towards B
};

// Along a normal n from A to B, a pair closes at up to its relative speed, or at A's or B's own
// speed towards the other: either may stop against a third body mid-step while the other keeps
// going. A column falling in unison has no relative speed, yet its lowest body lands first and
// the next one closes on it at full speed. Spins add their speed at the shapes' extents.
PairMotion pair_motion(const BodySim& sa, const BodySim& sb, const FxShape& shape_a, const FxShape& shape_b) {
  return {sa.linear_velocity, sb.linear_velocity,
          std::fabs(sa.angular_velocity) * shape_a.extent() + std::fabs(sb.angular_velocity) * shape_b.extent()};
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

// True when a point of `manifold` lies within the speculative margin of the pair's closing speed
// along its normal. That margin is never below base_speculative_distance, so a point within the
// base, as every resting contact is, answers without the closing speed and its square root.
bool any_point_within_margin(const Manifold& manifold, float dt, const PairMotion& motion) {
  return any_point_within(manifold, base_speculative_distance) ||
         any_point_within(manifold, speculative_distance(dt, motion.closing_along(manifold.normal)));
}

// Every body's BodyReach: one pass over the sims in order, so that a pair apart then reads two
// rows of four floats rather than its bodies' records and sims.
void measure_reach(const Bodies& bodies, std::vector<BodyReach>& reach) {
  reach.resize(bodies.sims.size());
  for (std::size_t i = 0; i < reach.size(); ++i) reach[i] = reach_of(bodies.sims[i]);
}

// The pass that measures every body's reach pays from about one pair apart for eight bodies (each
// pair it spares the collision of costs some 20 ns, the pass 1.5 ns a body). It runs from one for
// four: not for a stack, whose pairs all touch.
constexpr std::size_t bodies_per_apart_pair = 4;

// The granule of the parallel collision's ranges, and the fewest pairs worth waking the workers for:
// on a quiet machine two workers took 0.66 of one's collide stage from pile 300 up (fx2d/src/README.md).
constexpr std::uint32_t pairs_per_block = 64;
constexpr std::uint32_t min_parallel_pairs = 256;

// The update of a pair collided: whether it began or stopped touching, as its record now says.
PairUpdate touching_update(CachedContact& contact) {
  switch (ContactCache::update_touching(contact)) {
    case 1: return PairUpdate::began_touching;
    case -1: return PairUpdate::stopped_touching;
    default: return PairUpdate::collided;
  }
}

// Keeps every point of a freshly collided `manifold` while any lies within the speculative margin
// of the pair's closing speed along its normal, else none.
void keep_points_within_margin(Manifold& manifold, float dt, const PairMotion& motion) {
  if (manifold.point_count > 0 && !any_point_within_margin(manifold, dt, motion)) manifold.point_count = 0;
}

// Collides a pair of circles. Its one point always has the same feature id and its normal turns
// with neither body, so the record keeps no frame and its point keeps its impulses while it lasts:
// what collide_pair's general path finds for circles, without copying out the record's impulses.
PairUpdate collide_circle_pair(CachedContact& contact, const FxShape& a, const FxTransform& xf_a, const FxShape& b,
                               const FxTransform& xf_b, float dt, const PairMotion& motion) {
  const bool had_point = contact.manifold.point_count > 0;
  Manifold& manifold = contact.manifold;
  collide_circles(a, xf_a, b, xf_b, speculative_distance(dt, motion.fastest_closing()), manifold);
  keep_points_within_margin(manifold, dt, motion);
  if (!had_point || manifold.point_count == 0) {
    contact.normal_impulse[0] = 0.0f;
    contact.tangent_impulse[0] = 0.0f;
  }
  return touching_update(contact);
}

// Collides one cached pair whose bodies were awake when read, writing only its own record's
// manifold, impulses and `touching`: leaves the cache's count and the bodies to settle_pair().
PairUpdate collide_pair(const StepContext& step, CachedContact& contact, const Bodies& bodies,
                        const AabbTree& tree, std::span<const BodyReach> reach) {
  const std::uint32_t a = contact.body_a;
  const std::uint32_t b = contact.body_b;
  const BodyRecord& ra = bodies.records[a];
  const BodyRecord& rb = bodies.records[b];
  const bool active_a = ra.awake && ra.type != FxBodyType::static_body;
  const bool active_b = rb.awake && rb.type != FxBodyType::static_body;
  if (!active_a && !active_b) return PairUpdate::skipped;
  if (!overlaps(tree.fat_box(ra.proxy), tree.fat_box(rb.proxy))) return PairUpdate::separated;
  // Apart before and still surely apart (when the step tests that: `reach` is not empty): collide()
  // would leave the record as it is, bar the face it tries first next time, which decides no result.
  // A second test, of the bodies' tight boxes apart along x or y by more than the collision's
  // margin, rules out most of the rest (neighbours side by side, whose circles overlap: 73% of
  // settling_boxes 800's pairs without points that reach collide(), 78% of 200's) but did not pay:
  // `ab`, sleeping off, 12 rounds, instructions 0.983 (settling_boxes 800), 0.990 (200) and 1.001
  // (pile 300), steps 1.024, 0.993 and 0.976 (inconclusive). Their collisions are cheap already, the
  // face that last separated them tried first.
  const float dt = step.settings.dt;
  if (!reach.empty() && contact.manifold.point_count == 0 && surely_apart(reach[a], reach[b], dt)) {
    return PairUpdate::collided;
  }
  const BodySim& sa = bodies.sims[a];
  const BodySim& sb = bodies.sims[b];
  const FxTransform xf_a{{}, sa.rotation};
  const FxTransform xf_b{bodies.origin_offset(a, b), sb.rotation};
  const PairMotion motion = pair_motion(sa, sb, ra.shape, rb.shape);
  if (ra.shape.type() == FxShapeType::circle && rb.shape.type() == FxShapeType::circle) {
    return collide_circle_pair(contact, ra.shape, xf_a, rb.shape, xf_b, dt, motion);
  }
  // Resting polygons, the common case in a stack or a settled heap, skip the separating-axis search
  // and the clip while a point stays within the speculative margin. Not skipping the remeasure too
  // while B stays within 10 um of where it was last measured in A's frame (a resting stack's pairs
  // move 1e-9 to 1e-6 m a step, at float resolution): 16 more bytes in the frame, and though
  // stacks 50 and 200 did 0.969 and 0.962 of the instructions, their steps took 0.995 and 0.990
  // (inconclusive) and settling_boxes 200's 1.029 [1.022, 1.115], its collide stage 1.112 (`ab`,
  // sleeping off, 12-16 rounds).
  if (contact.frame.valid &&
      barely_moved(contact.frame, inv_mul(xf_a, xf_b), rb.shape, contact.reuse_distance)) {
    // The same features: every point keeps its impulses. Moved in place, as the full collision
    // below reads no more of the record's manifold than moving leaves as it was.
    move_manifold(contact.frame, xf_a, xf_b, contact.manifold);
    if (any_point_within_margin(contact.manifold, dt, motion)) return touching_update(contact);
  }
  // Collided at the widest margin any normal could need, then trimmed to the one it found, into the
  // record itself once the points whose impulses carry over are known.
  const WarmStart previous = ContactCache::warm_start_of(contact);
  Manifold& manifold = contact.manifold;
  collide(ra.shape, xf_a, rb.shape, xf_b, speculative_distance(dt, motion.fastest_closing()),
          manifold.separating_face, manifold);
  // Every point is kept while any is within the margin: both ends of a polygon's clipped edge, the
  // far one for a body struck or set turning within the step (collide.cpp).
  keep_points_within_margin(manifold, dt, motion);
  ContactCache::carry_impulses(previous, contact);
  const bool polygons = ra.shape.type() == FxShapeType::polygon && rb.shape.type() == FxShapeType::polygon;
  contact.frame.valid = false;
  // A pair with no points has nothing to reuse.
  if (polygons && manifold.point_count > 0) contact.frame = frame_of(manifold, xf_a, xf_b);
  return touching_update(contact);
}

// The part of a separated pair's update, or a collided one's that began or stopped touching, that
// touches what other pairs share: the cache's free list and touching count, the bodies' contact
// lists and awake flags.
void settle_pair(int id, PairUpdate update, ContactCache& contacts, Bodies& bodies) {
  CachedContact& contact = contacts.slots[id];
  BodyRecord& ra = bodies.records[contact.body_a];
  BodyRecord& rb = bodies.records[contact.body_b];
  if (update == PairUpdate::separated) {
    contacts.destroy(id, ra.contact_head, rb.contact_head);
    return;
  }
  if (update == PairUpdate::stopped_touching) {
    --contacts.touching_count;
    return;
  }
  ++contacts.touching_count;
  const bool active_a = ra.awake && ra.type != FxBodyType::static_body;
  const bool active_b = rb.awake && rb.type != FxBodyType::static_body;
  if (!ra.awake && active_b) wake_body(bodies, contact.body_a);
  if (!rb.awake && active_a) wake_body(bodies, contact.body_b);
}

}  // namespace

void update_contacts(const StepContext& step, NarrowPhaseScratch& scratch, ContactCache& contacts, Bodies& bodies,
                     const AabbTree& tree) {
  // Every pair would be skipped, and only a collided pair wakes a body.
  if (bodies.awake_count == 0) return;
  const auto slot_count = static_cast<std::uint32_t>(contacts.slots.size());
  std::vector<PairUpdate>& updates = scratch.pair_updates;
  // The pairs apart at the last step (the slots not touching, free ones too) decide whether the
  // test of pairs apart is worth its pass over the bodies; the test decides no result.
  const std::size_t apart_pairs = slot_count - static_cast<std::uint32_t>(contacts.touching_count);
  const bool test_apart = bodies.sims.size() <= bodies_per_apart_pair * apart_pairs;
  if (test_apart) measure_reach(bodies, scratch.reach);
  const std::span<const BodyReach> reach =
      test_apart ? std::span<const BodyReach>(scratch.reach) : std::span<const BodyReach>();
  const bool parallel = step.tasks.runs_in_parallel(slot_count, min_parallel_pairs);
  if (parallel) {
    updates.resize(slot_count);
    // One range per worker, the same slots every step: a pair's record stays in one core's cache.
    const std::uint32_t block = step.tasks.per_worker(slot_count, pairs_per_block);
    step.tasks.for_each_range(slot_count, block, min_parallel_pairs, [&](std::uint32_t first, std::uint32_t last) {
      for (std::uint32_t id = first; id < last; ++id) {
        CachedContact& contact = contacts.slots[id];
        updates[id] = contact.alive ? collide_pair(step, contact, bodies, tree, reach) : PairUpdate::skipped;
      }
    });
  }
  // In slot order, as one thread would: a pair that wakes a body makes the later pairs of that
  // body active, so a pair skipped above is collided here once its body has woken.
  for (std::uint32_t id = 0; id < slot_count; ++id) {
    PairUpdate update = parallel ? updates[id] : PairUpdate::skipped;
    if (update == PairUpdate::skipped) {
      CachedContact& contact = contacts.slots[id];
      if (!contact.alive) continue;
      update = collide_pair(step, contact, bodies, tree, reach);
    }
    if (update != PairUpdate::skipped && update != PairUpdate::collided) {
      settle_pair(static_cast<int>(id), update, contacts, bodies);
    }
  }
}

float manifold_reuse_distance(const FxShape& a, const FxShape& b) {
  return std::min(max_manifold_reuse_distance,
                  manifold_reuse_share_of_edge * std::min(shortest_edge(a), shortest_edge(b)));
}

BodyReach reach_of(const BodySim& sim) {
  const float radius = sim.enclosing_radius;
  return {(sim.origin - sim.carry) + rotate(sim.rotation, sim.local_center), radius,
          length(sim.linear_velocity) + std::fabs(sim.angular_velocity) * radius};
}

bool surely_apart(const BodyReach& a, const BodyReach& b, float dt) {
  const FxVec2f between = b.centre - a.centre;
  const float scale = std::fabs(a.centre.x) + std::fabs(a.centre.y) + std::fabs(b.centre.x) +
                      std::fabs(b.centre.y) + a.radius + b.radius;
  const float allowance = 1.0e-5f + 1.0e-6f * scale;
  const float margin = base_speculative_distance + dt * (a.speed + b.speed) + allowance;
  const float reach = a.radius + b.radius + margin;
  return dot(between, between) > reach * reach;
}

}  // namespace fx2d::detail

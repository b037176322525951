// Continuous collision (continuous.h): which bodies are fast this step, their sweeps, and the
// move back to the first time of impact.
#include "collision/continuous.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "world/speed_limits.h"
#include "world/step_context.h"
#include "collision/time_of_impact.h"

namespace fx2d::detail {
namespace {

// A dynamic body is fast when some point of it moves farther in a step than this share of its
// inner extent: less cannot carry it past anything before the contact it makes pushes back
// (Box2D's safety factor).
constexpr float fast_share = 0.5f;

// A pass spreads over the workers in blocks of this many fast bodies, once it has this many.
constexpr std::uint32_t fast_bodies_per_block = 16;
constexpr std::uint32_t min_parallel_fast_bodies = 64;

// A bound on how far any point of a body moved in the step `state` records.
float step_motion(const FxBodyState& state, float body_reach) {
  // Up to a quarter turn the angle is at most pi/2 times its sine; beyond, a half turn bounds it.
  const FxRot turn = state.delta_rotation;
  const float angle = turn.c >= 0.0f ? 1.5707964f * std::abs(turn.s) : 3.1415927f;
  return length(state.delta_position) + angle * body_reach;
}

// The motion of `body` over the step, with its origin at `origin` at the step's end.
Sweep sweep_of(const Bodies& bodies, std::span<const FxBodyState> states, std::uint32_t body, FxVec2f origin) {
  const BodySim& sim = bodies.sims[body];
  const FxBodyState& state = states[body];
  Sweep sweep;
  sweep.local_center = sim.local_center;
  sweep.rotation1 = sim.rotation;
  sweep.center1 = origin + rotate(sim.rotation, sim.local_center);
  sweep.center0 = sweep.center1 - state.delta_position;
  sweep.rotation0 = inv_mul(state.delta_rotation, sim.rotation);
  return sweep;
}

// Whether a body of the pass (bullets or not) is swept against `other`.
bool sweeps_against(const BodyRecord& other, bool bullet_pass) {
  return other.type != FxBodyType::dynamic || (bullet_pass && !other.bullet);
}

class FastBodyPass {
 public:
  // A fast body stops `gap` short of touching, so that the next step's contact has room to act.
  // `others_motion` bounds how far any body it is swept against moved this step.
  FastBodyPass(float gap, float others_motion, float max_speed, float dt, std::span<FxBodyState> states, Bodies& bodies,
               const BroadPhase& broad, bool bullets)
      : gap_(gap), others_motion_(others_motion), max_speed_(max_speed), dt_(dt), states_(states), bodies_(bodies),
        broad_(broad), bullets_(bullets) {}

  void advance(std::uint32_t body, float motion) {
    if (!may_hit_anything(body, motion)) return;
    const Sweep sweep = sweep_of(bodies_, states_, body, FxVec2f{});
    const Impact impact = first_impact(body, sweep);
    if (impact.fraction < 1.0f) move_to(body, sweep, impact);
  }

 private:
  // The first body hit, when, and its motion in the frame of the body that hit it.
  struct Impact {
    float fraction = 1.0f;
    bool from_contact = false;
    std::uint32_t other = 0;
    Sweep other_sweep;
  };

  // Whether any body but this one has its box in the tree the pass sweeps against within
  // bound_of_swept_box(): else first_impact()'s query, whose box lies within that one, finds
  // nothing, and the sweep is not worth working out. A body falling or swinging far from the
  // ground and the walls, or in the middle of a heap that walls hold, is not swept. `motion` is
  // the body's step_motion().
  bool may_hit_anything(std::uint32_t body, float motion) const {
    const std::vector<std::uint32_t>& body_of_proxy = bodies_of_proxies();
    bool found = false;
    tree().query(bound_of_swept_box(body, motion), [&](int proxy) {
      found = body_of_proxy[proxy] != body;
      return !found;
    });
    return found;
  }

  // A box that holds swept_box() with room to spare: the body's box at the step's end grown by
  // twice how far its farthest point moved (`motion`, step_motion()), plus rounding's share of the
  // coordinates, then by the others' motion.
  FxAABB bound_of_swept_box(std::uint32_t body, float motion) const {
    const FxAABB& end = bodies_.sims[body].aabb;
    const float scale =
        std::abs(end.lower.x) + std::abs(end.lower.y) + std::abs(end.upper.x) + std::abs(end.upper.y);
    const float rounding = 0.01f + 1.0e-5f * scale;
    return inflate(end, 2.0f * motion + rounding + others_motion_);
  }

  // The tree the pass sweeps against, and its proxies' bodies.
  const AabbTree& tree() const { return bullets_ ? broad_.tree : broad_.fixed_tree; }
  const std::vector<std::uint32_t>& bodies_of_proxies() const {
    return bullets_ ? broad_.body_of_proxy : broad_.body_of_fixed_proxy;
  }

  // The box the body's shape covers at the step's start and at its end, grown by how far the
  // others moved: the tree holds their boxes as of the step's start (the next step's broad phase
  // moves them), so a body that moved into the sweep during the step is found only so.
  FxAABB swept_box(std::uint32_t body, const Sweep& sweep) const {
    const BodySim& sim = bodies_.sims[body];
    const FxTransform start = sweep.at(0.0f);
    FxAABB box;
    bodies_.records[body].shape.compute_aabb(FxTransform{sim.origin + start.p, start.q}, box);
    return inflate(union_of(box, sim.aabb), others_motion_);
  }

  // The earliest impact of `body` on a body it is swept against; fraction 1 when there is none.
  // Ties go to the lower index, so the tree's order of visits does not matter. The first pass
  // searches only the static and kinematic bodies' tree.
  Impact first_impact(std::uint32_t body, const Sweep& sweep) const {
    const FxShape& shape = bodies_.records[body].shape;
    const std::vector<std::uint32_t>& body_of_proxy = bodies_of_proxies();
    Impact earliest;
    tree().query(swept_box(body, sweep), [&](int proxy) {
      const std::uint32_t other = body_of_proxy[proxy];
      const BodyRecord& record = bodies_.records[other];
      if (other == body || !sweeps_against(record, bullets_) || broad_.jointed(body, other)) return true;
      const Sweep other_sweep = sweep_of(bodies_, states_, other, bodies_.origin_offset(body, other));
      const TimeOfImpact impact = time_of_impact(shape, sweep, record.shape, other_sweep, gap_);
      const float fraction = impact.fraction;
      const bool earlier = fraction < earliest.fraction || (fraction == earliest.fraction && other < earliest.other);
      if (fraction < 1.0f && earlier) earliest = {fraction, impact.from_contact, other, other_sweep};
      return true;
    });
    return earliest;
  }

  // Puts `body` where it was at the impact, then carries it with the body it hit for the rest of
  // the step, so the two end the step as they were at the impact: a gap apart, on the same sides.
  // A body stopped by a static body it already touched slides on along it instead (slid_along()).
  // Not along a kinematic one: that may be what drives into the body (a paddle pressing it to the
  // floor), and carried with it the body keeps where the sweep found room.
  void move_to(std::uint32_t body, const Sweep& sweep, const Impact& impact) {
    const FxTransform at_impact = sweep.at(impact.fraction);
    const FxTransform hit_at_impact = impact.other_sweep.at(impact.fraction);
    BodySim& sim = bodies_.sims[body];
    BodyRecord& record = bodies_.records[body];
    const BodyRecord& hit = bodies_.records[impact.other];
    const FxVec2f contact_normal =
        impact.from_contact ? shape_separation(record.shape, at_impact, hit.shape, hit_at_impact).normal
                            : FxVec2f{};
    const FxTransform end = impact.from_contact && hit.type == FxBodyType::static_body
                                ? slid_along(body, sweep, impact.fraction, at_impact.q, contact_normal)
                                : carried_with(impact.other_sweep, at_impact, hit_at_impact);
    FxBodyState& state = states_[body];
    FxCarryAdd(sim.origin, sim.carry, end.p);
    sim.rotation = end.q;
    state.delta_position = end.p + rotate(end.q, sim.local_center) - sweep.center0;
    state.delta_rotation = inv_mul(sweep.rotation0, end.q);
    record.shape.compute_aabb(FxTransform{sim.origin, sim.rotation}, sim.aabb);
    broad_.refresh(record, sim, dt_);
    if (impact.from_contact) stop_approach(body, impact.other, contact_normal);
  }

  // Where a body at `at_impact` ends the step when it keeps its pose relative to the body it hit,
  // which moves on as `hit_sweep` says.
  static FxTransform carried_with(const Sweep& hit_sweep, const FxTransform& at_impact,
                                  const FxTransform& hit_at_impact) {
    const FxTransform hit_at_end = hit_sweep.at(1.0f);
    const FxTransform relative = inv_mul(hit_at_impact, at_impact);
    return {transform_point(hit_at_end, relative.p), mul(hit_at_end.q, relative.q)};
  }

  // Where a body stopped at `fraction` of `sweep` by a static body it already touched ends the
  // step when it slides on along it, its turn held at the impact's (`turn`): the rest of its
  // centre's motion, less what of it goes into that body along `normal` (from the body towards the
  // static one), swept again against what its pass sweeps against, so that the slide stops at
  // anything else in the way. Carried with the static body, it would stop dead: a box sliding fast
  // on the ground, pressed a few millimetres into it by a load, whose corner dips a millimetre
  // further within the step is stopped at that moment with its speed kept, and again in every
  // step after, while the bodies behind it run into it (smash_pyramid, 7 runs with gravity
  // perturbed, overlap sampled every step: deepest 1.01-1.17 m carried, 0.31-0.41 m slid).
  FxTransform slid_along(std::uint32_t body, const Sweep& sweep, float fraction, FxRot turn,
                         FxVec2f normal) const {
    Sweep slide;
    slide.local_center = sweep.local_center;
    slide.center0 = lerp(sweep.center0, sweep.center1, fraction);
    const FxVec2f rest = sweep.center1 - slide.center0;
    slide.center1 = slide.center0 + (rest - std::max(dot(rest, normal), 0.0f) * normal);
    slide.rotation0 = turn;
    slide.rotation1 = turn;
    return slide.at(first_impact(body, slide).fraction);
  }

  // Takes from `body`'s velocity what carries its centre towards a body it already touched, along
  // the normal where the sweep stopped it. The contact left that approach (a first impact's is the
  // next step's contact to answer, with spin and momentum to share); kept, it would stop a body that
  // turns about the point it touches early in every step (its sweep takes the centre on a straight
  // line, not on the arc about that point), and the body would never move on. Matching a moving
  // body's speed along the normal can make it faster than the scene's limit (a body at the limit
  // overtaken by a kinematic wall), so the result is held to it like every other velocity.
  void stop_approach(std::uint32_t body, std::uint32_t other, FxVec2f normal) {
    FxVec2f& velocity = bodies_.sims[body].linear_velocity;
    const float approach = dot(velocity - bodies_.sims[other].linear_velocity, normal);
    if (approach > 0.0f) velocity = limited_speed(velocity - approach * normal, max_speed_);
  }

  float gap_;
  float others_motion_;
  float max_speed_;
  float dt_;
  std::span<FxBodyState> states_;
  Bodies& bodies_;
  const BroadPhase& broad_;
  bool bullets_;
};

// The farthest any point of a moving body that the bullets' pass sweeps against moved this step.
float others_motion_for_bullets(std::span<const FxBodyState> states, std::span<const std::uint32_t> moving,
                                const Bodies& bodies) {
  float farthest = 0.0f;
  for (const std::uint32_t body : moving) {
    if (!sweeps_against(bodies.records[body], true)) continue;
    farthest = std::max(farthest, step_motion(states[body], bodies.sims[body].reach));
  }
  return farthest;
}

// The least distance from a shape's centroid to its surface (metres).
float inner_extent(const FxShape& shape) {
  if (shape.type() == FxShapeType::circle) return shape.radius();
  float nearest = std::numeric_limits<float>::max();
  for (int i = 0; i < shape.vertex_count(); ++i) {
    nearest = std::min(nearest, dot(shape.normals()[i], shape.vertices()[i] - shape.centroid()));
  }
  return nearest;
}

}  // namespace

void set_continuous_extents(BodySim& sim, FxBodyType type, const FxShape& shape) {
  sim.reach = reach(shape, sim.local_center);
  sim.fast_motion =
      type == FxBodyType::dynamic ? fast_share * inner_extent(shape) : std::numeric_limits<float>::infinity();
}

void solve_continuous(const StepContext& step, ContinuousScratch& scratch, std::span<FxBodyState> states,
                      std::span<const std::uint32_t> moving, Bodies& bodies, const BroadPhase& broad) {
  // One walk over the moving bodies, reading only their states and sims (a record is several
  // cache lines away, and this walk took most of the stage when it read them): the fast ones, and
  // how far the kinematic ones, which the first pass sweeps against, moved.
  std::vector<ContinuousScratch::FastBody>& fast = scratch.fast_bodies;
  fast.clear();
  float kinematic_motion = 0.0f;
  for (const std::uint32_t body : moving) {
    const BodySim& sim = bodies.sims[body];
    const float motion = step_motion(states[body], sim.reach);
    if (motion > sim.fast_motion) fast.push_back({body, motion});
    if (sim.fast_motion == std::numeric_limits<float>::infinity()) kinematic_motion = std::max(kinematic_motion, motion);
  }
  // Bullets go second, against the motion the first pass left the other bodies.
  for (const bool bullets : {false, true}) {
    const auto in_pass = [&](const ContinuousScratch::FastBody& fast_body) {
      return bodies.records[fast_body.body].bullet == bullets;
    };
    if (std::none_of(fast.begin(), fast.end(), in_pass)) continue;
    const float others_motion = bullets ? others_motion_for_bullets(states, moving, bodies) : kinematic_motion;
    FastBodyPass pass(step.settings.linear_slop, others_motion, step.limits.max_speed, step.settings.dt, states, bodies,
                      broad, bullets);
    // A fast body moves only itself, and is swept only against bodies its pass never moves (not
    // dynamic in the first pass, not bullets in the second), so a pass's bodies advance on any
    // thread in any order.
    step.tasks.for_each_range(static_cast<std::uint32_t>(fast.size()), fast_bodies_per_block, min_parallel_fast_bodies,
                              [&](std::uint32_t first, std::uint32_t last) {
                                for (std::uint32_t k = first; k < last; ++k) {
                                  if (in_pass(fast[k])) pass.advance(fast[k].body, fast[k].motion);
                                }
                              });
  }
}

}  // namespace fx2d::detail

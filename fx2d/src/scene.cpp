// The step: a fixed sequence of stages, each one function, each timed as one FxStage.
//
//   broad phase      update_broad_phase()   proxies, new pairs          (once per step)
//   narrow phase     update_contacts()      manifolds, contact cache    (once per step)
//   velocity passes  prepare_solver()       gather body state, build contact constraints, colour
//                                           them and pack them into batches
//                    solve_substeps()       per substep: integrate velocities, warm start,
//                                           velocity passes, integrate positions, relaxation passes;
//                                           then restitution
//   position solve   solve_positions()      project remaining deep overlaps
//   integration      finalize_bodies()      write poses back with carries, refresh boxes
//   bookkeeping      update_sleep(), impulse storage, the step callback
//
// Collision runs once per step and substeps stay cheap: contact anchors are fixed for the step
// and separations are updated from each body's accumulated displacement.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "step_context.h"
#include "world.h"

namespace fx2d::detail {
namespace {

void require(bool condition, const char* field, const char* expected) {
  if (!condition) throw FxInvalidArgument(std::string("FxSceneSettings: ") + field + ": expected " + expected);
}

class WorldConstraintContext final : public FxConstraintContext {
 public:
  explicit WorldConstraintContext(World& world) : world_(world) {}
  FxBodyState& state(const FxEntity& e) override { return world_.states[e.packed_index()]; }
  float inv_mass(const FxEntity& e) const override { return world_.sims[e.packed_index()].inv_mass; }
  float inv_inertia(const FxEntity& e) const override { return world_.sims[e.packed_index()].inv_inertia; }
  FxRot start_rotation(const FxEntity& e) const override { return world_.sims[e.packed_index()].rotation; }
  FxVec2f center_offset(const FxEntity& a, const FxEntity& b) const override {
    return world_.center_offset(a.packed_index(), b.packed_index());
  }
  FxVec2f local_center(const FxEntity& e) const override { return world_.sims[e.packed_index()].local_center; }

 private:
  World& world_;
};

// A substep's rate caps a soft constraint's stiffness: above a quarter of it the spring would
// resolve faster than the substep can represent.
float capped_hertz(float hertz, float substep_dt) { return std::min(hertz, 0.25f / substep_dt); }

// Component-wise, so that a force large enough to overflow inv_mass * force to infinity still gives
// a finite acceleration (the velocity clamp then keeps its direction); below the bound, unchanged.
FxVec2f clamped_acceleration(FxVec2f acceleration, float bound) {
  return {std::clamp(acceleration.x, -bound, bound), std::clamp(acceleration.y, -bound, bound)};
}

}  // namespace

void validate_settings(const FxSceneSettings& s) {
  constexpr float max_damping_ratio = 1000.0f;  // far past critical (1); beyond it only overflow
  require(is_finite(s.gravity), "gravity", "finite components");
  // Bounded, not only finite: a dt of 1e38 s or a damping ratio of 1e38 overflows the soft-constraint
  // coefficients (make_softness) into inf * 0, and a dt of 1e-40 s underflows the substep to 0.
  require(s.dt >= 1.0e-6f && s.dt <= 1.0f, "dt", "a number in [1e-6, 1] seconds");
  require(s.substeps >= 1, "substeps", "an integer >= 1");
  require(s.velocity_passes >= 1, "velocity_passes", "an integer >= 1");
  require(s.relax_passes >= 1, "relax_passes", "an integer >= 1");
  require(s.position_passes >= 0, "position_passes", "an integer >= 0");
  require(std::isfinite(s.time_to_sleep) && s.time_to_sleep >= 0.0f, "time_to_sleep", "a finite number >= 0");
  require(std::isfinite(s.linear_sleep_speed) && s.linear_sleep_speed >= 0.0f, "linear_sleep_speed", "a finite number >= 0");
  require(std::isfinite(s.angular_sleep_speed) && s.angular_sleep_speed >= 0.0f, "angular_sleep_speed", "a finite number >= 0");
  require(std::isfinite(s.restitution_threshold) && s.restitution_threshold >= 0.0f, "restitution_threshold", "a finite number >= 0");
  require(std::isfinite(s.contact_hertz) && s.contact_hertz > 0.0f, "contact_hertz", "a finite number > 0");
  require(s.contact_damping_ratio > 0.0f && s.contact_damping_ratio <= max_damping_ratio, "contact_damping_ratio",
          "a number in (0, 1000]");
  require(std::isfinite(s.joint_hertz) && s.joint_hertz > 0.0f, "joint_hertz", "a finite number > 0");
  require(s.joint_damping_ratio > 0.0f && s.joint_damping_ratio <= max_damping_ratio, "joint_damping_ratio",
          "a number in (0, 1000]");
  require(std::isfinite(s.max_push_speed) && s.max_push_speed > 0.0f, "max_push_speed", "a finite number > 0");
  require(std::isfinite(s.linear_slop) && s.linear_slop >= 0.0f, "linear_slop", "a finite number >= 0");
  require(std::isfinite(s.max_linear_speed) && s.max_linear_speed > 0.0f, "max_linear_speed", "a finite number > 0");
}

World::World(const FxSceneSettings& s) : settings(s) {
  validate_settings(settings);
#if FX2D_SCALAR_SOLVER
  settings.force_scalar_solver = true;  // a build that measures the scalar twin (CMake FX2D_SCALAR_SOLVER)
#endif
}

FxVec2f slowed_to(FxVec2f v, float max_speed) {
  const float speed_squared = length_squared(v);
  if (std::isfinite(speed_squared)) return v * (max_speed / std::sqrt(speed_squared));
  // Overflowed, or not a number: keep the direction of the largest components, or the infinite
  // components' signs alone; a NaN component counts as zero.
  if (!is_finite(v)) {
    v = {std::isinf(v.x) ? std::copysign(1.0f, v.x) : 0.0f, std::isinf(v.y) ? std::copysign(1.0f, v.y) : 0.0f};
  }
  const float largest = std::max(std::fabs(v.x), std::fabs(v.y));
  return largest > 0.0f ? max_speed * normalize((1.0f / largest) * v) : FxVec2f{};
}

void clamp_velocity(const FxSceneSettings& settings, BodySim& sim) {
  sim.linear_velocity = limited_speed(sim.linear_velocity, settings.max_linear_speed);
  sim.angular_velocity = limited_spin(sim.angular_velocity, max_angular_speed(settings));
}

FxVec2f World::origin_offset(std::uint32_t a, std::uint32_t b) const {
  const BodySim& sa = sims[a];
  const BodySim& sb = sims[b];
  return (sb.origin - sa.origin) - (sb.carry - sa.carry);
}

FxVec2f World::center_offset(std::uint32_t a, std::uint32_t b) const {
  const BodySim& sa = sims[a];
  const BodySim& sb = sims[b];
  return origin_offset(a, b) + rotate(sb.rotation, sb.local_center) - rotate(sa.rotation, sa.local_center);
}

void World::step() {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::uint64_t cycle_start = read_cycle_counter();
  profile = FxProfile{};
  stepping = true;
  {
    StageClock clock(profile, FxStage::broad_phase);
    const StepContext context(settings, static_cast<std::uint32_t>(records.size()), clock);
    update_broad_phase();
    clock.switch_to(FxStage::narrow_phase);
    update_contacts();
    clock.switch_to(FxStage::velocity_passes);
    prepare_solver(context);
    solve_substeps(context);
    clock.switch_to(FxStage::position_solve);
    solve_positions();
    clock.switch_to(FxStage::integration);
    finalize_bodies();
    clock.switch_to(FxStage::bookkeeping);
    solver.store_impulses(contacts);
    update_sleep();
    stepping = false;
    ++step_index;
    if (step_callback) step_callback(*owner);
  }
#if FX2D_PROFILE
  profile.step_cycles = read_cycle_counter() - cycle_start;
  profile.step_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
  if (profile.step_cycles > 0) {
    const double ms_per_cycle = profile.step_ms / static_cast<double>(profile.step_cycles);
    for (int i = 0; i < fx_stage_count; ++i) profile.stage_ms[i] = ms_per_cycle * static_cast<double>(profile.stage_cycles[i]);
  }
#else
  static_cast<void>(wall_start);
  static_cast<void>(cycle_start);
#endif
}

StepContext::StepContext(const FxSceneSettings& s, std::uint32_t bodies, StageClock& stage_clock)
    : settings(s),
      substep_dt(s.dt / static_cast<float>(s.substeps)),
      // Any more would take a body past max_linear_speed within one substep, where it is clamped anyway.
      max_acceleration(2.0f * s.max_linear_speed / substep_dt),
      limits{s.max_linear_speed, max_angular_speed(s)},
      contact{make_softness(capped_hertz(s.contact_hertz, substep_dt), s.contact_damping_ratio, substep_dt),
              1.0f / substep_dt, s.max_push_speed},
      joint_softness(make_softness(capped_hertz(s.joint_hertz, substep_dt), s.joint_damping_ratio, substep_dt)),
      body_count(bodies),
      clock(stage_clock) {}

void World::prepare_solver(const StepContext& step) {
  // Gather the hot state of every body; sleeping and static ones keep zero velocity and are
  // never written by a constraint (a touching constraint always has its bodies awake).
  integration.clear(step.body_count);
  const float h = step.substep_dt;
  states.resize(records.size() + 1);
  states.back() = FxBodyState{};
  movable.resize(records.size() + 1);
  movable.back() = 0;
  for (std::uint32_t i = 0; i < records.size(); ++i) {
    movable[i] = records[i].type == FxBodyType::dynamic;
    const bool moves = records[i].awake && records[i].type != FxBodyType::static_body;
    FxBodyState& state = states[i];
    state = FxBodyState{};
    if (!moves) continue;
    state.linear_velocity = sims[i].linear_velocity;
    state.angular_velocity = sims[i].angular_velocity;
    integration.add_moving(i);
    if (records[i].type != FxBodyType::dynamic) continue;
    integration.add_dynamic(i, clamped_acceleration(settings.gravity + sims[i].inv_mass * sims[i].force, step.max_acceleration),
                            1.0f / (1.0f + h * records[i].linear_damping), 1.0f / (1.0f + h * records[i].angular_damping));
  }
  integration.finish();
  solver.prepare(*this);
  contact_graph.build(solver.constraints, movable);
  contact_batches.pack(solver.constraints, contact_graph, step.body_count);
}

void World::solve_substeps(const StepContext& step) {
  const float h = step.substep_dt;
  StageClock& clock = step.clock;
  WorldConstraintContext context(*this);
  context.substep_dt = h;
  context.inv_substep_dt = step.contact.inv_substep_dt;
  context.softness = step.joint_softness;
  context.max_bias_velocity = settings.max_push_speed;
  context.max_linear_speed = step.limits.max_speed;
  context.max_angular_speed = step.limits.max_spin;
  const bool has_constraints = !constraints.empty();
  if (has_constraints) {
    clock.switch_to(FxStage::constraints);
    for (const auto& constraint : constraints) constraint->prepare(context);
  }

  // One pass over every constraint, then every contact: contacts last, so they win conflicts.
  auto velocity_pass = [&](bool use_bias) {
    if (has_constraints) {
      clock.switch_to(FxStage::constraints);
      for (const auto& constraint : constraints) constraint->evaluate(context, use_bias);
    }
    clock.switch_to(FxStage::velocity_passes);
    contact_batches.resolve_velocities(states, step.contact, use_bias, settings.force_scalar_solver);
  };

  const SpeedLimits limits = step.limits;
  clock.switch_to(FxStage::velocity_passes);
  contact_batches.update_separations(states);
  for (int substep = 0; substep < settings.substeps; ++substep) {
    clock.switch_to(FxStage::integration);
    integration.integrate_velocities(states, h, limits);
    if (has_constraints) {
      clock.switch_to(FxStage::constraints);
      for (const auto& constraint : constraints) constraint->warm_start(context);
    }
    clock.switch_to(FxStage::velocity_passes);
    contact_batches.warm_start(states, settings.force_scalar_solver);
    for (int pass = 0; pass < settings.velocity_passes; ++pass) velocity_pass(true);
    clock.switch_to(FxStage::integration);
    // Clamped again here and at the step's end: the passes can push a body squeezed between
    // immovable bodies, or held by joints that fight, past the limits the integration kept.
    integration.integrate_positions(states, h, limits);
    clock.switch_to(FxStage::velocity_passes);
    contact_batches.update_separations(states);
    for (int pass = 0; pass < settings.relax_passes; ++pass) velocity_pass(false);
  }
  clock.switch_to(FxStage::velocity_passes);
  contact_batches.unpack(solver.constraints);
  solver.apply_restitution(states, settings.restitution_threshold);
}

void World::solve_positions() {
  for (int pass = 0; pass < settings.position_passes; ++pass) solver.project_positions(states, settings.linear_slop);
}

void World::finalize_bodies() {
  const float dt = settings.dt;
  for (const std::uint32_t i : integration.moving_bodies()) {
    BodySim& sim = sims[i];
    BodyRecord& record = records[i];
    const FxBodyState& state = states[i];
    const FxRot start = sim.rotation;
    FxRot end = mul(state.delta_rotation, start);
    const float norm = std::sqrt(end.c * end.c + end.s * end.s);
    end = {end.c / norm, end.s / norm};
    // The origin moves with the centre of mass and swings about it as the body turns.
    const FxVec2f origin_step =
        state.delta_position + rotate(start, sim.local_center) - rotate(end, sim.local_center);
    FxCarryAdd(sim.origin, sim.carry, origin_step);
    sim.rotation = end;
    sim.linear_velocity = state.linear_velocity;
    sim.angular_velocity = state.angular_velocity;
    clamp_velocity(settings, sim);
    sim.force = {};

    const bool resting = length_squared(sim.linear_velocity) < settings.linear_sleep_speed * settings.linear_sleep_speed &&
                         sim.angular_velocity * sim.angular_velocity < settings.angular_sleep_speed * settings.angular_sleep_speed;
    record.sleep_time = (resting && record.can_sleep) ? record.sleep_time + dt : 0.0f;

    record.shape.compute_aabb(FxTransform{sim.origin, sim.rotation}, sim.aabb);
    if (!tree.fat_box(record.proxy).contains(sim.aabb)) record.moved = true;
  }
}

}  // namespace fx2d::detail

namespace fx2d {

std::string_view fx_version() { return FX2D_VERSION_STRING; }

bool fx_profiling_enabled() {
#if FX2D_PROFILE
  return true;
#else
  return false;
#endif
}

FxScene::FxScene(const FxSceneSettings& settings) : world_(std::make_unique<detail::World>(settings)) {
  world_->owner = this;
}

FxScene::~FxScene() = default;

std::shared_ptr<FxEntity> FxScene::create_entity(const FxEntityDef& def) { return world_->create_entity(def); }

void FxScene::remove_entity(const FxEntity& entity) { world_->remove_entity(world_->index_of(entity)); }

void FxScene::add_constraint(std::shared_ptr<FxConstraint> constraint) { world_->add_constraint(std::move(constraint)); }

void FxScene::remove_constraint(const FxConstraint& constraint) { world_->remove_constraint(constraint); }

void FxScene::step() { world_->step(); }

void FxScene::set_step_callback(std::function<void(FxScene&)> callback) { world_->step_callback = std::move(callback); }

const FxSceneSettings& FxScene::settings() const { return world_->settings; }

void FxScene::set_settings(const FxSceneSettings& settings) {
  detail::validate_settings(settings);
  world_->settings = settings;
  if (!settings.sleeping) {
    for (std::uint32_t i = 0; i < world_->records.size(); ++i) world_->wake_body(i);
  }
}

std::size_t FxScene::entity_count() const { return world_->records.size(); }

const std::shared_ptr<FxEntity>& FxScene::entity(std::uint32_t packed_index) const {
  return world_->records.at(packed_index).handle;
}

std::size_t FxScene::constraint_count() const { return world_->constraints.size(); }

int FxScene::contact_count() const { return world_->contacts.touching_count; }

void FxScene::contacts(std::vector<FxContact>& out) const {
  out.clear();
  for (const detail::CachedContact& contact : world_->contacts.slots) {
    if (!contact.touching) continue;
    FxContact& c = out.emplace_back();
    c.entity_a = contact.body_a;
    c.entity_b = contact.body_b;
    c.normal = contact.manifold.normal;
    c.point_count = contact.manifold.point_count;
    const FxVec2f origin_a = world_->sims[contact.body_a].origin;
    for (int i = 0; i < c.point_count; ++i) {
      const detail::ManifoldPoint& mp = contact.manifold.points[i];
      c.points[i] = {origin_a + mp.point, mp.separation, contact.normal_impulse[i], contact.tangent_impulse[i], mp.id};
    }
  }
}

const FxProfile& FxScene::profile() const { return world_->profile; }

std::uint64_t FxScene::step_index() const { return world_->step_index; }

}  // namespace fx2d

// The step: a fixed sequence of stages, each one function of the step context and of the parts
// of the scene it owns or reads, each timed as the FxStage of the same name (fx2d/Profile.h).
//
//   broad_phase      update_broad_phase()     proxies, new pairs                      broad_phase.h
//   collide          update_contacts()        manifolds, contact cache                narrow_phase.h
//   prepare          prepare_solver()         gather body state, list the contacts    solver_stages.h
//   colour_and_pack  colour_and_pack()        colour them, build constraints in lanes
//                    solve_substeps()         per substep:
//   integrate          integrate_velocities()   gravity, forces, damping; later substeps carry the impulses
//   on warm_start         warm_start()             the accumulated impulses (first substep, or with joints)
//   solve              solve()                  soft velocity passes, then the push of deep overlaps
//   integrate          integrate_positions()
//   relax              relax()                  take the push back, rigid passes
//   restitution      apply_restitution()
//   position_solve   solve_positions()        project remaining deep overlaps
//   integrate        finalize_bodies()        write poses back with carries, refresh boxes
//   continuous       solve_continuous()       fast bodies back to their first impact     continuous.h
//   store            store_impulses()         impulses for the next step's warm start
//   sleep            update_sleep()           resting islands                         sleep.h
//   constraints      user constraints' share of prepare, warm start and every pass
// The step callback runs after the last stage, in no stage.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "collision/narrow_phase.h"
#include "world/step_context.h"
#include "world/world.h"

namespace fx2d::detail {
namespace {

void require(bool condition, const char* field, const char* expected) {
  if (!condition) throw FxInvalidArgument(std::string("FxSceneSettings: ") + field + ": expected " + expected);
}

// Throws FxInvalidArgument unless every setting is in range.
void validate_settings(const FxSceneSettings& s) {
  constexpr float max_damping_ratio = 1000.0f;  // far past critical (1); beyond it only overflow
  constexpr int max_workers = 64;               // far past any core count a step scales to
  require(is_finite(s.gravity), "gravity", "finite components");
  // Bounded, not only finite: a dt of 1e38 s or a damping ratio of 1e38 overflows the soft-constraint
  // coefficients (make_softness) into inf * 0, and a dt of 1e-40 s underflows the substep to 0.
  require(s.dt >= 1.0e-6f && s.dt <= 1.0f, "dt", "a number in [1e-6, 1] seconds");
  require(s.substeps >= 1, "substeps", "an integer >= 1");
  require(s.velocity_passes >= 1, "velocity_passes", "an integer >= 1");
  require(s.relax_passes >= 1, "relax_passes", "an integer >= 1");
  require(s.joint_relax_passes >= 1, "joint_relax_passes", "an integer >= 1");
  require(s.position_passes >= 0, "position_passes", "an integer >= 0");
  require(std::isfinite(s.rest_schedule_time) && s.rest_schedule_time >= 0.0f, "rest_schedule_time",
          "a finite number >= 0");
  require(s.shallow_schedule_depth >= 0, "shallow_schedule_depth", "an integer >= 0");
  require(std::isfinite(s.shallow_schedule_speed) && s.shallow_schedule_speed >= 0.0f,
          "shallow_schedule_speed", "a finite number >= 0");
  require(s.impact_schedule_travel >= 0.0f, "impact_schedule_travel", "a number >= 0");
  require(s.impact_velocity_passes >= 1, "impact_velocity_passes", "an integer >= 1");
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
  require(s.workers >= 1 && s.workers <= max_workers, "workers", "an integer in [1, 64]");
  require((s.scheduler.enqueue == nullptr) == (s.scheduler.wait == nullptr), "scheduler",
          "both enqueue and wait, or neither");
}

// A substep's rate caps a soft constraint's stiffness: above a quarter of it the spring would
// resolve faster than the substep can represent. Measured: capped at a third instead (120 Hz at 7
// substeps), a box 100 times heavier than the one it stands on slid 34 mm off it in 5 s.
float capped_hertz(float hertz, float substep_dt) { return std::min(hertz, 0.25f / substep_dt); }

// The soft spring's pushes go through the velocities and add up down a column of overlaps; this
// many of them together reach max_push_speed, so a column of eight (overlap_recovery's pyramid)
// is not launched. A slower spring holds less load: capped at 0.27 m/s instead of 0.375 m/s,
// stability's mass_ratio fell from 1020 to 790 (uncapped below max_push_speed: 3158).
constexpr float spring_pushes_per_push = 8.0f;

}  // namespace

StepContext::StepContext(const FxSceneSettings& s, float last_substep_dt, std::uint32_t bodies,
                         StageClock& stage_clock, const Tasks& step_tasks)
    : settings(s),
      substep_dt(s.dt / static_cast<float>(s.substeps)),
      impulse_ratio(last_substep_dt > 0.0f ? substep_dt / last_substep_dt : 1.0f),
      // Any more would take a body past max_linear_speed within one substep, where it is clamped anyway.
      max_acceleration(2.0f * s.max_linear_speed / substep_dt),
      limits{s.max_linear_speed, max_angular_speed(s)},
      contact{make_softness(capped_hertz(s.contact_hertz, substep_dt), s.contact_damping_ratio, substep_dt),
              1.0f / substep_dt, s.max_push_speed, s.max_push_speed / spring_pushes_per_push, s.linear_slop},
      joint_softness(
          make_softness(capped_hertz(s.joint_hertz, substep_dt), s.joint_damping_ratio, substep_dt)),
      body_count(bodies),
      clock(stage_clock),
      tasks(step_tasks) {}

World::World(const FxSceneSettings& s, FxScene& owner) : settings_(s), owner_(owner) {
  validate_settings(settings_);
#if FX2D_SCALAR_SOLVER
  settings_.force_scalar_solver = true;  // a build that measures the scalar twin (CMake FX2D_SCALAR_SOLVER)
#endif
  tasks_.configure(settings_);
}

void World::set_settings(const FxSceneSettings& settings) {
  validate_settings(settings);
  settings_ = settings;
  tasks_.configure(settings_);
  if (!settings.sleeping) {
    for (std::uint32_t i = 0; i < bodies_.count(); ++i) wake_body(i);
  }
}

void World::step() {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::uint64_t cycle_start = read_cycle_counter();
  profile_ = FxProfile{};
  stepping_ = true;
  {
    StageClock clock(profile_, FxStage::broad_phase);
    const StepContext step(settings_, last_substep_dt_, bodies_.count(), clock, tasks_);
    // Only after set_settings() changed dt or substeps: the joints scale theirs in prepare().
    if (step.impulse_ratio != 1.0f) contacts_.scale_impulses(step.impulse_ratio);
    last_substep_dt_ = step.substep_dt;
    update_broad_phase(step, broad_phase_, bodies_, contacts_, constraints_);
    clock.switch_to(FxStage::collide);
    update_contacts(step, narrow_phase_, contacts_, bodies_, broad_phase_.tree);
    clock.switch_to(FxStage::prepare);
    prepare_solver(step, solver_, bodies_, contacts_, constraints_);
    clock.switch_to(FxStage::colour_and_pack);
    colour_and_pack(step, solver_, bodies_, contacts_);
    solve_substeps(step, solver_, bodies_, constraints_);
    profile_.velocity_passes = solver_.passes.velocity;
    profile_.relax_passes = solver_.passes.relax;
    clock.switch_to(FxStage::restitution);
    apply_restitution(step, solver_);
    clock.switch_to(FxStage::position_solve);
    solve_positions(step, solver_);
    clock.switch_to(FxStage::integrate);
    finalize_bodies(step, solver_, bodies_, broad_phase_);
    clock.switch_to(FxStage::continuous);
    solve_continuous(step, continuous_, solver_.states, solver_.integration.moving_bodies(), bodies_, broad_phase_);
    clock.switch_to(FxStage::store);
    store_impulses(solver_, contacts_);
    clock.switch_to(FxStage::sleep);
    update_sleep(step, sleep_, bodies_, solver_.contact_solver.sources(), constraints_,
                 solver_.integration.moving_bodies());
  }
  stepping_ = false;
  ++step_index_;
  if (step_callback_) step_callback_(owner_);
#if FX2D_PROFILE
  profile_.step_cycles = read_cycle_counter() - cycle_start;
  profile_.step_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
  if (profile_.step_cycles > 0) {
    const double ms_per_cycle = profile_.step_ms / static_cast<double>(profile_.step_cycles);
    for (int i = 0; i < fx_stage_count; ++i) profile_.stage_ms[i] = ms_per_cycle * static_cast<double>(profile_.stage_cycles[i]);
  }
#else
  static_cast<void>(wall_start);
  static_cast<void>(cycle_start);
#endif
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

FxScene::FxScene(const FxSceneSettings& settings) : world_(std::make_unique<detail::World>(settings, *this)) {}

FxScene::~FxScene() = default;

std::shared_ptr<FxEntity> FxScene::create_entity(const FxEntityDef& def) { return world_->create_entity(def); }

void FxScene::remove_entity(const FxEntity& entity) { world_->remove_entity(world_->index_of(entity)); }

void FxScene::add_constraint(std::shared_ptr<FxConstraint> constraint) { world_->add_constraint(std::move(constraint)); }

void FxScene::remove_constraint(const FxConstraint& constraint) { world_->remove_constraint(constraint); }

void FxScene::step() { world_->step(); }

void FxScene::set_step_callback(std::function<void(FxScene&)> callback) { world_->set_step_callback(std::move(callback)); }

const FxSceneSettings& FxScene::settings() const { return world_->settings(); }

void FxScene::set_settings(const FxSceneSettings& settings) { world_->set_settings(settings); }

std::size_t FxScene::entity_count() const { return world_->bodies().count(); }

const std::shared_ptr<FxEntity>& FxScene::entity(std::uint32_t packed_index) const {
  return world_->bodies().records.at(packed_index).handle;
}

std::size_t FxScene::constraint_count() const { return world_->constraint_count(); }

int FxScene::contact_count() const { return world_->contacts().touching_count; }

void FxScene::contacts(std::vector<FxContact>& out) const {
  out.clear();
  for (const detail::CachedContact& contact : world_->contacts().slots) {
    if (!contact.touching) continue;
    FxContact& c = out.emplace_back();
    c.entity_a = contact.body_a;
    c.entity_b = contact.body_b;
    c.normal = contact.manifold.normal;
    c.point_count = contact.manifold.point_count;
    const FxVec2f origin_a = world_->bodies().sims[contact.body_a].origin;
    for (int i = 0; i < c.point_count; ++i) {
      const detail::ManifoldPoint& mp = contact.manifold.points[i];
      c.points[i] = {origin_a + mp.point, mp.separation, contact.normal_impulse[i], contact.tangent_impulse[i], mp.id};
    }
  }
}

const FxProfile& FxScene::profile() const { return world_->profile(); }

std::uint64_t FxScene::step_index() const { return world_->step_index(); }

}  // namespace fx2d

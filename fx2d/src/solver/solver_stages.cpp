// The solver's stages of a step (solver_stages.h). Collision runs once per step and substeps stay
// cheap: contact anchors are fixed for the step and separations are updated from each body's
// accumulated displacement.
#include "solver/solver_stages.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "world/step_context.h"

namespace fx2d::detail {
namespace {

// How user constraints (joints) see the solver's state during the substeps.
class SolverConstraintContext final : public FxConstraintContext {
 public:
  SolverConstraintContext(const StepContext& step, SolverData& solver, const Bodies& bodies)
      : solver_(solver), bodies_(bodies) {
    substep_dt = step.substep_dt;
    impulse_ratio = step.impulse_ratio;
    inv_substep_dt = step.contact.inv_substep_dt;
    softness = step.joint_softness;
    max_linear_speed = step.limits.max_speed;
    max_angular_speed = step.limits.max_spin;
  }
  FxBodyState& state(const FxEntity& e) override { return solver_.states[e.packed_index()]; }
  float inv_mass(const FxEntity& e) const override { return sim(e).inv_mass; }
  float inv_inertia(const FxEntity& e) const override { return sim(e).inv_inertia; }
  FxRot start_rotation(const FxEntity& e) const override { return sim(e).rotation; }
  FxVec2f center_offset(const FxEntity& a, const FxEntity& b) const override {
    return bodies_.center_offset(a.packed_index(), b.packed_index());
  }
  FxVec2f local_center(const FxEntity& e) const override { return sim(e).local_center; }

 private:
  const BodySim& sim(const FxEntity& e) const { return bodies_.sims[e.packed_index()]; }

  SolverData& solver_;
  const Bodies& bodies_;
};

// Component-wise, so that a force large enough to overflow inv_mass * force to infinity still gives
// a finite acceleration (the velocity clamp then keeps its direction); below the bound, unchanged.
FxVec2f clamped_acceleration(FxVec2f acceleration, float bound) {
  return {std::clamp(acceleration.x, -bound, bound), std::clamp(acceleration.y, -bound, bound)};
}

// Refreshes the box of a body write_back_bodies() has written. compute_aabb() reads its transform
// with one 16-byte load, and a load the CPU cannot forward from the narrower stores still in its
// store buffer waits for them to reach the cache: so the boxes of a block are refreshed after the
// whole block is written back (the pose's stores long done), and the transform is written
// in one 16-byte store, not a temporary's two eight-byte ones (without both, the integrate stage
// took 1.06 to 1.16 times as long on the canonical scenes).
void refresh_box(BodySim& sim, BodyRecord& record, const BroadPhase& broad, float dt) {
  using Row = float __attribute__((vector_size(16)));
  static_assert(sizeof(FxTransform) == sizeof(Row), "a transform is four floats");
  const Row row = {sim.origin.x, sim.origin.y, sim.rotation.c, sim.rotation.s};
  FxTransform pose;
  std::memcpy(static_cast<void*>(&pose), &row, sizeof row);
  record.shape.compute_aabb(pose, sim.aabb);
  broad.refresh(record, sim, dt);
}

// Whether a moving body keeps the world in the rest schedule: a dynamic body that has rested long
// enough and is still slow (the user may have set its velocity or struck it since), or a kinematic
// one standing still. sleep_time is counted whether or not bodies may sleep.
bool keeps_rest(const BodyRecord& record, const BodySim& sim, const FxSceneSettings& settings) {
  const FxVec2f v = sim.linear_velocity;
  const float w = sim.angular_velocity;
  if (record.type != FxBodyType::dynamic) return v.x == 0.0f && v.y == 0.0f && w == 0.0f;
  const float linear = settings.linear_sleep_speed, angular = settings.angular_sleep_speed;
  return record.sleep_time >= settings.rest_schedule_time && v.x * v.x + v.y * v.y < linear * linear &&
         w * w < angular * angular;
}

// Whether no movable body stands on a chain of more than `depth` bodies. The chains depend only on
// the links and which bodies are movable, so when the contacts have the bodies, point counts and
// movability they had at the last step (ContactGraph::same_as_last), and no joint links anything,
// the last step's answer to the same question stands; one pass over the contacts instead of a
// breadth-first search (the same bits).
bool chains_within(SolverData& solver, const SolverData::ChainsFound& last,
                   std::span<const ConstraintSource> sources, const Constraints& joints, int depth) {
  const bool same =
      last.depth == depth && joints.empty() && solver.contact_graph.same_as_last(sources, solver.states);
  const bool within =
      same ? last.within : solver.support_chains.all_within(sources, joints, solver.states, depth);
  // An answer found through joints is not kept: with them gone, the same contacts may hold deeper chains.
  if (joints.empty()) solver.chains_found = {depth, within};
  return within;
}

// The passes of a step not at rest: the shallow schedule's, the impact schedule's or the settings'
// (FxSceneSettings). The closing speed first, as it costs one read per contact and rules out a
// shallow step of impacts before any chain is followed.
PassCounts passes_of_moving_step(const StepContext& step, SolverData& solver,
                                 const SolverData::ChainsFound& last, const Bodies& bodies,
                                 const ContactCache& contacts, const Constraints& constraints) {
  const FxSceneSettings& settings = step.settings;
  const std::span<const ConstraintSource> sources = solver.contact_solver.sources();
  const Closing closing = closing_speeds(sources, contacts, bodies,
                                         settings.impact_schedule_travel * step.contact.inv_substep_dt);
  if (settings.shallow_schedule && closing.fastest <= settings.shallow_schedule_speed &&
      chains_within(solver, last, sources, constraints, settings.shallow_schedule_depth)) {
    return light_schedule_passes;
  }
  if (closing.impact) {
    return {std::max(settings.velocity_passes, settings.impact_velocity_passes), settings.relax_passes};
  }
  return {settings.velocity_passes, settings.relax_passes};
}

}  // namespace

void SolverData::reserve(std::size_t bodies) {
  states.reserve(bodies + 1);
  integration.reserve(bodies);
  contact_solver.reserve(4 * bodies, bodies + 1);
  contact_graph.reserve(4 * bodies, bodies + 1);
  contact_batches.reserve(4 * bodies);
  support_chains.reserve(bodies + 1, 4 * bodies);
}

void prepare_solver(const StepContext& step, SolverData& solver, const Bodies& bodies,
                    const ContactCache& contacts, const Constraints& constraints) {
  // Gather the hot state of every awake body; sleeping and static ones keep zero velocity and are
  // never written by a constraint (a touching constraint always has its bodies awake). Every state
  // is cleared in one fill, which the compiler turns into wide stores, before the loop that skips
  // the bodies at rest: a sleeping body costs a store and a test here.
  const FxSceneSettings& settings = step.settings;
  // Good for this step only if this step looks again (chains_within).
  const SolverData::ChainsFound last_chains = std::exchange(solver.chains_found, {});
  const std::vector<BodyRecord>& records = bodies.records;
  const std::vector<BodySim>& sims = bodies.sims;
  BodyIntegration& integration = solver.integration;
  std::vector<FxBodyState>& states = solver.states;
  integration.clear(step.body_count, records.size());
  // A world asleep gathers no state and builds no constraint (a touching constraint always has an
  // awake body): the stages after this one read only the empty lists of moving bodies and
  // constraints. Its profile reports the settings' passes.
  if (bodies.awake_count == 0) {
    solver.passes = {settings.velocity_passes, settings.relax_passes};
    integration.finish();
    solver.contact_solver.clear();
    return;
  }
  const float h = step.substep_dt;
  states.assign(records.size() + 1, FxBodyState{});
  bool at_rest = settings.rest_schedule;
  for (std::uint32_t i = 0; i < records.size(); ++i) {
    const bool moves = records[i].awake && records[i].type != FxBodyType::static_body;
    if (!moves) continue;
    FxBodyState& state = states[i];
    state.linear_velocity = sims[i].linear_velocity;
    state.angular_velocity = sims[i].angular_velocity;
    at_rest = at_rest && keeps_rest(records[i], sims[i], settings);
    integration.add_moving(i);
    if (records[i].type != FxBodyType::dynamic) continue;
    state.flags = movable_flag;
    integration.add_dynamic(
        i, clamped_acceleration(settings.gravity + sims[i].inv_mass * sims[i].force, step.max_acceleration),
        1.0f / (1.0f + h * records[i].linear_damping), 1.0f / (1.0f + h * records[i].angular_damping));
  }
  integration.finish();
  solver.contact_solver.prepare(contacts, bodies);
  solver.at_rest = at_rest;
  solver.passes = at_rest ? light_schedule_passes
                          : passes_of_moving_step(step, solver, last_chains, bodies, contacts, constraints);
}

void colour_and_pack(const StepContext& step, SolverData& solver, const Bodies& bodies, const ContactCache& contacts) {
  const std::span<const ConstraintSource> constraints = solver.contact_solver.sources();
  solver.contact_graph.build(constraints, solver.states);
  solver.contact_batches.pack(constraints, solver.contact_graph, contacts, bodies, step.body_count, step.tasks,
                              step.settings.force_scalar_solver);
  solver.contact_batches.update_separations(solver.states, step.contact.linear_slop, step.tasks);
  solver.separations_once = solver.at_rest && solver.contact_batches.separations_hold(
                                                  step.settings.dt, solver.integration.largest_acceleration(),
                                                  resting_rebound / step.contact.softness.bias_rate);
}

namespace {

// The substep's stages. Each switches the step's clock to itself; a user constraint's share of
// a stage is charged to FxStage::constraints.
class Substep {
 public:
  Substep(const StepContext& step, SolverData& solver, const Bodies& bodies, const Constraints& constraints)
      : step_(step), solver_(solver), constraints_(constraints), joints_(step, solver, bodies) {
    if (constraints_.empty()) return;
    step_.clock.switch_to(FxStage::constraints);
    solver_.joint_rows.prepare(constraints_, bodies, joints_, solver_.states);
  }

  // Keeps the joints' impulses for the next step's warm start.
  void finish() {
    if (constraints_.empty()) return;
    step_.clock.switch_to(FxStage::constraints);
    solver_.joint_rows.store();
  }

  void set_point_order(PointOrder order) { point_order_ = order; }

  // With `carry_impulses`, the integration also gives each body the substep's warm start
  // (carries_warm_start()).
  void integrate_velocities(bool carry_impulses) {
    step_.clock.switch_to(FxStage::integrate);
    solver_.integration.integrate_velocities(solver_.states, step_.substep_dt, step_.limits, carry_impulses,
                                             step_.tasks);
  }

  // The first substep's warm start applies the impulses the contacts kept from the last step, with
  // the rows pack() worked out for this one. A later substep's reapplies the impulses accumulated
  // in the substeps before, through the same rows, which is exactly what they changed each body's
  // velocity by since its last integration: so the integration carries that change on, and the
  // sweep over the contacts is left out. Not with joints: their rows turn with their bodies within
  // the step.
  bool carries_warm_start(int substep) const { return substep > 0 && constraints_.empty(); }

  void warm_start() {
    if (!constraints_.empty()) {
      step_.clock.switch_to(FxStage::constraints);
      solver_.joint_rows.warm_start(solver_.states, step_.settings.force_scalar_solver);
    }
    step_.clock.switch_to(FxStage::warm_start);
    solver_.contact_batches.warm_start(solver_.states, step_.settings.force_scalar_solver, step_.tasks);
  }

  void solve() {
    for (int pass = 0; pass < solver_.passes.velocity; ++pass) velocity_pass(FxStage::solve, true);
    solver_.contact_batches.push(solver_.states, step_.contact, step_.settings.force_scalar_solver, step_.tasks);
  }

  void integrate_positions() {
    step_.clock.switch_to(FxStage::integrate);
    // Clamped again here and at the step's end: the passes can push a body squeezed between
    // immovable bodies, or held by joints that fight, past the limits the integration kept.
    solver_.integration.integrate_positions(solver_.states, step_.substep_dt, step_.limits, step_.tasks);
  }

  void relax() {
    step_.clock.switch_to(FxStage::relax);
    solver_.contact_batches.take_back_push(solver_.states, step_.settings.force_scalar_solver, step_.tasks);
    if (!solver_.separations_once) {
      solver_.contact_batches.update_separations(solver_.states, step_.contact.linear_slop, step_.tasks);
    }
    for (int pass = 0; pass < solver_.passes.relax; ++pass) {
      velocity_pass(FxStage::relax, false, pass < step_.settings.joint_relax_passes);
    }
  }

 private:
  // One pass over every constraint (unless `with_joints` is false), then every contact: contacts
  // last, so they win conflicts.
  void velocity_pass(FxStage stage, bool use_bias, bool with_joints = true) {
    if (with_joints && !constraints_.empty()) {
      step_.clock.switch_to(FxStage::constraints);
      solver_.joint_rows.evaluate(solver_.states, use_bias, step_.settings.force_scalar_solver);
    }
    step_.clock.switch_to(stage);
    solver_.contact_batches.resolve_velocities(solver_.states, step_.contact, use_bias, point_order_,
                                               step_.settings.force_scalar_solver, step_.tasks);
  }

  const StepContext& step_;
  SolverData& solver_;
  const Constraints& constraints_;
  SolverConstraintContext joints_;
  PointOrder point_order_ = PointOrder::first_to_last;
};

}  // namespace

void solve_substeps(const StepContext& step, SolverData& solver, const Bodies& bodies, const Constraints& constraints) {
  // Nothing moves and nothing holds: every substep would sweep empty lists.
  if (solver.integration.moving_bodies().empty() && constraints.empty()) return;
  Substep substep(step, solver, bodies, constraints);
  for (int i = 0; i < step.settings.substeps; ++i) {
    substep.set_point_order(i % 2 == 0 ? PointOrder::first_to_last : PointOrder::last_to_first);
    const bool carried = substep.carries_warm_start(i);
    substep.integrate_velocities(carried);
    if (!carried) substep.warm_start();
    substep.solve();
    substep.integrate_positions();
    substep.relax();
  }
  substep.finish();
}

void apply_restitution(const StepContext& step, SolverData& solver) {
  solver.contact_solver.apply_restitution(solver.contact_batches, solver.states, step.settings.restitution_threshold);
}

void solve_positions(const StepContext& step, SolverData& solver) {
  for (int pass = 0; pass < step.settings.position_passes; ++pass) {
    solver.contact_solver.project_positions(solver.contact_batches, solver.states, step.settings.linear_slop);
  }
}

void finalize_bodies(const StepContext& step, const SolverData& solver, Bodies& bodies, const BroadPhase& broad) {
  const std::span<const std::uint32_t> moving = solver.integration.moving_bodies();
  const auto count = static_cast<std::uint32_t>(moving.size());
  step.tasks.for_each_range(count, step.tasks.per_worker(count, lane_count), min_parallel_bodies,
                            [&](std::uint32_t first, std::uint32_t last) {
                              const std::span<const std::uint32_t> block = moving.subspan(first, last - first);
                              write_back_bodies(block, solver.states.data(), bodies.sims.data(),
                                                bodies.records.data(), step.limits, step.settings);
                              for (const std::uint32_t i : block) {
                                bodies.sims[i].force = {};
                                refresh_box(bodies.sims[i], bodies.records[i], broad, step.settings.dt);
                              }
                            });
}

void store_impulses(const SolverData& solver, ContactCache& contacts) {
  solver.contact_solver.store_impulses(solver.contact_batches, contacts);
}

}  // namespace fx2d::detail

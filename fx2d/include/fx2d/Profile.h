// Where a step's time went: one timer per stage function of FxScene::step().
//
// Each stage is one function of the step (see src/world/scene.cpp), so a phase in a result file names
// code a reader can open. Cycles come from the time-stamp counter (reference cycles, not core
// cycles) read where the step changes stage, once per change; milliseconds are the step's
// wall-clock time shared out in proportion to cycles, which costs one clock read per step instead
// of two per stage. The step callback runs after the last stage and is in no stage. With
// FX2D_PROFILE off, the timers compile to nothing and the profile stays zero.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace fx2d {

enum class FxStage : int {
  broad_phase,      // update_broad_phase: proxy tree updates, new pair search
  collide,          // update_contacts: contact manifolds and the contact cache
  prepare,          // prepare_solver: gather the bodies' state, build the contact constraints
  colour_and_pack,  // colour_and_pack: colour the constraints, pack them into batches, first separations
  integrate,        // integrate_velocities and integrate_positions per substep, finalize_bodies
  warm_start,       // warm_start: the contacts' accumulated impulses, in the first substep (the later
                    // ones' integration carries them on when there are no joints)
  solve,            // solve: the velocity passes with position correction, per substep
  relax,            // relax: separations at the new poses, passes without correction, per substep
  restitution,      // apply_restitution, after the substeps
  position_solve,   // solve_positions: the final non-linear position projection
  continuous,       // solve_continuous: fast bodies stopped at their first time of impact
  constraints,      // user constraints (joints): preparation and their share of every pass
  store,            // store_impulses: impulses kept for the next step's warm start
  sleep,            // update_sleep: resting islands
};
inline constexpr int fx_stage_count = 14;

constexpr std::string_view stage_name(FxStage stage) {
  constexpr std::array<std::string_view, fx_stage_count> names = {
      "broad_phase", "collide",     "prepare",        "colour_and_pack", "integrate", "warm_start", "solve",
      "relax",       "restitution", "position_solve", "continuous",      "constraints", "store",   "sleep"};
  return names[static_cast<int>(stage)];
}

struct FxProfile {
  std::array<double, fx_stage_count> stage_ms{};             // milliseconds per stage, last step
  std::array<std::uint64_t, fx_stage_count> stage_cycles{};  // reference cycles per stage, last step
  double step_ms = 0.0;                                      // whole step, wall clock
  std::uint64_t step_cycles = 0;
  // The passes per substep the last step took: the settings', one and one on the rest or the
  // shallow schedule, or more soft passes on the impact schedule (FxSceneSettings::rest_schedule,
  // shallow_schedule, impact_schedule_travel). Filled in with or without FX2D_PROFILE.
  int velocity_passes = 0;
  int relax_passes = 0;

  double ms(FxStage stage) const { return stage_ms[static_cast<int>(stage)]; }
  std::uint64_t cycles(FxStage stage) const { return stage_cycles[static_cast<int>(stage)]; }
};

// True when the library was built with FX2D_PROFILE, i.e. profiles are filled in.
bool fx_profiling_enabled();

}  // namespace fx2d

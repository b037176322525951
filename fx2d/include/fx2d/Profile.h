// Where a step's time went: one timer per named stage of FxScene::step().
//
// The stages are the functions of the step (see src/scene.cpp), so a phase in a result file maps
// onto code a reader can open. Cycles come from the time-stamp counter (reference cycles, not
// core cycles) read at stage boundaries; milliseconds are the step's wall-clock time shared out in
// proportion to cycles, which costs one clock read per step instead of two per stage. With
// FX2D_PROFILE off, the timers compile to nothing and the profile stays zero.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace fx2d {

enum class FxStage : int {
  integration,      // velocity and position integration, pose finalisation
  broad_phase,      // bounding boxes, proxy tree updates, new pair search
  narrow_phase,     // contact manifolds and the contact cache
  velocity_passes,  // contact preparation, colouring, warm starting, velocity passes, relaxation, restitution
  position_solve,   // the final non-linear position projection
  constraints,      // user constraints (joints): preparation and their share of every pass
  bookkeeping,      // sleeping, impulse storage, the step callback
};
inline constexpr int fx_stage_count = 7;

constexpr std::string_view stage_name(FxStage stage) {
  constexpr std::array<std::string_view, fx_stage_count> names = {
      "integration", "broad_phase", "narrow_phase", "velocity_passes", "position_solve", "constraints", "bookkeeping"};
  return names[static_cast<int>(stage)];
}

struct FxProfile {
  std::array<double, fx_stage_count> stage_ms{};             // milliseconds per stage, last step
  std::array<std::uint64_t, fx_stage_count> stage_cycles{};  // reference cycles per stage, last step
  double step_ms = 0.0;                                      // whole step, wall clock
  std::uint64_t step_cycles = 0;

  double ms(FxStage stage) const { return stage_ms[static_cast<int>(stage)]; }
  std::uint64_t cycles(FxStage stage) const { return stage_cycles[static_cast<int>(stage)]; }
};

// True when the library was built with FX2D_PROFILE, i.e. profiles are filled in.
bool fx_profiling_enabled();

}  // namespace fx2d

// The step context: what the stages of one step read, worked out once when the step begins.
//
// Every per-step value (the substep time h and its inverse, the soft-constraint coefficients, the
// speed limits, the body count, the threads) has exactly one expression, here, so no two stages can derive the
// same value differently: a value computed twice by different expressions may differ in the last
// bit, and the solver's results are compared bit for bit.
#pragma once

#include <cstdint>

#include "solver/body_integration.h"
#include "solver/contact_solver.h"
#include "fx2d/Constraint.h"
#include "fx2d/Scene.h"
#include "world/profile_timer.h"
#include "world/tasks.h"

namespace fx2d::detail {

struct StepContext {
  // last_substep_dt: the h of the step before, 0 before the first.
  StepContext(const FxSceneSettings& settings, float last_substep_dt, std::uint32_t body_count,
              StageClock& clock, const Tasks& tasks);

  const FxSceneSettings& settings;
  float substep_dt;            // h: seconds per substep
  // h over the last step's h (1 for the first step). The impulses carried from the last step for
  // warm starting were a substep's, so they are scaled by it: a resting load needs m g h a substep.
  float impulse_ratio;
  float max_acceleration;      // m/s^2; more would pass max_linear_speed within one substep
  SpeedLimits limits;          // the scene's linear and angular speed limits
  ContactSolveParams contact;  // contact softness, 1/h and the largest push speed
  FxSoftness joint_softness;
  std::uint32_t body_count;    // bodies at the step's start; also the padding body's index
  StageClock& clock;           // charges each stage its time (profile_timer.h)
  const Tasks& tasks;          // the threads a stage may spread its loops over (tasks.h)
};

}  // namespace fx2d::detail

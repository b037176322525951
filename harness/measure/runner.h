// Times one engine on one scene: the measurement loop behind `fx2d-bench run`.
//
// Invariants: building a scene is never timed; every timed repeat starts from a freshly built
// instance, so every repeat times the same trajectory from t = 0; the warm-up runs on its own
// discarded instance, so it warms caches and branch predictors without changing what is
// measured; accuracy and state hashes are read only between steps, after the step's clocks have
// stopped, and only on the first repeat; the step loop allocates nothing in the timed region.
#pragma once

#include <functional>
#include <string_view>

#include "common/results.h"
#include "engines/engine.h"
#include "scene/scene_spec.h"

namespace fxbench {

struct RunPlan {
  int repeats = 5;          // timed repeats of scene.steps steps, >= 1
  int warmup_steps = 0;     // untimed steps on a discarded instance before the repeats, >= 0
  int hash_every = 50;      // state hash after every hash_every-th step and after the last, >= 1
  int accuracy_every = 10;  // accuracy sample after every accuracy_every-th step and the last, >= 1
};

// Reported before the warm-up, before each repeat, and once when the run is done.
struct RunProgress {
  std::string_view engine;
  std::string_view scene;
  int repeat = 0;           // the repeat about to run, 1-based; 0 during the warm-up
  int repeats = 0;
  long steps_done = 0;      // steps this run has finished so far, warm-up included
};
using ProgressFn = std::function<void(const RunProgress&)>;

// Steps a run takes in all, warm-up included, for progress estimates.
long planned_steps(const SceneSpec& scene, const RunPlan& plan);

// Builds and times `engine` on `scene` per `plan`. Engine failures propagate as thrown.
// On a SIGINT (interrupt.h) it stops between two steps and returns only the whole repeats done:
// `repeats` < plan.repeats, and 0 (an empty record) if the first repeat was not finished.
RunRecord measure_engine(const SceneSpec& scene, const EngineInfo& engine, const RunPlan& plan,
                         const ProgressFn& progress = {});

}  // namespace fxbench

// `fx2d-bench count-instructions` (hidden from --help): the child that `run --counter
// instructions` starts under `valgrind --tool=callgrind --collect-atstart=no`
// (instruction_counter.h). It loads one scene, builds it on one engine outside the count, and
// turns callgrind's collection on for exactly the step loop: scene.steps steps of that freshly
// built instance, nothing before or after. Callgrind writes the count when the process ends.
//
// Reads top to bottom: the options, the refusals (not under valgrind, not exactly one scene, a
// scene that is not the one the parent resolved, an unknown engine), then the counted loop.
#include <memory>

#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "engines/engine.h"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define FX2D_BENCH_HAVE_CALLGRIND 1
#else
#define FX2D_BENCH_HAVE_CALLGRIND 0
#endif

namespace fxbench {
namespace {

struct CountOptions {
  SceneOptions scenes;
  std::string engine;
  std::string scene_hash;
};

bool running_under_valgrind() {
#if FX2D_BENCH_HAVE_CALLGRIND
  return RUNNING_ON_VALGRIND != 0;
#else
  return false;
#endif
}

// Only the loop is counted: callgrind's collection is toggled on before the first step and off
// after the last, so building and tearing down the instance are outside the count.
void step_counted(Engine& engine, int steps) {
#if FX2D_BENCH_HAVE_CALLGRIND
  CALLGRIND_TOGGLE_COLLECT;
  for (int step = 0; step < steps; ++step) engine.step();
  CALLGRIND_TOGGLE_COLLECT;
#else
  (void)engine;
  (void)steps;
#endif
}

void count_instructions_command(const CountOptions& options) {
  if (!FX2D_BENCH_HAVE_CALLGRIND)
    throw InputError("count-instructions: this fx2d-bench was built without valgrind/callgrind.h");
  if (!running_under_valgrind())
    throw InputError("count-instructions counts only under valgrind --tool=callgrind --collect-atstart=no; "
                     "use fx2d-bench run --counter instructions");
  const std::vector<SceneSpec> scenes = options.scenes.load();
  if (scenes.size() != 1) throw InputError("count-instructions: expected exactly one SCENE");
  const SceneSpec& scene = scenes.front();
  if (!options.scene_hash.empty() && scene.hash != options.scene_hash)
    throw InputError("count-instructions: scene " + scene.name + " resolves to hash " + scene.hash + ", expected " +
                     options.scene_hash);
  const EngineInfo* info = find_engine(options.engine);
  if (info == nullptr) throw InputError("count-instructions: --engine " + options.engine + ": no such engine");

  const std::unique_ptr<Engine> engine = info->make();
  engine->build(scene);
  step_counted(*engine, scene.steps);
}

}  // namespace

void register_count_instructions(CLI::App& app) {
  auto options = std::make_shared<CountOptions>();
  CLI::App* count = app.add_subcommand("count-instructions",
                                       "Internal: the step loop under callgrind, for run --counter instructions");
  count->group("");  // hidden: a user asks for counts with `run --counter instructions`
  options->scenes.add_to(*count, "pile");
  count->add_option("--engine", options->engine, "The engine, any name find_engine() takes (plugins included)")
      ->required();
  count->add_option("--scene-hash", options->scene_hash, "Refuse a scene that does not resolve to this hash");
  count->callback([options] { count_instructions_command(*options); });
}

}  // namespace fxbench

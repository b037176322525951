// The shared option groups; see cli_options.h.
#include "commands/cli_options.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>

#include "common/errors.h"
#include "engines/plugin_engine.h"
#include "scene/scene_loader.h"

namespace fxbench {
namespace {

const CLI::Validator json_pointer_assignment(
    [](std::string& text) -> std::string {
      const auto equals = text.find('=');
      if (text.starts_with('/') && equals != std::string::npos && equals > 1) return {};
      return "expected /json/pointer=value, got '" + text + "'";
    },
    "/POINTER=VALUE");

}  // namespace

void SceneOptions::add_to(CLI::App& command, const std::string& default_scene) {
  scenes = {default_scene};
  command.add_option("SCENE", scenes, "Scene files, or names of embedded scenes (pile, stacks, settling_boxes)")
      ->capture_default_str();
  bodies_option = command.add_option("--bodies", bodies, "The scene's size parameter N (e.g. pile: circles)")
                      ->check(CLI::Range(1, 1'000'000));
  steps_option = command.add_option("--steps", steps, "Steps per repeat (default: the scene's, 200 for canonical scenes)")
                     ->check(CLI::Range(1, 10'000'000));
  command.add_option("--set", sets, "Override any scene field by JSON pointer, e.g. --set /gravity/1=-9.81")
      ->check(json_pointer_assignment)
      ->allow_extra_args(false);
}

std::vector<SceneSpec> SceneOptions::load() const {
  SceneOverrides overrides;
  if (bodies_option->count() > 0) overrides.bodies = bodies;
  if (steps_option->count() > 0) overrides.steps = steps;
  for (const std::string& assignment : sets) {
    const auto equals = assignment.find('=');
    overrides.sets.emplace_back(assignment.substr(0, equals), assignment.substr(equals + 1));
  }
  std::vector<SceneSpec> specs;
  for (const std::string& scene : scenes) {
    specs.push_back(load_scene(scene, overrides));
    // The format allows a scene of no steps, but there is nothing in one to time or sample.
    if (specs.back().steps == 0)
      throw InputError("scene " + specs.back().name + ": /steps is 0; every measuring command needs at least 1 step");
  }
  return specs;
}

void EngineOptions::add_to(CLI::App& command) {
  std::vector<std::string> choices{"all"};
  for (const EngineInfo& engine : engine_registry()) choices.push_back(engine.name);
  command.add_option("--engine", names, "Engines to run, comma-separated, or all")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->check(CLI::IsMember(choices) | CLI::Validator(
                                           [](std::string& name) {
                                             return is_plugin_engine_name(name) ? std::string() : "not a plugin";
                                           },
                                           "plugin:PATH[|LABEL]"))
      ->capture_default_str();
}

std::vector<const EngineInfo*> EngineOptions::selected() const {
  const bool all = std::ranges::find(names, "all") != names.end();
  std::vector<const EngineInfo*> engines;
  for (const EngineInfo& engine : engine_registry())
    if (all || std::ranges::find(names, engine.name) != names.end()) engines.push_back(&engine);
  for (const std::string& name : names)  // plugins after the registry's engines, in the order given
    if (is_plugin_engine_name(name)) engines.push_back(find_engine(name));
  for (auto engine = engines.begin(); engine != engines.end(); ++engine) {
    if (!(*engine)->unavailable.empty()) throw InputError((*engine)->unavailable);
    if (std::ranges::find(engines.begin(), engine, (*engine)->name, &EngineInfo::name) != engine)
      throw InputError("--engine: two engines are named " + (*engine)->name +
                       "; give each plugin a label of its own (plugin:PATH|LABEL)");
  }
  return engines;
}

bool EngineOptions::came_with_all(const EngineInfo& engine) const {
  const bool in_registry = std::ranges::any_of(engine_registry(), [&](const EngineInfo& entry) { return &entry == &engine; });
  return in_registry && std::ranges::find(names, engine.name) == names.end();
}

std::vector<const EngineInfo*> EngineOptions::able_to_build(const SceneSpec& scene) const {
  std::vector<const EngineInfo*> able;
  for (const EngineInfo* engine : selected()) {
    const std::optional<std::string> missing = missing_capability(engine->capabilities, scene);
    if (!missing) {
      // The engine's knobs check its /solver block here, before anything is measured.
      if (!engine->knobs.empty()) knob_values(engine->solver, engine->knobs, scene);
      able.push_back(engine);
      continue;
    }
    if (!came_with_all(*engine)) throw InputError("scene " + scene.name + ": engine " + engine->name + " cannot build " + *missing);
    std::cerr << "fx2d-bench: scene " << scene.name << ": skipping " << engine->name << ", which cannot build "
              << *missing << '\n';
  }
  return able;
}

void ShardOptions::add_to(CLI::App& command) {
  command
      .add_option("--shard", text,
                  "Run only part K of N of the work list, or `auto` from FX2D_SHARD_INDEX/FX2D_SHARD_COUNT or "
                  "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT; join the parts with `fx2d-bench merge`")
      ->capture_default_str();
}

}  // namespace fxbench

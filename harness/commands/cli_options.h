// Option groups shared by subcommands: each struct registers its own CLI11 options and turns what
// was parsed into harness values, so every subcommand that selects scenes or engines spells and
// checks those options the same way.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "common/shard.h"
#include "engines/engine.h"
#include "scene/scene_spec.h"

namespace fxbench {

// SCENE ... --bodies N --steps N --set /pointer=value: which scenes, and overrides applied to
// each of them before validation (scene_loader.h).
struct SceneOptions {
  std::vector<std::string> scenes;
  int bodies = 0;
  int steps = 0;
  std::vector<std::string> sets;
  CLI::Option* bodies_option = nullptr;
  CLI::Option* steps_option = nullptr;

  // `default_scene` is used when no SCENE is given.
  void add_to(CLI::App& command, const std::string& default_scene);
  // A SCENE is a file when one exists at that path, else the name of an embedded scene.
  // Throws InputError.
  std::vector<SceneSpec> load() const;
};

// --engine fx2d,box2d,ode | all: which engines, always in registry order, each at most once.
struct EngineOptions {
  std::vector<std::string> names{"all"};

  void add_to(CLI::App& command);
  // Throws InputError when two of them would be recorded under one name (a plugin labelled fx2d
  // beside fx2d): results could not tell them apart.
  std::vector<const EngineInfo*> selected() const;
  // The selected engines that can build `scene` (EngineCapabilities). An engine named on the
  // command line that cannot is refused with InputError; one that came with `all` is left out,
  // with a line on stderr saying so.
  std::vector<const EngineInfo*> able_to_build(const SceneSpec& scene) const;

 private:
  // A registry engine selected by `all` rather than by its own name.
  bool came_with_all(const EngineInfo& engine) const;
};

// --shard K/N | auto: which part of the command's work list this process runs (shard.h).
struct ShardOptions {
  std::string text = "1/1";

  void add_to(CLI::App& command);
  // Throws InputError for a malformed value or `auto` with no scheduler's variables set.
  Shard shard() const { return parse_shard(text); }
};

}  // namespace fxbench

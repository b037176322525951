// Loads a scene file (JSON, format in scenes/README.md) into a SceneSpec.
//
// Command-line overrides are applied to the JSON before validation, so an override is checked
// exactly like the file itself, and the resolved scene (with every default filled in) is what is
// hashed and embedded in result files. Every error is an InputError whose message names the file,
// the line:column where the file has one, the JSON pointer, and what was expected.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene_spec.h"

namespace fxbench {

struct SceneOverrides {
  std::optional<int> bodies;                              // --bodies N: the scene's size parameter
  std::optional<int> steps;                               // --steps N
  std::vector<std::pair<std::string, std::string>> sets;  // --set /json/pointer=value (value is JSON, or a bare string)
};

// Reads and resolves `path`. Throws InputError.
SceneSpec load_scene_file(const std::string& path, const SceneOverrides& overrides = {});
// Resolves scene text; `origin` names it in messages (a path, or "<embedded:pile>").
SceneSpec load_scene_text(const std::string& text, const std::string& origin, const SceneOverrides& overrides = {});

// A scene named on a command line or in a policy: the file at `file_or_name` when one exists,
// else the embedded scene of that name. Throws InputError.
SceneSpec load_scene(const std::string& file_or_name, const SceneOverrides& overrides = {});

// The canonical scenes compiled into the binary, so a default run needs no file: "pile",
// "stacks", "settling_boxes" (the same text as scenes/<name>.json).
std::optional<std::string> embedded_scene_text(const std::string& name);

}  // namespace fxbench

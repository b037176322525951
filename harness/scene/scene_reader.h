// A parsed scene document into a SceneSpec: every value validated, defaults filled in and
// written back, generators expanded into explicit bodies.
#pragma once

#include "scene/json_reader.h"
#include "scene/scene_spec.h"

namespace fxbench::scene_detail {

// Builds the scene `document` describes and leaves in it exactly what the scene was built from
// (defaults and "auto" sizes resolved), so that its dump is the scene's resolved JSON. Refuses
// bad values through `errors`.
SceneSpec read_scene(const ErrorReporter& errors, Json& document);

}  // namespace fxbench::scene_detail

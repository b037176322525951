// A parsed scene document into a SceneSpec: every value validated, defaults filled in and
// written back, generators expanded into explicit bodies.
#pragma once

#include "scene/json_reader.h"
#include "scene/scene_spec.h"

namespace fxbench::scene_detail {

// Builds the scene `document` describes and leaves in it exactly what the scene was built from
// (defaults and "auto" sizes resolved), so that its dump is the scene's resolved JSON. Refuses
// bad values through `errors`, and, with `size_must_be_read` (a size given on the command line),
// a size that no generator takes its count from.
SceneSpec read_scene(const ErrorReporter& errors, Json& document, bool size_must_be_read);

}  // namespace fxbench::scene_detail

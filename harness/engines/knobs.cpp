// An engine's knobs read from a scene (engine.h): the one conversion from a scene's
// /solver/<engine> block to the values a plugin receives, and the one check of those values.
//
// Invariant: a value a plugin receives is of its knob's type and inside its range; a key of the
// block that is no knob of the engine is refused, so a misspelt knob never silently keeps its
// default.
#include <cmath>
#include <nlohmann/json.hpp>
#include <ranges>

#include "common/errors.h"
#include "common/number_text.h"
#include "engines/engine.h"
#include "scene/json_text.h"

namespace fxbench {
namespace {

using Json = nlohmann::json;

// The scene's /solver/<solver> block; empty for a scene built in code (no resolved JSON).
Json solver_block(const std::string& solver, const SceneSpec& scene) {
  const Json resolved = Json::parse(scene.resolved_json, nullptr, false);
  if (resolved.is_discarded() || !resolved.contains("solver")) return Json::object();
  return resolved["solver"].value(solver, Json::object());
}

double checked_value(const Knob& knob, const Json& value, const std::string& where) {
  const auto refuse = [&] {
    throw InputError(where + ": expected " + knob_range_text(knob) + ", got " + value.dump());
  };
  if (knob.type == Knob::Type::boolean) {
    if (!value.is_boolean()) refuse();
    return value.get<bool>() ? 1.0 : 0.0;
  }
  if (!value.is_number()) refuse();
  const double number = value.get<double>();
  if (knob.type == Knob::Type::integer && number != std::floor(number)) refuse();
  if (!(number >= knob.min && number <= knob.max)) refuse();
  return number;
}

}  // namespace

std::string knob_range_text(const Knob& knob) {
  if (knob.type == Knob::Type::boolean) return "true or false";
  const std::string kind = knob.type == Knob::Type::integer ? "an integer" : "a number";
  return kind + formatted(" from %g", knob.min) + formatted(" to %g", knob.max);
}

std::vector<double> knob_values(const std::string& solver, std::span<const Knob> knobs,
                                const SceneSpec& scene) {
  const Json block = solver_block(solver, scene);
  // A value's place as the scene loader found it (a file's line:column, or the --set that wrote
  // it); the scene's name for a value the scene format itself filled in.
  const auto where = [&](const std::string& key) {
    const std::string pointer = scene_detail::child_pointer("/solver/" + solver, key);
    const auto place = scene.knob_places.find(pointer);
    const std::string origin = place != scene.knob_places.end() ? place->second
                               : scene.source_path.empty()      ? "scene " + scene.name
                                                                : scene.source_path;
    return origin + ": " + scene_detail::display_pointer(pointer);
  };
  for (const auto& [key, value] : block.items()) {
    if (std::ranges::find(knobs, key, &Knob::name) == knobs.end()) {
      std::string names;
      for (const Knob& knob : knobs) names += (names.empty() ? "" : ", ") + knob.name;
      throw InputError(where(key) + ": not a knob of " + solver + "; expected one of " + names);
    }
  }
  std::vector<double> values;
  for (const Knob& knob : knobs)
    values.push_back(block.contains(knob.name) ? checked_value(knob, block[knob.name], where(knob.name))
                                               : knob.default_value);
  return values;
}

// The scene format writes the defaults of its own blocks into the resolved scene, but for keys it
// leaves out to keep older scenes' hashes: those blocks are recorded as they are. A plugin's block
// holds only what the scene gives, so its knobs' defaults are filled in here.
std::string engine_settings_json(const EngineInfo& engine, const SceneSpec& scene) {
  Json block = solver_block(engine.solver, scene);
  if (std::ranges::find(format_solver_blocks, engine.solver) != format_solver_blocks.end())
    return block.dump();
  for (const Knob& knob : engine.knobs) {
    if (block.contains(knob.name)) continue;
    if (knob.type == Knob::Type::boolean)
      block[knob.name] = knob.default_value != 0.0;
    else if (knob.type == Knob::Type::integer)
      block[knob.name] = static_cast<long long>(knob.default_value);
    else
      block[knob.name] = knob.default_value;
  }
  return block.dump();
}

}  // namespace fxbench

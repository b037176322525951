// Loads scene files (format: scenes/README.md) into SceneSpecs: parse, apply command-line
// overrides, validate, fill defaults, expand generators into explicit bodies.
//
// Invariant: every value is taken through one reader call that checks it and writes the resolved
// value back into the document, so resolved_json holds exactly what the SceneSpec was built from
// and nothing else; every rejection is one InputError line naming where the value came from (a
// file's line:column, or the command-line override that set it), its JSON pointer, and what was
// expected.
#include "scene/scene_loader.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string_view>

#include "common/bounded_read.h"
#include "common/errors.h"
#include "common/hash.h"
#include "scene/json_reader.h"
#include "scene/json_text.h"
#include "scene/scene_reader.h"

namespace fxbench {
namespace {

using namespace scene_detail;

// ---------------------------------------------------------------------------------------------
// Overrides

// Writes `value` at `pointer`, creating the objects on the way that the document leaves out (a
// file says only what differs from the defaults). Returns the pointer of what it wrote: the
// value's, or that of the first object it had to create.
std::string write_override(Json& document, const std::string& pointer, Json value, const std::string& label) {
  const auto tokens = split_pointer(pointer);
  if (!tokens || tokens->empty()) {
    throw InputError(label + ": expected a JSON pointer such as /solver/fx2d/substeps, got " +
                     in_quotes(pointer));
  }
  Json* node = &document;
  std::string at;
  std::optional<std::string> first_created;
  for (std::size_t i = 0; i < tokens->size(); ++i) {
    const std::string& token = (*tokens)[i];
    const bool last = i + 1 == tokens->size();
    const std::string parent = at;
    at = child_pointer(at, token);
    if (node->is_object()) {
      if (!node->contains(token) && !first_created) first_created = at;
      node = &(*node)[token];
      if (!last && node->is_null()) *node = (*tokens)[i + 1] == "-" ? Json::array() : Json::object();
    } else if (node->is_array()) {
      if (last && token == "-") {
        node->push_back(Json());
        node = &node->back();
        if (!first_created) first_created = child_pointer(parent, node->size() - 1);
        continue;
      }
      const std::optional<std::size_t> index = parse_array_index(token);
      if (!index || *index >= node->size()) {
        throw InputError(label + ": " + display_pointer(parent) + ": expected an index below " +
                         std::to_string(node->size()) + (last ? " or \"-\"" : "") + ", got " +
                         in_quotes(token));
      }
      node = &(*node)[*index];
    } else {
      throw InputError(label + ": " + display_pointer(parent) + ": expected an object or an array to hold " +
                       in_quotes(token) + ", got " + describe_value(*node));
    }
  }
  *node = std::move(value);
  return first_created.value_or(pointer);
}

// The text as JSON if it parses, else as a string, so --set /name=pile2 needs no quotes.
Json parse_override_value(const std::string& text, const std::string& label) {
  Json value = Json::parse(text, nullptr, false);
  if (!value.is_discarded()) return value;
  value = text;
  try {
    value.dump();
  } catch (const Json::type_error&) {
    throw InputError(label + ": expected UTF-8 text, got bytes that are not");
  }
  return value;
}

void apply_overrides(Json& document, const SceneOverrides& overrides, ErrorReporter& errors) {
  const auto apply = [&](const std::string& label, const std::string& pointer, Json value) {
    errors.add_override({label, write_override(document, pointer, std::move(value), label)});
  };
  if (overrides.bodies) apply("--bodies " + std::to_string(*overrides.bodies), "/size", *overrides.bodies);
  if (overrides.steps) apply("--steps " + std::to_string(*overrides.steps), "/steps", *overrides.steps);
  for (const auto& [pointer, value_text] : overrides.sets) {
    const std::string label = "--set " + pointer + "=" + value_text;
    apply(label, pointer, parse_override_value(value_text, label));
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Loading

SceneSpec load_scene_text(const std::string& text, const std::string& origin,
                          const SceneOverrides& overrides) {
  Json document = parse_json_text(text, origin, "a scene");
  ErrorReporter errors(text, origin);
  apply_overrides(document, overrides, errors);
  SceneSpec spec = read_scene(errors, document, overrides.bodies.has_value());
  spec.resolved_json = document.dump(2);
  Fnv1a64 hash;
  hash.add(spec.resolved_json);
  spec.hash = hash.hex();
  return spec;
}

SceneSpec load_scene_file(const std::string& path, const SceneOverrides& overrides) {
  if (std::filesystem::is_directory(path)) throw InputError(path + ": cannot open: " + std::strerror(EISDIR));
  // Scenes are compact (generators, not body lists of millions); a larger file is not a scene,
  // and parsing one can cost gigabytes first.
  const std::string text = read_bounded_file(path, "a scene file");
  SceneSpec spec = load_scene_text(text, path, overrides);
  spec.source_path = path;
  return spec;
}

SceneSpec load_scene(const std::string& file_or_name, const SceneOverrides& overrides) {
  if (std::filesystem::exists(file_or_name)) return load_scene_file(file_or_name, overrides);
  if (const auto text = embedded_scene_text(file_or_name)) {
    return load_scene_text(*text, "<embedded:" + file_or_name + ">", overrides);
  }
  throw InputError(file_or_name + ": no such scene file, nor the name of an embedded scene");
}

}  // namespace fxbench

// `fx2d-bench engines`: the engines the harness can run, in registry order, with their library
// versions and the solver settings each reads from a scene (and, in JSON, the file each engine
// loaded as a plugin came from, and every knob as the engine declares it). `--engine` takes
// plugins as every measuring command does, so a plugin's author sees its knobs as fx2d-bench does.
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands/cli_options.h"
#include "commands/commands.h"
#include "engines/engine.h"
#include "format/text_table.h"

namespace fxbench {
namespace {

struct EnginesOptions {
  EngineOptions engines;
  bool json = false;
  bool knobs = false;
};

const char* type_name(Knob::Type type) {
  if (type == Knob::Type::boolean) return "boolean";
  return type == Knob::Type::integer ? "integer" : "number";
}

// The default as a scene would write it: true/false for a boolean.
nlohmann::ordered_json default_json(const Knob& knob) {
  if (knob.type == Knob::Type::boolean) return knob.default_value != 0.0;
  if (knob.type == Knob::Type::integer) return static_cast<long long>(knob.default_value);
  return knob.default_value;
}

nlohmann::ordered_json knobs_json(const EngineInfo& engine) {
  nlohmann::ordered_json knobs = nlohmann::ordered_json::array();
  for (const Knob& knob : engine.knobs) {
    knobs.push_back({{"name", knob.name}, {"type", type_name(knob.type)}, {"min", knob.min}, {"max", knob.max},
                     {"default", default_json(knob)}, {"description", knob.description}});
  }
  return knobs;
}

// One line a knob: ENGINE.KNOB (what --axis names), what it takes, its default, what it does.
void print_knobs(const std::vector<const EngineInfo*>& engines) {
  std::vector<std::vector<std::string>> rows;
  for (const EngineInfo* engine : engines) {
    for (const Knob& knob : engine->knobs) {
      rows.push_back({engine->name + "." + knob.name, knob_range_text(knob),
                      "default " + default_json(knob).dump(), knob.description});
    }
  }
  std::cout << aligned_columns(rows);
}

void list_engines(const EnginesOptions& options) {
  const std::vector<const EngineInfo*> engines = options.engines.selected();
  if (options.json) {
    nlohmann::ordered_json listing = nlohmann::ordered_json::array();
    for (const EngineInfo* engine : engines) {
      listing.push_back({{"name", engine->name}, {"version", engine->version}, {"settings", engine->settings}});
      if (!engine->plugin_path.empty()) listing.back()["plugin"] = engine->plugin_path;
      listing.back()["knobs"] = knobs_json(*engine);
    }
    std::cout << nlohmann::ordered_json{{"schema", "fx2d-bench.engines/1"}, {"engines", listing}}.dump(2) << '\n';
    return;
  }
  if (options.knobs) return print_knobs(engines);
  std::vector<std::vector<std::string>> rows;
  for (const EngineInfo* engine : engines) rows.push_back({engine->name, engine->version, engine->settings});
  std::cout << aligned_columns(rows);
}

}  // namespace

void register_engines(CLI::App& app) {
  auto options = std::make_shared<EnginesOptions>();
  CLI::App* engines = app.add_subcommand("engines", "List the engines with their versions and settings");
  options->engines.add_to(*engines);
  engines->add_flag("--knobs", options->knobs,
                    "One line per knob: ENGINE.KNOB, what it takes, its default and what it does");
  engines->add_flag("--json", options->json, "Print one JSON object (fx2d-bench.engines/1), knobs included");
  engines->callback([options] { list_engines(*options); });
}

}  // namespace fxbench

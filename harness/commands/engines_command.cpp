// `fx2d-bench engines`: the engines the harness can run, in registry order, with their library
// versions and the solver settings each reads from a scene (and, in JSON, the file each engine
// loaded as a plugin came from).
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands/commands.h"
#include "engines/engine.h"
#include "format/text_table.h"

namespace fxbench {
namespace {

void list_engines(bool json) {
  if (json) {
    nlohmann::ordered_json engines = nlohmann::ordered_json::array();
    for (const EngineInfo& engine : engine_registry()) {
      engines.push_back({{"name", engine.name}, {"version", engine.version}, {"settings", engine.settings}});
      if (!engine.plugin_path.empty()) engines.back()["plugin"] = engine.plugin_path;
    }
    std::cout << nlohmann::ordered_json{{"schema", "fx2d-bench.engines/1"}, {"engines", engines}}.dump(2) << '\n';
    return;
  }
  std::vector<std::vector<std::string>> rows;
  for (const EngineInfo& engine : engine_registry()) rows.push_back({engine.name, engine.version, engine.settings});
  std::cout << aligned_columns(rows);
}

}  // namespace

void register_engines(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* engines = app.add_subcommand("engines", "List the engines with their versions and settings");
  engines->add_flag("--json", *json, "Print one JSON object (fx2d-bench.engines/1)");
  engines->callback([json] { list_engines(*json); });
}

}  // namespace fxbench

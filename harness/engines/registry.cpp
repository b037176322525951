// The table of engines the harness can run, in the fixed order every report lists them.
//
// Invariant: this is the only place that names an engine; the CLI, reports and tests reach an
// adapter through find_engine() or by walking engine_registry(). Chipmunk2D is the plugin this
// build makes; other plugins (engines/plugin_engine.h) are not listed: find_engine() loads one
// when its name asks for it.
#include <algorithm>
#include <deque>
#include <filesystem>
#include <mutex>
#include <vector>

#include "common/child_process.h"
#include "common/errors.h"
#include "engines/engines.h"
#include "engines/plugin_engine.h"

namespace fxbench {
namespace {

// A plugin this build makes, by file name: in the engine plugin folder at its place relative to
// the running executable (../lib/fx2d-bench from bin/fx2d-bench under an install prefix, and from
// harness/fx2d-bench in the build tree), else in the build tree's folder, for the build tree's
// other programs (its tests) that sit elsewhere.
std::string built_plugin(const std::string& file) {
  namespace fs = std::filesystem;
  const fs::path beside =
      fs::path(own_executable()).parent_path() / FX2D_BENCH_ENGINE_PLUGINS_FROM_EXECUTABLE / file;
  return fs::exists(beside) ? beside.lexically_normal().string()
                            : (fs::path(FX2D_BENCH_ENGINE_PLUGIN_BUILD_DIR) / file).string();
}

// The entry of a plugin this build makes. One that does not load is listed with why and refused
// only when selected (cli_options.cpp), so that a broken install leaves the other engines working.
EngineInfo built_plugin_engine(const std::string& file, const std::string& name) {
  const std::string path = built_plugin(file);
  try {
    return plugin_engine_info(Plugin::load(path), name);
  } catch (const InputError& error) {
    EngineInfo info;
    info.name = name;
    info.version = "unavailable";
    info.settings = error.what();
    info.plugin_path = path;
    info.unavailable = error.what();
    info.make = [why = info.unavailable]() -> std::unique_ptr<Engine> { throw InputError(why); };
    return info;
  }
}

}  // namespace

std::span<const EngineInfo> engine_registry() {
  static const std::vector<EngineInfo> engines = [] {
    std::vector<EngineInfo> all{fx2d_engine_info()};
    all.push_back(box2d_engine_info());
    all.push_back(ode_engine_info());
    // The plugin this build makes (engines/chipmunk/).
    all.push_back(built_plugin_engine(FX2D_BENCH_CHIPMUNK_PLUGIN_FILE, "chipmunk"));
    return all;
  }();
  return engines;
}

namespace {

// Plugins loaded by name, each once per process; a deque, so that entries never move.
const EngineInfo& loaded_plugin(const std::string& name) {
  static std::mutex mutex;
  static std::deque<std::pair<std::string, EngineInfo>> loaded;
  const std::scoped_lock lock(mutex);
  const auto found = std::ranges::find(loaded, name, &std::pair<std::string, EngineInfo>::first);
  if (found != loaded.end()) return found->second;
  return loaded.emplace_back(name, plugin_engine_info(name)).second;
}

}  // namespace

const EngineInfo* find_engine(const std::string& name) {
  if (is_plugin_engine_name(name)) return &loaded_plugin(name);
  const auto engines = engine_registry();
  const auto found = std::ranges::find(engines, name, &EngineInfo::name);
  return found == engines.end() ? nullptr : &*found;
}

}  // namespace fxbench

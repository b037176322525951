// An Engine over a plugin's function table (plugin/fx2d_plugin_abi.h): the one place where a
// SceneSpec becomes the flat C scene a plugin builds. The built-in "fx2d" engine is this same
// engine over the table linked into the binary, so a plugin built from this tree and the
// built-in engine step every scene to the same state, bit for bit.
//
// Invariants: a plugin library stays loaded while any Plugin handle, EngineInfo or engine made
// from it lives; libraries are opened with RTLD_NOW | RTLD_LOCAL, so two builds of Fx2D loaded
// at once resolve nothing against each other; a table whose abi_version is not
// FX2D_BENCH_PLUGIN_ABI_VERSION is refused before any other member of it is read.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "engines/engine.h"
#include "plugin/fx2d_plugin_abi.h"

namespace fxbench {

// What an Fx2D engine, built in or plugged in, reads from a scene (for `fx2d-bench engines`).
inline constexpr const char* fx2d_settings_description =
    "fx2d.substeps substeps x fx2d.velocity_passes velocity passes, sleeping per fx2d.sleeping";

// What an Fx2D engine, built in or plugged in, can build: any shape and joint, bodies no faster
// than FxSceneSettings::max_linear_speed (checked against the built-in engine in engines/fx2d.cpp).
inline constexpr double fx2d_max_linear_speed = 400.0;  // m/s
inline const EngineCapabilities fx2d_capabilities{.max_linear_speed = fx2d_max_linear_speed};

// One plugin's function table and the library that holds it (none for a linked-in table).
class Plugin {
 public:
  // Loads the shared library at `path` (made absolute) and checks its entry point and ABI
  // version. Throws InputError, one line naming the path: not found, not loadable, no entry
  // point, another ABI version.
  static std::shared_ptr<const Plugin> load(const std::string& path);
  // The table linked into this binary.
  static std::shared_ptr<const Plugin> linked(const Fx2dBenchPluginV1& table);

  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;
  ~Plugin();

  const Fx2dBenchPluginV1& table() const { return *table_; }
  const std::string& path() const { return path_; }  // absolute; empty for a linked-in table
  // The engine library's version, then the build description when the plugin gives one.
  std::string version() const;

 private:
  Plugin(void* library, const Fx2dBenchPluginV1* table, std::string path)
      : library_(library), table_(table), path_(std::move(path)) {}

  void* library_;
  const Fx2dBenchPluginV1* table_;
  std::string path_;
};

// An engine over `plugin`'s table; reads the scene's fx2d settings.
std::unique_ptr<Engine> make_plugin_engine(std::shared_ptr<const Plugin> plugin);

// The registry entry of a loaded plugin, named `name`; its make() keeps the library loaded.
EngineInfo plugin_engine_info(std::shared_ptr<const Plugin> plugin, std::string name);

// Engine names that select a plugin: "plugin:PATH" or "plugin:PATH|LABEL".
inline constexpr std::string_view plugin_name_prefix = "plugin:";
bool is_plugin_engine_name(std::string_view name);
// Loads the plugin an engine name selects; the entry is named LABEL, or the whole name.
// Throws InputError.
EngineInfo plugin_engine_info(const std::string& engine_name);

}  // namespace fxbench

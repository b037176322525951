// An Engine over a plugin's function table (plugin/fx2d_plugin_abi.h): the one place where a
// SceneSpec becomes the flat C scene a plugin builds, and where a table's knobs and capabilities
// become the harness's. The built-in "fx2d" engine is this same engine over the table linked into
// the binary, so a plugin built from this tree and the built-in engine step every scene to the
// same state, bit for bit; Chipmunk2D is this engine over the plugin the build makes.
//
// Invariants: a plugin library stays loaded while any Plugin handle, EngineInfo or engine made
// from it lives; libraries are opened with RTLD_NOW | RTLD_LOCAL, so two builds of one engine
// loaded at once resolve nothing against each other; a table whose abi_version is not
// FX2D_BENCH_PLUGIN_ABI_VERSION is refused before any other member of it is read, and one whose
// name or knobs are malformed is refused before it is used.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "engines/engine.h"
#include "plugin/fx2d_plugin_abi.h"

namespace fxbench {

// One plugin's function table and the library that holds it (none for a linked-in table).
class Plugin {
 public:
  // Loads the shared library at `path` (made absolute) and checks its entry point, ABI version,
  // name and knobs. Throws InputError, one line naming the path: not found, not loadable, no
  // entry point, another ABI version, a malformed name or knob.
  static std::shared_ptr<const Plugin> load(const std::string& path);
  // The table linked into this binary.
  static std::shared_ptr<const Plugin> linked(const Fx2dBenchPlugin& table);

  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;
  ~Plugin();

  const Fx2dBenchPlugin& table() const { return *table_; }
  const std::string& path() const { return path_; }  // absolute; empty for a linked-in table
  // The engine's name, also its /solver block (Fx2dBenchPlugin::name).
  std::string name() const { return table_->name; }
  // The engine library's version, then the build description when the plugin gives one.
  std::string version() const;
  const std::vector<Knob>& knobs() const { return knobs_; }
  EngineCapabilities capabilities() const;

 private:
  Plugin(void* library, const Fx2dBenchPlugin* table, std::string path);

  void* library_;
  const Fx2dBenchPlugin* table_;
  std::string path_;
  std::vector<Knob> knobs_;
};

// Fx2D's table linked into this binary (plugin/fx2d_plugin.cpp): the built-in "fx2d" engine's
// plugin, which `ab --a built-in` times against a plugin file of the same build.
std::shared_ptr<const Plugin> linked_fx2d_plugin();

// An engine over `plugin`'s table; reads the scene's /solver/<plugin name> knobs.
std::unique_ptr<Engine> make_plugin_engine(std::shared_ptr<const Plugin> plugin);

// The instance `engine` has built, when it is an engine over `plugin`'s table (so that the caller,
// which linked that table in, knows the World inside it); nullptr for another engine or one not
// built yet. For a diagnostic of a linked-in adapter (engines.h, ode_out_of_plane_drift).
const Fx2dBenchInstance* built_instance(const Engine& engine, const Plugin& plugin);

// The registry entry of a loaded plugin, named `name`; its make() keeps the library loaded.
EngineInfo plugin_engine_info(std::shared_ptr<const Plugin> plugin, std::string name);

// Engine names that select a plugin: "plugin:PATH" or "plugin:PATH|LABEL".
inline constexpr std::string_view plugin_name_prefix = "plugin:";
bool is_plugin_engine_name(std::string_view name);
// Loads the plugin an engine name selects; the entry is named LABEL, or the whole name.
// Throws InputError.
EngineInfo plugin_engine_info(const std::string& engine_name);

}  // namespace fxbench

// The built-in Fx2D engine: the plugin engine (plugin_engine.h) over the plugin table linked into
// this binary (plugin/fx2d_plugin.cpp), so the built-in engine and a plugin built from the same
// tree share every line of scene conversion, knobs and capabilities, and step the same
// trajectories.
#include "engines/engines.h"
#include "engines/plugin_engine.h"

namespace fxbench {

std::shared_ptr<const Plugin> linked_fx2d_plugin() {
  static const std::shared_ptr<const Plugin> linked = Plugin::linked(*fx2d_bench_plugin_table());
  return linked;
}

std::unique_ptr<Engine> make_fx2d_engine() { return make_plugin_engine(linked_fx2d_plugin()); }

EngineInfo fx2d_engine_info() { return plugin_engine_info(linked_fx2d_plugin(), "fx2d"); }

}  // namespace fxbench

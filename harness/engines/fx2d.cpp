// The built-in Fx2D engine: the plugin engine (plugin_engine.h) over the plugin table linked into
// this binary (plugin/fx2d_plugin.cpp), so the built-in engine and a plugin built from the same
// tree share every line of scene conversion and step the same trajectories.
#include <fx2d/Scene.h>

#include "engines/engines.h"
#include "engines/plugin_engine.h"

namespace fxbench {

static_assert(fx2d::FxSceneSettings{}.max_linear_speed == fx2d_max_linear_speed,
              "fx2d_capabilities (plugin_engine.h) declares the speed Fx2D accepts");

std::unique_ptr<Engine> make_fx2d_engine() {
  static const std::shared_ptr<const Plugin> linked = Plugin::linked(*fx2d_bench_plugin_table());
  return make_plugin_engine(linked);
}

}  // namespace fxbench

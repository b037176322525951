// The table of engines the harness can run, in the fixed order every report lists them.
//
// Invariant: this is the only place that names an engine; the CLI, reports and tests reach an
// adapter through find_engine() or by walking engine_registry(). Plugins (engines/plugin_engine.h)
// are not listed: find_engine() loads one when its name asks for it.
#include <algorithm>
#include <deque>
#include <mutex>

#include "engines/engines.h"
#include "engines/plugin_engine.h"
#include "fx2d/Version.h"

namespace fxbench {

std::span<const EngineInfo> engine_registry() {
  static const EngineInfo engines[] = {
      {"fx2d", std::string(fx2d::fx_version()), fx2d_settings_description, &make_fx2d_engine, "fx2d", fx2d_capabilities},
      {"box2d", FX2D_BENCH_BOX2D_VERSION,
       "b2World::Step with box2d.velocity_iterations and box2d.position_iterations, sleeping per box2d.sleeping; "
       "one friction (the dynamic one)",
       &make_box2d_engine, "box2d", EngineCapabilities{}},
      {"ode", FX2D_BENCH_ODE_VERSION,
       "dWorldQuickStep with ode.iterations, ode.erp, ode.cfm, auto-disable per ode.auto_disable; plane-2D joints, "
       "1 m deep boxes, circles as spheres, friction pyramid",
       &make_ode_engine, "ode", ode_capabilities},
  };
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

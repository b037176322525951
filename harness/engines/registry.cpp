// The table of engines the harness can run, in the fixed order every report lists them.
//
// Invariant: this is the only place that names an engine; the CLI, reports and tests reach an
// adapter through find_engine() or by walking engine_registry().
#include <algorithm>

#include "engines/engines.h"
#include "fx2d/Version.h"

namespace fxbench {

std::span<const EngineInfo> engine_registry() {
  static const EngineInfo engines[] = {
      {"fx2d", std::string(fx2d::fx_version()), "fx2d.substeps substeps x fx2d.velocity_passes velocity passes, sleeping per fx2d.sleeping",
       &make_fx2d_engine},
      {"box2d", FX2D_BENCH_BOX2D_VERSION,
       "b2World::Step with box2d.velocity_iterations and box2d.position_iterations, sleeping per box2d.sleeping; "
       "one friction (the dynamic one)",
       &make_box2d_engine},
      {"ode", FX2D_BENCH_ODE_VERSION,
       "dWorldQuickStep with ode.iterations, ode.erp, ode.cfm, auto-disable per ode.auto_disable; plane-2D joints, "
       "1 m deep boxes, circles as spheres, friction pyramid",
       &make_ode_engine},
  };
  return engines;
}

const EngineInfo* find_engine(const std::string& name) {
  const auto engines = engine_registry();
  const auto found = std::ranges::find(engines, name, &EngineInfo::name);
  return found == engines.end() ? nullptr : &*found;
}

}  // namespace fxbench

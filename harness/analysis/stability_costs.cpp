// The measured cost table of stability_costs.h: user CPU seconds (not wall time, which the other
// jobs of a shared machine inflate unevenly) of, per test T and engine E of the suite at its
// defaults, one `/usr/bin/time -f %U fx2d-bench stability --test T --engine E` of a Release build,
// the pairs one after another (measured 2026-11-26 on the 2-core development machine at load
// average 1.8 to 2.4; the table before, at load 8 to 14, had pyramid on ODE at 99 of 112 s: user
// time grows with the machine's load, ODE's large pyramids most). time's 0.01 s resolution is the
// floor.
// Remeasure when a test or an engine changes much; only the proportions matter, and a stale table
// costs balance, never correctness. Pyramid on ODE is 29.5 of the suite's 38.7 s: no split of
// whole pairs can bring the largest part under 0.76 of the suite, so `--shard` spreads that
// search's probes over several shards (stability_pieces.h).
#include "analysis/stability_costs.h"

#include <algorithm>
#include <string_view>

namespace fxbench {
namespace {

struct PairCost {
  std::string_view test;
  std::string_view engine;
  double seconds;
};

constexpr PairCost measured[] = {
    {"card_house", "fx2d", 0.01},
    {"card_house", "box2d", 0.01},
    {"card_house", "ode", 0.03},
    {"card_house", "chipmunk", 0.01},
    {"chain_load", "fx2d", 0.04},
    {"chain_load", "box2d", 0.01},
    {"chain_load", "ode", 0.03},
    {"chain_load", "chipmunk", 0.01},
    {"far_start", "fx2d", 0.01},
    {"far_start", "box2d", 0.01},
    {"far_start", "ode", 0.01},
    {"far_start", "chipmunk", 0.01},
    {"friction_ramp", "fx2d", 0.01},
    {"friction_ramp", "box2d", 0.01},
    {"friction_ramp", "ode", 0.01},
    {"friction_ramp", "chipmunk", 0.01},
    {"mass_ratio", "fx2d", 0.01},
    {"mass_ratio", "box2d", 0.01},
    {"mass_ratio", "ode", 0.03},
    {"mass_ratio", "chipmunk", 0.01},
    {"overlap_recovery", "fx2d", 0.02},
    {"overlap_recovery", "box2d", 0.08},
    {"overlap_recovery", "ode", 0.14},
    {"overlap_recovery", "chipmunk", 0.01},
    {"pyramid", "fx2d", 0.90},
    {"pyramid", "box2d", 4.57},
    {"pyramid", "ode", 29.52},
    {"pyramid", "chipmunk", 2.65},
    {"spinning_plank", "fx2d", 0.01},
    {"spinning_plank", "box2d", 0.01},
    {"spinning_plank", "ode", 0.01},
    {"spinning_plank", "chipmunk", 0.01},
    {"thin_floor", "fx2d", 0.01},
    {"thin_floor", "box2d", 0.01},
    {"thin_floor", "ode", 0.01},
    {"thin_floor", "chipmunk", 0.01},
    {"thin_wall", "fx2d", 0.01},
    {"thin_wall", "box2d", 0.01},
    {"thin_wall", "ode", 0.01},
    {"thin_wall", "chipmunk", 0.01},
    {"vertical_stack", "fx2d", 0.06},
    {"vertical_stack", "box2d", 0.07},
    {"vertical_stack", "ode", 0.28},
    {"vertical_stack", "chipmunk", 0.01},
};

constexpr double unmeasured_seconds = 1.0;

const PairCost* measured_pair(const std::string& test, const std::string& engine) {
  const auto found = std::ranges::find_if(measured, [&](const PairCost& pair) { return pair.test == test && pair.engine == engine; });
  return found == std::end(measured) ? nullptr : found;
}

}  // namespace

double stability_cost(const std::string& test, const std::string& engine) {
  const PairCost* pair = measured_pair(test, engine);
  return pair == nullptr ? unmeasured_seconds : pair->seconds;
}

bool stability_cost_measured(const std::string& test, const std::string& engine) {
  return measured_pair(test, engine) != nullptr;
}

}  // namespace fxbench

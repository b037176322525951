// The measured cost table of stability_costs.h. Remeasure with, per test T and engine E,
// `time fx2d-bench stability --test T --engine E` when a test or an engine changes much; only the
// proportions matter, and a stale table costs balance, never correctness.
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
    {"card_house", "fx2d", 0.047},
    {"card_house", "box2d", 0.042},
    {"card_house", "ode", 0.063},
    {"chain_load", "fx2d", 0.109},
    {"chain_load", "box2d", 0.038},
    {"chain_load", "ode", 0.076},
    {"friction_ramp", "fx2d", 0.023},
    {"friction_ramp", "box2d", 0.021},
    {"friction_ramp", "ode", 0.048},
    {"mass_ratio", "fx2d", 0.040},
    {"mass_ratio", "box2d", 0.042},
    {"mass_ratio", "ode", 0.074},
    {"overlap_recovery", "fx2d", 0.055},
    {"overlap_recovery", "box2d", 0.209},
    {"overlap_recovery", "ode", 0.377},
    {"pyramid", "fx2d", 0.309},
    {"pyramid", "box2d", 2.832},
    {"pyramid", "ode", 38.176},
    {"thin_wall", "fx2d", 0.050},
    {"thin_wall", "box2d", 0.046},
    {"thin_wall", "ode", 0.041},
    {"vertical_stack", "fx2d", 0.410},
    {"vertical_stack", "box2d", 0.200},
    {"vertical_stack", "ode", 0.893},
};

constexpr double unmeasured_seconds = 1.0;

}  // namespace

double stability_cost(const std::string& test, const std::string& engine) {
  const auto found = std::ranges::find_if(measured, [&](const PairCost& pair) { return pair.test == test && pair.engine == engine; });
  return found == std::end(measured) ? unmeasured_seconds : found->seconds;
}

}  // namespace fxbench

// The measured cost table of stability_costs.h: user CPU seconds (not wall time, which the other
// jobs of a shared machine inflate unevenly) of, per test T and engine E of the suite at its
// defaults, one `/usr/bin/time -f %U fx2d-bench stability --test T --engine E` of a Release build,
// the pairs one after another (measured 2026-11-26 on the 2-core development machine at load
// average 1.8 to 2.4; the table before, at load 8 to 14, had pyramid on ODE at 99 of 112 s: user
// time grows with the machine's load, ODE's large pyramids most). time's 0.01 s resolution is the
// floor. Each pair's last pass is the boundary its unsharded search found (`fx2d-bench stability
// --engine all --json`, the same build, 2026-11-26; Fx2D's vertical_stack and mass_ratio again
// with the rest schedule, 2026-11-27; mass_ratio again at max_push_speed 3.5; vertical_stack again
// at one soft pass, 2026-11-28), what a spread search predicts.
// Remeasure when a test or an engine changes much; only the proportions matter, and a stale table
// costs balance, never correctness. Pyramid on ODE is 29.5 of the suite's 38.7 s: no split of
// whole pairs can bring the largest part under 0.76 of the suite, so `--shard` spreads that
// search's probes over several shards (stability_pieces.h).
#include "analysis/stability_costs.h"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace fxbench {
namespace {

struct PairCost {
  std::string_view test;
  std::string_view engine;
  double seconds;
  std::optional<double> last_pass;  // none: the search failed at its start
};

constexpr PairCost measured_pairs[] = {
    {"card_house", "fx2d", 0.01, 0.2421875},
    {"card_house", "box2d", 0.01, 0.453125},
    {"card_house", "ode", 0.03, 0.75},
    {"card_house", "chipmunk", 0.01, 0.25},
    {"chain_load", "fx2d", 0.04, 939.0121402415833},
    {"chain_load", "box2d", 0.01, 98.70149282610822},
    {"chain_load", "ode", 0.03, 22.627416997969522},
    {"chain_load", "chipmunk", 0.01, 34.896247445288246},
    {"far_start", "fx2d", 0.01, 1000.0},
    {"far_start", "box2d", 0.01, 1000.0},
    {"far_start", "ode", 0.01, 109.05077326652577},
    {"far_start", "chipmunk", 0.01, 109.05077326652577},
    {"friction_ramp", "fx2d", 0.01, 75.0},
    {"friction_ramp", "box2d", 0.01, 75.0},
    {"friction_ramp", "ode", 0.01, 75.0},
    {"friction_ramp", "chipmunk", 0.01, std::nullopt},
    {"mass_ratio", "fx2d", 0.01, 1217.7480857627863},
    {"mass_ratio", "box2d", 0.01, 394.8059713044329},
    {"mass_ratio", "ode", 0.03, 90.50966799187809},
    {"mass_ratio", "chipmunk", 0.01, 197.40298565221644},
    {"overlap_recovery", "fx2d", 0.02, 0.5},
    {"overlap_recovery", "box2d", 0.08, 0.3875},
    {"overlap_recovery", "ode", 0.14, 0.03},
    {"overlap_recovery", "chipmunk", 0.01, 0.02},
    {"pyramid", "fx2d", 0.90, 128.0},
    {"pyramid", "box2d", 4.57, 55.0},
    {"pyramid", "ode", 29.52, 55.0},
    {"pyramid", "chipmunk", 2.65, 47.0},
    {"spinning_plank", "fx2d", 0.01, 1000.0},
    {"spinning_plank", "box2d", 0.01, 1000.0},
    {"spinning_plank", "ode", 0.01, 56.93943173783459},
    {"spinning_plank", "chipmunk", 0.01, 70.71067811865476},
    {"thin_floor", "fx2d", 0.01, 1000.0},
    {"thin_floor", "box2d", 0.01, 1000.0},
    {"thin_floor", "ode", 0.01, std::nullopt},
    {"thin_floor", "chipmunk", 0.01, std::nullopt},
    {"thin_wall", "fx2d", 0.01, 1000.0},
    {"thin_wall", "box2d", 0.01, 1000.0},
    {"thin_wall", "ode", 0.01, 6.771277734684464},
    {"thin_wall", "chipmunk", 0.01, 6.771277734684464},
    {"vertical_stack", "fx2d", 0.06, 125.0},
    {"vertical_stack", "box2d", 0.07, 31.0},
    {"vertical_stack", "ode", 0.28, 16.0},
    {"vertical_stack", "chipmunk", 0.01, 13.0},
};

constexpr double unmeasured_seconds = 1.0;

// How a probe's cost grows with its bodies, per engine: cost ~ bodies^power. Fitted to the user
// CPU time of pyramid's probes, each whole (fx2d-bench stability --test pyramid --engine E, one
// probe timed at a time; 2026-11-26, load 3 to 5), from base 32 (528 bodies) to 55 (1540), and
// for Fx2D, which holds to 128, to 8256 bodies: ODE's time per step grows faster than its bodies
// (1.4), Box2D's a little (1.1), Chipmunk2D's as they do, Fx2D's by 1.3. An engine not listed
// is taken as linear.
struct BodyPower {
  std::string_view engine;
  double power;
};

constexpr BodyPower body_powers[] = {{"fx2d", 1.3}, {"box2d", 1.1}, {"ode", 1.4}, {"chipmunk", 1.0}};

// A failure that settles stops early: pyramid's failures on ODE and Box2D settle at step 30 of
// 300 and cost 0.07 to 0.15 of a pass of the same size.
constexpr double early_stop_share = 0.1;

const PairCost* measured_pair(const std::string& test, const std::string& engine) {
  const auto found = std::ranges::find_if(measured_pairs, [&](const PairCost& pair) { return pair.test == test && pair.engine == engine; });
  return found == std::end(measured_pairs) ? nullptr : found;
}

}  // namespace

double stability_cost(const std::string& test, const std::string& engine) {
  const PairCost* pair = measured_pair(test, engine);
  return pair == nullptr ? unmeasured_seconds : pair->seconds;
}

std::optional<double> stability_last_pass(const std::string& test, const std::string& engine) {
  const PairCost* pair = measured_pair(test, engine);
  return pair == nullptr ? std::nullopt : pair->last_pass;
}

double stability_probe_cost(const SceneSpec& scene, const std::string& engine, bool stops_early) {
  const auto found = std::ranges::find_if(body_powers, [&](const BodyPower& body) { return body.engine == engine; });
  const double power = found == std::end(body_powers) ? 1.0 : found->power;
  return std::pow(static_cast<double>(scene.bodies.size()), power) * scene.steps * (stops_early ? early_stop_share : 1.0);
}

bool stability_cost_measured(const std::string& test, const std::string& engine) {
  return measured_pair(test, engine) != nullptr;
}

}  // namespace fxbench

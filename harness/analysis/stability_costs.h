// What each stability test x engine pair costs to search, measured, so that `stability --shard`
// balances its parts by time rather than by count: one pair (pyramid on ODE) takes most of the
// suite, and a split by count would put it beside half of the rest.
#pragma once

#include <optional>
#include <string>

#include "scene/scene_spec.h"

namespace fxbench {

// User CPU seconds the full search of `test` on `engine` took (`fx2d-bench stability --test T
// --engine E`, process included, Release build; the method is in stability_costs.cpp). A pair
// missing from the table (a new test, a plugin engine) costs 1 s.
double stability_cost(const std::string& test, const std::string& engine);

// The last pass the full search of `test` on `engine` found when the table was measured: what
// a search spread over shards predicts (stability_pieces.h). None when it failed at its start or
// the pair is not in the table.
std::optional<double> stability_last_pass(const std::string& test, const std::string& engine);

// What simulating `scene` on `engine` costs, in units comparable only within one engine: bodies
// to the engine's measured power, times steps, a tenth of that when the run `stops_early` (a
// failure that settles). How a spread search deals its probes.
double stability_probe_cost(const SceneSpec& scene, const std::string& engine, bool stops_early);

// Whether the table holds a measurement of the pair (shard_test checks that it does for every
// test of the suite on every engine of the registry).
bool stability_cost_measured(const std::string& test, const std::string& engine);

}  // namespace fxbench

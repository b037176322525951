// A sweep's grid and its measured points: the knob axes of each engine, the grid they span, the
// figures of a measured point (cost and error), the whole plan's work items for --shard, and the
// Pareto fronts over the points. `fx2d-bench sweep` (commands/sweep.cpp) measures the points;
// format/sweep_format.h prints and stores them.
//
// Invariants: a point's cost is its median ms per step over dt (ms per simulated second), so points
// with different time steps compare like for like; its error is the scene's primary metric, the
// worst over the sampled steps, and +infinity when any body went NaN.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/results.h"
#include "common/shard.h"
#include "scene/scene_spec.h"
#include "stats/pareto.h"
#include "stats/statistics.h"

namespace fxbench {

// One accuracy knob: an integer under /solver/<engine>/<key> of the scene format. An axis with no
// values is not swept: its knob keeps the scene's own value and is left out of every point.
struct KnobAxis {
  std::string engine;
  std::string key;
  std::string flag;
  int min_value = 1;  // the knob's lower bound in the scene format
  std::vector<int> values;
  std::optional<int> when_unset;  // an optional key's value when the scene leaves it out
};

using Knobs = std::vector<std::pair<std::string, int>>;  // (key, value), in axis order

struct GridPoint {
  Knobs knobs;
  double dt = 0.0;
  bool is_default = false;
};

struct PointResult {
  std::string scene;
  std::string engine;
  GridPoint grid;
  std::size_t run = 0;       // index into ResultSet::runs
  PrimaryMetric metric = PrimaryMetric::penetration;
  double ms_median = 0.0;    // median over repeats of each repeat's mean ms per step
  Interval ms_interval;      // its percentile bootstrap interval
  double cost = 0.0;         // ms per simulated second
  double error = 0.0;        // the primary metric, worst over the sampled steps; +inf after a NaN
  AccuracySample worst;
  int pareto_group = 0;      // one per scene x engine of the whole plan, so shards agree
  std::size_t work_item = 0; // the point's index in the whole plan
  // Its cost over the cost of its scene and engine's default point, round by round (compare_with_defaults);
  // empty when the default was not measured in the same rounds.
  std::optional<RatioEstimate> vs_default;
};

// The whole plan's points in order, each with its measuring cost and its key: what --shard splits
// and what the file records, so that merge can tell two shards of one sweep from two sweeps.
struct WorkItem {
  std::size_t scene = 0;
  std::size_t grid = 0;
  std::size_t point = 0;
  int pareto_group = 0;
};

struct WorkList {
  std::vector<WorkItem> items;
  std::vector<double> costs;  // bodies x steps: what a point's measurement grows with
  std::string identity;       // work_list_identity of every item's key
};

struct Sweep {
  ResultSet results;
  std::vector<PointResult> points;
  FrontMarks marks;  // over this shard's points only; merge recomputes them over all
  Shard shard;
  WorkList work;
};

std::string metric_name(PrimaryMetric metric);

// Whether `axis` is swept for `engine`: its engine's, with values to try.
bool swept_on(const KnobAxis& axis, const std::string& engine);

// The scene's own value of each swept knob of `engine`: what the resolved scene holds under
// /solver, or the engine's default for an optional key the scene leaves out.
Knobs default_knobs(const SceneSpec& scene, const std::vector<KnobAxis>& axes, const std::string& engine);

// Every combination of the engine's axes, first axis slowest, then the default when missing; the
// whole once per time step; then the scene's own point when no time step asked is the scene's.
std::vector<GridPoint> grid_of(const std::vector<KnobAxis>& axes, const std::string& engine, const Knobs& defaults,
                               const std::vector<double>& dts, double scene_dt);

// "key=value key=value", in axis order.
std::string knobs_text(const Knobs& knobs);

// A --dt point keeps the scene's duration: its step count scaled by the ratio of time steps.
int steps_at(const SceneSpec& base, double dt);

// The figures of one measured point: `run` is the run at `run_index` of the result set.
PointResult figures_of(const RunRecord& run, std::size_t run_index, const SceneSpec& scene, const GridPoint& point);

// Marks each point on or off its scene x engine front (pareto_group).
void place_on_fronts(Sweep& sweep);

// Sets each point's vs_default: the paired median over the rounds k of cost_k(point) / cost_k(default),
// with its bootstrap interval (bootstrap_paired_median_ratio), where cost_k is round k's mean ms per
// step over dt and the default is the point of the same front marked is_default. The points of one
// front take their rounds in turn (interleave.h), so round k of each ran in the same pass over them
// and the machine's drift cancels in the ratio, as it does in `ab`. A point whose default is not
// among the sweep's points (another shard measured it), or ran another number of rounds, gets none.
void compare_with_defaults(Sweep& sweep);

}  // namespace fxbench

// A sweep's grid and its points' figures: see sweep_grid.h.
#include "analysis/sweep_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "analysis/summary.h"

namespace fxbench {

std::string metric_name(PrimaryMetric metric) {
  return metric == PrimaryMetric::displacement ? "displacement" : "penetration";
}

bool swept_on(const KnobAxis& axis, const std::string& engine) { return axis.engine == engine && !axis.values.empty(); }

// The scene's own value of each swept knob of `engine`: what the resolved scene holds under
// /solver, or the engine's default for an optional key the scene leaves out.
Knobs default_knobs(const SceneSpec& scene, const std::vector<KnobAxis>& axes, const std::string& engine) {
  // A plugin's block is absent from a scene that sets none of its knobs.
  const auto settings =
      nlohmann::json::parse(scene.resolved_json).at("solver").value(engine, nlohmann::json::object());
  Knobs knobs;
  for (const KnobAxis& axis : axes) {
    if (!swept_on(axis, engine)) continue;
    knobs.emplace_back(axis.key, settings.contains(axis.key) ? settings.at(axis.key).get<int>() : axis.when_unset.value());
  }
  return knobs;
}

// Every combination of the engine's axes, first axis slowest, then the default when missing; the
// whole once per time step; then the scene's own point when no time step asked is the scene's.
std::vector<GridPoint> grid_of(const std::vector<KnobAxis>& axes, const std::string& engine, const Knobs& defaults,
                               const std::vector<double>& dts, double scene_dt) {
  std::vector<Knobs> combinations{{}};
  for (const KnobAxis& axis : axes) {
    if (!swept_on(axis, engine)) continue;
    std::vector<Knobs> extended;
    for (const Knobs& partial : combinations)
      for (int value : axis.values) {
        Knobs knobs = partial;
        knobs.emplace_back(axis.key, value);
        extended.push_back(std::move(knobs));
      }
    combinations = std::move(extended);
  }
  if (std::ranges::find(combinations, defaults) == combinations.end()) combinations.push_back(defaults);
  std::vector<GridPoint> grid;
  for (double dt : dts.empty() ? std::vector<double>{scene_dt} : dts)
    for (const Knobs& knobs : combinations) grid.push_back({knobs, dt, knobs == defaults && dt == scene_dt});
  if (std::ranges::none_of(grid, &GridPoint::is_default)) grid.push_back({defaults, scene_dt, true});
  return grid;
}

std::string knobs_text(const Knobs& knobs) {
  std::string text;
  for (const auto& [key, value] : knobs) text += (text.empty() ? "" : " ") + key + "=" + std::to_string(value);
  return text;
}

// A --dt point keeps the scene's duration: its step count scaled by the ratio of time steps.
int steps_at(const SceneSpec& base, double dt) {
  return dt == base.dt ? base.steps : static_cast<int>(std::max(1L, std::lround(base.steps * base.dt / dt)));
}

PointResult figures_of(const RunRecord& run, std::size_t run_index, const SceneSpec& scene, const GridPoint& point) {
  PointResult result;
  result.scene = scene.name;
  result.engine = run.engine;
  result.grid = point;
  result.run = run_index;
  result.metric = scene.primary_metric;
  const std::vector<double> repeat_means = row_means(run.wall_ms, static_cast<std::size_t>(run.steps));
  // A bootstrap of median(B) / median({1}) is the bootstrap of median(B) itself: the resampled
  // one-element A is always 1.
  const std::vector<double> unit{1.0};
  const RatioEstimate estimate = bootstrap_median_ratio(unit, repeat_means);
  result.ms_median = estimate.ratio;
  result.ms_interval = estimate.ci;
  result.cost = result.ms_median / point.dt;
  result.worst = summarise(run).worst;
  const double metric = scene.primary_metric == PrimaryMetric::displacement ? result.worst.max_displacement
                                                                             : result.worst.max_penetration;
  result.error = result.worst.nan > 0 ? std::numeric_limits<double>::infinity() : metric;
  return result;
}

namespace {

// Each round's mean ms per step over dt: its cost per simulated second, in ms.
std::vector<double> round_costs(const RunRecord& run, double dt) {
  std::vector<double> costs = row_means(run.wall_ms, static_cast<std::size_t>(run.steps));
  for (double& cost : costs) cost /= dt;
  return costs;
}

}  // namespace

void compare_with_defaults(Sweep& sweep) {
  // Each front's default, looked up once rather than searched for from every point.
  std::unordered_map<int, std::size_t> default_of;
  for (std::size_t i = 0; i < sweep.points.size(); ++i) {
    if (sweep.points[i].grid.is_default) default_of.try_emplace(sweep.points[i].pareto_group, i);
  }
  for (PointResult& point : sweep.points) {
    point.vs_default.reset();
    const auto found = default_of.find(point.pareto_group);
    if (found == default_of.end()) continue;
    const PointResult& its_default = sweep.points[found->second];
    const RunRecord& run = sweep.results.runs[point.run];
    const RunRecord& default_run = sweep.results.runs[its_default.run];
    if (run.repeats != default_run.repeats || run.repeats == 0) continue;
    point.vs_default = bootstrap_paired_median_ratio(round_costs(default_run, its_default.grid.dt),
                                                     round_costs(run, point.grid.dt));
  }
}

void place_on_fronts(Sweep& sweep) {
  std::vector<ParetoPoint> pareto;
  for (const PointResult& point : sweep.points) pareto.push_back({point.pareto_group, point.cost, point.error});
  sweep.marks = mark_fronts(pareto);
}

}  // namespace fxbench

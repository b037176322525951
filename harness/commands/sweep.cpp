// `fx2d-bench sweep`: speed against accuracy. For each scene and engine, measures every point of a
// grid over the engine's accuracy knobs (and the time step, where asked), then finds each engine's
// Pareto front (pareto.h) and where the scene's own settings stand on it.
//
// Reads top to bottom: the knob axes and options, the grid of one engine, the measurement of
// every point (a scene reloaded with the point's settings as --set overrides, so each run records
// the exact scene it ran and its settings, then runner.h's measure_engine), the figures of a point,
// the fronts, then the three outputs (table, JSON `fx2d-bench.sweep/1`, HDF5 `/sweep` as in
// harness/RESULTS_FORMAT.md).
//
// Invariants: the scene's own setting of each engine is always measured, and added to the grid
// when the grid lacks it; every point of one scene simulates the same duration (a --dt point
// scales the step count); a point's cost is its median ms per step over dt (ms per simulated
// second), so points with different time steps compare like for like; its error is the scene's
// primary metric, the worst over the sampled steps, and +infinity when any body went NaN.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "analysis/summary.h"
#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "common/number_text.h"
#include "format/summary_format.h"
#include "format/text_table.h"
#include "measure/clocks.h"
#include "measure/provenance.h"
#include "measure/runner.h"
#include "stats/pareto.h"
#include "stats/statistics.h"
#include "storage/h5_tables.h"

namespace fxbench {
namespace {

inline constexpr const char* sweep_schema = "fx2d-bench.sweep/1";

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

struct SweepOptions {
  SceneOptions scenes;
  EngineOptions engines;
  ShardOptions shard;
  // Grids kept small enough that the default sweep of a canonical scene at its middle size takes
  // a few minutes on two cores; see harness/README.md for the measured times.
  std::vector<KnobAxis> axes{
      {"fx2d", "substeps", "--fx2d-substeps", 1, {1, 2, 4, 8, 14, 32}, {}},
      {"fx2d", "velocity_passes", "--fx2d-passes", 0, {1, 2, 4, 8}, {}},
      {"box2d", "velocity_iterations", "--box2d-velocity", 1, {1, 2, 4, 8, 16, 32}, {}},
      {"box2d", "position_iterations", "--box2d-position", 0, {1, 3, 8}, {}},
      {"ode", "iterations", "--ode-iterations", 1, {5, 10, 20, 40, 80}, {}},
      {"fx2d", "relax_passes", "--fx2d-relax", 1, {}, Fx2dSettings::engine_relax_passes},
      {"chipmunk", "iterations", "--chipmunk-iterations", 1, {2, 5, 10, 20, 40}, {}},  // unset: the knob's
                                                                                       // default
  };
  std::vector<std::string> axis_texts;  // --axis ENGINE.KNOB=v1,v2,...: any engine's integer knob
  std::vector<double> dts;  // empty: the scene's own
  int repeats = 3;
  bool json = false;
  std::string out;
  bool force = false;
};

using Knobs = std::vector<std::pair<std::string, int>>;  // (key, value), in axis order

// The largest value a short form's flag takes: far beyond any useful iteration count.
constexpr int max_knob_value = 1000;

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
};

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

// One engine's grid on one scene, and the scene's own value of each of its swept knobs.
struct EngineGrid {
  const EngineInfo* engine;
  Knobs defaults;
  std::vector<GridPoint> points;
};

// A --dt point keeps the scene's duration: its step count scaled by the ratio of time steps.
int steps_at(const SceneSpec& base, double dt) {
  return dt == base.dt ? base.steps : static_cast<int>(std::max(1L, std::lround(base.steps * base.dt / dt)));
}

// The scene as `base_options` loads it, with the point's settings applied after the user's --set.
// Only knobs that differ from the scene's own are set, so the default point is the scene itself,
// hash included, even where the scene leaves an optional knob out.
SceneSpec load_point(const SceneOptions& base_options, const std::string& scene, const SceneSpec& base,
                     const EngineGrid& grid, const GridPoint& point) {
  SceneOptions options = base_options;
  options.scenes = {scene};
  for (std::size_t k = 0; k < point.knobs.size(); ++k) {
    const auto& [key, value] = point.knobs[k];
    if (value != grid.defaults[k].second)
      options.sets.push_back("/solver/" + grid.engine->solver + "/" + key + "=" + std::to_string(value));
  }
  if (point.dt != base.dt) {
    options.sets.push_back("/dt=" + nlohmann::json(point.dt).dump());
    options.sets.push_back("/steps=" + std::to_string(steps_at(base, point.dt)));
  }
  return options.load().front();
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

// Shows "point k of n" on stderr, redrawn in place, only when stderr is a terminal.
void show_progress(std::size_t done, std::size_t total, const std::string& engine, const SceneSpec& scene,
                   const GridPoint& point) {
  if (isatty(STDERR_FILENO) != 1) return;
  std::fprintf(stderr, "\r\x1b[Ksweep %zu/%zu: %s on %s, %s dt=%g", done + 1, total, engine.c_str(), scene.name.c_str(),
               knobs_text(point.knobs).c_str(), point.dt);
  std::fflush(stderr);
}

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

struct PlannedScene {
  std::string argument;
  SceneSpec base;
  std::vector<EngineGrid> grids;
};

std::vector<PlannedScene> plan_sweep(const SweepOptions& options) {
  std::vector<PlannedScene> plan;
  for (const std::string& argument : options.scenes.scenes) {
    SceneOptions one = options.scenes;
    one.scenes = {argument};
    PlannedScene scene{argument, one.load().front(), {}};
    for (const EngineInfo* engine : options.engines.able_to_build(scene.base)) {
      Knobs defaults = default_knobs(scene.base, options.axes, engine->solver);
      std::vector<GridPoint> points = grid_of(options.axes, engine->solver, defaults, options.dts, scene.base.dt);
      scene.grids.push_back({engine, std::move(defaults), std::move(points)});
    }
    plan.push_back(std::move(scene));
  }
  return plan;
}

WorkList work_list_of(const std::vector<PlannedScene>& plan, int repeats) {
  WorkList work;
  std::vector<std::string> keys{"sweep repeats=" + std::to_string(repeats)};
  int group = 0;
  for (std::size_t s = 0; s < plan.size(); ++s) {
    const PlannedScene& scene = plan[s];
    for (std::size_t g = 0; g < scene.grids.size(); ++g, ++group) {
      const EngineGrid& grid = scene.grids[g];
      for (std::size_t p = 0; p < grid.points.size(); ++p) {
        const GridPoint& point = grid.points[p];
        work.items.push_back({s, g, p, group});
        work.costs.push_back(static_cast<double>(std::max(1, scene.base.size)) * steps_at(scene.base, point.dt));
        keys.push_back(scene.base.hash + " " + grid.engine->name + " " + knobs_text(point.knobs) +
                       formatted(" dt=%.17g", point.dt));
      }
    }
  }
  work.identity = work_list_identity(keys);
  return work;
}

void place_on_fronts(Sweep& sweep) {
  std::vector<ParetoPoint> pareto;
  for (const PointResult& point : sweep.points) pareto.push_back({point.pareto_group, point.cost, point.error});
  sweep.marks = mark_fronts(pareto);
}

Sweep run_sweep(const SweepOptions& options, const std::string& command_line) {
  const std::vector<PlannedScene> plan = plan_sweep(options);
  Sweep sweep;
  sweep.shard = options.shard.shard();
  sweep.work = work_list_of(plan, options.repeats);
  const std::vector<std::size_t> mine = items_of(sweep.shard, sweep.work.costs);
  sweep.results.provenance = collect_provenance(command_line, measure_counter_ghz());
  for (std::size_t item : mine) {
    const WorkItem& work = sweep.work.items[item];
    const PlannedScene& scene = plan[work.scene];
    const EngineGrid& grid = scene.grids[work.grid];
    const GridPoint& point = grid.points[work.point];
    const SceneSpec spec = load_point(options.scenes, scene.argument, scene.base, grid, point);
    show_progress(sweep.points.size(), mine.size(), grid.engine->name, spec, point);
    const RunPlan run_plan{options.repeats, 0, spec.steps, 10};
    sweep.results.runs.push_back(measure_engine(spec, *grid.engine, run_plan));
    sweep.results.scenes.push_back({spec.name, spec.hash, spec.resolved_json, spec.source_path,
                                    metric_name(spec.primary_metric)});
    sweep.points.push_back(figures_of(sweep.results.runs.back(), sweep.results.runs.size() - 1, spec, point));
    sweep.points.back().pareto_group = work.pareto_group;
    sweep.points.back().work_item = item;
  }
  if (isatty(STDERR_FILENO) == 1) std::fputs("\r\x1b[K", stderr);
  place_on_fronts(sweep);
  return sweep;
}

std::string table_of(const Sweep& sweep) {
  std::vector<std::vector<std::string>> rows = {{"scene", "engine", "settings", "dt s", "ms/step [95% CI]",
                                                 "max pen mm", "max disp m", "escaped", "nan", "front", "default"}};
  for (std::size_t i = 0; i < sweep.points.size(); ++i) {
    const PointResult& point = sweep.points[i];
    const std::string primary = " (primary)";
    const bool by_displacement = point.metric == PrimaryMetric::displacement;
    rows.push_back({point.scene, point.engine, knobs_text(point.grid.knobs), formatted("%.5g", point.grid.dt),
                    formatted("%.3f", point.ms_median) + formatted(" [%.3f", point.ms_interval.low) +
                        formatted("-%.3f]", point.ms_interval.high),
                    formatted("%.2f", point.worst.max_penetration * 1e3) + (by_displacement ? "" : primary),
                    formatted("%.3f", point.worst.max_displacement) + (by_displacement ? primary : ""),
                    std::to_string(point.worst.escaped), std::to_string(point.worst.nan),
                    sweep.marks.on_front[i] ? "#" + std::to_string(sweep.marks.front_rank[i] + 1) : "-",
                    point.grid.is_default ? "default" : ""});
  }
  std::string text = aligned_columns(rows);
  for (std::size_t i = 0; i < sweep.points.size(); ++i) {
    const PointResult& point = sweep.points[i];
    if (!point.grid.is_default) continue;
    text += point.scene + ", " + point.engine + " default (" + knobs_text(point.grid.knobs) + "): ";
    if (const auto better = sweep.marks.dominated_by[i]) {
      const PointResult& other = sweep.points[*better];
      text += "off its front; " + knobs_text(other.grid.knobs) + formatted(" dt=%g", other.grid.dt) +
              " is at least as accurate at " + formatted("%.0f%% of its cost\n", 100.0 * other.cost / point.cost);
    } else {
      text += "on its front, #" + std::to_string(sweep.marks.front_rank[i] + 1) + " from the fastest\n";
    }
  }
  return text;
}

nlohmann::ordered_json json_of(const Sweep& sweep) {
  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  nlohmann::ordered_json fronts = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < sweep.points.size(); ++i) {
    const PointResult& point = sweep.points[i];
    const RunRecord& run = sweep.results.runs[point.run];
    nlohmann::ordered_json settings = nlohmann::ordered_json::object();
    for (const auto& [key, value] : point.grid.knobs) settings[key] = value;
    const AccuracySample& worst = point.worst;
    points.push_back({
        {"index", i},
        {"scene", point.scene},
        {"scene_hash", run.scene_hash},
        {"bodies", run.bodies},
        {"engine", point.engine},
        {"settings", settings},
        {"dt", point.grid.dt},
        {"steps", run.steps},
        {"repeats", run.repeats},
        {"ms_per_step", {{"median", point.ms_median}, {"ci_low", point.ms_interval.low}, {"ci_high", point.ms_interval.high}}},
        {"ms_per_simulated_s", point.cost},
        {"primary_metric", metric_name(point.metric)},
        {"primary_error", std::isinf(point.error) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(point.error)},
        {"accuracy", accuracy_json(worst)},
        {"default", point.grid.is_default},
        {"on_front", static_cast<bool>(sweep.marks.on_front[i])},
        {"dominated_by", sweep.marks.dominated_by[i] ? nlohmann::ordered_json(*sweep.marks.dominated_by[i]) : nlohmann::ordered_json(nullptr)},
    });
  }
  for (const std::vector<std::size_t>& front : sweep.marks.fronts) {
    const PointResult& first = sweep.points[front.front()];
    fronts.push_back({{"scene", first.scene}, {"engine", first.engine}, {"points", front}});
  }
  return {{"schema", sweep_schema}, {"points", points}, {"fronts", fronts}};
}

// Named columns of one row per point, from field(point, index).
template <class T, class Field>
H5Column column(const Sweep& sweep, std::string name, std::string units, Field field) {
  std::vector<T> values;
  for (std::size_t i = 0; i < sweep.points.size(); ++i) values.push_back(static_cast<T>(field(sweep.points[i], i)));
  return {std::move(name), std::move(units), std::move(values)};
}

H5Table table_h5(const Sweep& sweep, const SweepOptions& options) {
  const auto run = [&](const PointResult& point) -> const RunRecord& { return sweep.results.runs[point.run]; };
  std::vector<H5Column> columns{
      column<std::string>(sweep, "scene", "", [](const PointResult& p, std::size_t) { return p.scene; }),
      column<std::string>(sweep, "scene_hash", "", [&](const PointResult& p, std::size_t) { return run(p).scene_hash; }),
      column<std::int32_t>(sweep, "bodies", "bodies", [&](const PointResult& p, std::size_t) { return run(p).bodies; }),
      column<std::string>(sweep, "engine", "", [](const PointResult& p, std::size_t) { return p.engine; }),
      column<std::string>(sweep, "settings", "", [&](const PointResult& p, std::size_t) { return run(p).engine_settings; }),
      column<std::int32_t>(sweep, "run", "index", [](const PointResult& p, std::size_t) { return p.run; }),
      column<std::int32_t>(sweep, "work_item", "index", [](const PointResult& p, std::size_t) { return p.work_item; }),
      column<std::int32_t>(sweep, "pareto_group", "index", [](const PointResult& p, std::size_t) { return p.pareto_group; }),
  };
  for (const KnobAxis& axis : options.axes) {
    columns.push_back(column<std::int32_t>(sweep, axis.engine + "_" + axis.key, "count", [&](const PointResult& p, std::size_t) {
      for (const auto& [key, value] : p.grid.knobs)
        if (p.engine == axis.engine && key == axis.key) return value;
      return -1;
    }));
  }
  const auto worst = [](double AccuracySample::*field) {
    return [field](const PointResult& p, std::size_t) { return p.worst.*field; };
  };
  std::vector<H5Column> figures{
      column<double>(sweep, "dt", "s", [](const PointResult& p, std::size_t) { return p.grid.dt; }),
      column<std::int32_t>(sweep, "steps", "step", [&](const PointResult& p, std::size_t) { return run(p).steps; }),
      column<double>(sweep, "ms_per_step", "ms", [](const PointResult& p, std::size_t) { return p.ms_median; }),
      column<double>(sweep, "ms_per_step_ci_low", "ms", [](const PointResult& p, std::size_t) { return p.ms_interval.low; }),
      column<double>(sweep, "ms_per_step_ci_high", "ms", [](const PointResult& p, std::size_t) { return p.ms_interval.high; }),
      column<double>(sweep, "ms_per_simulated_s", "ms/s", [](const PointResult& p, std::size_t) { return p.cost; }),
      column<std::string>(sweep, "primary_metric", "", [](const PointResult& p, std::size_t) { return metric_name(p.metric); }),
      column<double>(sweep, "primary_error", "m", [](const PointResult& p, std::size_t) { return p.error; }),
      column<double>(sweep, "max_penetration", "m", worst(&AccuracySample::max_penetration)),
      column<double>(sweep, "mean_penetration", "m", worst(&AccuracySample::mean_penetration)),
      column<double>(sweep, "max_displacement", "m", worst(&AccuracySample::max_displacement)),
      column<double>(sweep, "max_lateral_drift", "m", worst(&AccuracySample::max_lateral_drift)),
      column<double>(sweep, "final_kinetic_energy", "J", worst(&AccuracySample::kinetic_energy)),
      column<std::int32_t>(sweep, "escaped", "bodies", [](const PointResult& p, std::size_t) { return p.worst.escaped; }),
      column<std::int32_t>(sweep, "nan", "bodies", [](const PointResult& p, std::size_t) { return p.worst.nan; }),
      column<std::uint8_t>(sweep, "is_default", "flag", [](const PointResult& p, std::size_t) { return p.grid.is_default; }),
      column<std::uint8_t>(sweep, "on_front", "flag", [&](const PointResult&, std::size_t i) { return sweep.marks.on_front[i]; }),
      column<std::int32_t>(sweep, "front_rank", "rank", [&](const PointResult&, std::size_t i) { return sweep.marks.front_rank[i]; }),
      column<std::int32_t>(sweep, "dominated_by", "index", [&](const PointResult&, std::size_t i) {
        return sweep.marks.dominated_by[i] ? static_cast<int>(*sweep.marks.dominated_by[i]) : -1;
      }),
  };
  columns.insert(columns.end(), std::make_move_iterator(figures.begin()), std::make_move_iterator(figures.end()));
  return {"/sweep",
          {{"schema", std::string(sweep_schema)},
           {"repeats", static_cast<std::int32_t>(options.repeats)},
           {"interval", std::string("95% percentile bootstrap (2000 resamples) of the median of per-repeat mean ms/step")},
           {"cost", std::string("ms_per_simulated_s = ms_per_step / dt")},
           {"shard", sweep.shard.text()},
           {"work_items", static_cast<std::int32_t>(sweep.work.items.size())},
           {"work_list", sweep.work.identity}},
          std::move(columns)};
}

// The knob `--axis ENGINE.KNOB=...` names, among the selected engines' knobs.
const Knob& axis_knob(const SweepOptions& options, const std::string& text, const std::string& engine,
                      const std::string& key) {
  for (const EngineInfo* selected : options.engines.selected()) {
    if (selected->solver != engine) continue;
    const auto knob = std::ranges::find(selected->knobs, key, &Knob::name);
    if (knob == selected->knobs.end())
      throw InputError("--axis " + text + ": " + engine + " has no knob " + key +
                       " (fx2d-bench engines lists them)");
    if (knob->type != Knob::Type::integer)
      throw InputError("--axis " + text + ": " + key +
                       " is not an integer knob; only integer knobs are swept");
    return *knob;
  }
  throw InputError("--axis " + text + ": no selected engine reads /solver/" + engine);
}

// Each --axis ENGINE.KNOB=v1,v2,...: the values of a short form's axis, or a new axis of a plugin's
// knob; then each axis of a plugin's knob takes the knob's default where a scene leaves it unset.
void add_axes(SweepOptions& options) {
  for (const std::string& text : options.axis_texts) {
    const auto dot = text.find('.');
    const auto equals = text.find('=');
    if (dot == std::string::npos || equals == std::string::npos || dot > equals)
      throw InputError("--axis " + text +
                       ": expected ENGINE.KNOB=v1,v2,... such as chipmunk.iterations=5,10,20");
    const std::string engine = text.substr(0, dot);
    const std::string key = text.substr(dot + 1, equals - dot - 1);
    const auto existing = std::ranges::find_if(
        options.axes, [&](const KnobAxis& axis) { return axis.engine == engine && axis.key == key; });
    // A short form's axis (Box2D's and ODE's included, which declare no knobs) keeps its flag's
    // bounds; any other axis takes its knob's.
    double low = 0.0;
    double high = max_knob_value;
    if (existing != options.axes.end()) {
      low = existing->min_value;
    } else {
      const Knob& knob = axis_knob(options, text, engine, key);
      low = knob.min;
      high = knob.max;
    }
    std::vector<int> values;
    std::stringstream list(text.substr(equals + 1));
    for (std::string item; std::getline(list, item, ',');) {
      int value = 0;
      if (!CLI::detail::lexical_cast(item, value) || value < low || value > high)
        throw InputError("--axis " + text + formatted(": expected integers from %g", low) +
                         formatted(" to %g, got '", high) + item + "'");
      values.push_back(value);
    }
    if (existing != options.axes.end())
      existing->values = std::move(values);
    else
      options.axes.push_back({engine, key, "--axis", static_cast<int>(low), std::move(values), {}});
  }
  for (KnobAxis& axis : options.axes) {
    for (const EngineInfo* engine : options.engines.selected()) {
      const auto knob = std::ranges::find(engine->knobs, axis.key, &Knob::name);
      if (engine->solver == axis.engine && knob != engine->knobs.end() && !axis.when_unset)
        axis.when_unset = static_cast<int>(knob->default_value);
    }
  }
}

void sweep_command(SweepOptions options, const std::string& command_line) {
  if (!options.out.empty() && !options.force && std::filesystem::exists(options.out))
    throw InputError(options.out + ": exists; pass --force to overwrite it");
  add_axes(options);
  const Sweep sweep = run_sweep(options, command_line);
  if (options.json)
    std::cout << json_of(sweep).dump(2) << '\n';
  else
    std::cout << table_of(sweep);
  std::cout.flush();
  if (options.out.empty()) return;
  ResultSet results = sweep.results;
  std::vector<SceneRecord> unique;
  for (SceneRecord& scene : results.scenes)
    if (std::ranges::find(unique, scene.hash, &SceneRecord::hash) == unique.end()) unique.push_back(std::move(scene));
  results.scenes = std::move(unique);
  const H5Table table = table_h5(sweep, options);
  write_results_with_tables_h5(results, std::span(&table, 1), options.out, options.force);
}

}  // namespace

void register_sweep(CLI::App& app, const std::string& command_line) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* sweep = app.add_subcommand("sweep", "Speed against accuracy over each engine's solver settings, with Pareto fronts");
  options->scenes.add_to(*sweep, "pile");
  options->engines.add_to(*sweep);
  options->shard.add_to(*sweep);
  for (KnobAxis& axis : options->axes) {
    const std::string what = axis.engine + " " + axis.key + " values to try, comma-separated";
    CLI::Option* option = sweep->add_option(axis.flag, axis.values, axis.values.empty() ? what + " (default: not swept)" : what)
                              ->delimiter(',')
                              ->allow_extra_args(false)
                              ->check(CLI::Range(axis.min_value, max_knob_value));
    if (!axis.values.empty()) option->capture_default_str();
  }
  sweep
      ->add_option("--axis", options->axis_texts,
                   "Sweep any engine's integer knob, e.g. chipmunk.iterations=5,10,20 (the flags above are "
                   "its short forms)")
      ->allow_extra_args(false);
  sweep->add_option("--dt", options->dts, "Time steps to try, s, comma-separated (default: the scene's)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->check(CLI::Range(1e-6, 1.0));
  sweep->add_option("--repeats", options->repeats, "Timed repeats per point")->check(CLI::Range(1, 1000))->capture_default_str();
  sweep->add_flag("--json", options->json, "Print the points and fronts as one JSON object (fx2d-bench.sweep/1)");
  CLI::Option* out = sweep->add_option("--out", options->out, "Write the runs and the /sweep table to this HDF5 file");
  sweep->add_flag("--force", options->force, "Overwrite the --out file if it exists")->needs(out);
  sweep->callback([options, command_line] { sweep_command(*options, command_line); });
}

}  // namespace fxbench

// `fx2d-bench sweep`: speed against accuracy. For each scene and engine, measures every point of a
// grid over the engine's accuracy knobs (and the time step, where asked), then finds each engine's
// Pareto front (pareto.h) and where the scene's own settings stand on it.
//
// Reads top to bottom: the knob axes and options, the plan (each scene's grid per engine, from
// analysis/sweep_grid.h), the measurement of every point of this shard (a scene reloaded with the
// point's settings as --set overrides, so each run records the exact scene it ran and its
// settings; the points of one front timed in interleaved rounds, interleave.h), the fronts, then
// the outputs (format/sweep_format.h: table, JSON `fx2d-bench.sweep/1`, HDF5 `/sweep` as in
// harness/RESULTS_FORMAT.md).
//
// Invariants: the scene's own setting of each engine is always measured, and added to the grid
// when the grid lacks it; every point of one scene simulates the same duration (a --dt point
// scales the step count).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "analysis/sweep_grid.h"
#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "common/number_text.h"
#include "format/sweep_format.h"
#include "measure/clocks.h"
#include "measure/interleave.h"
#include "measure/provenance.h"
#include "measure/runner.h"
#include "storage/h5_tables.h"

namespace fxbench {
namespace {

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
      {"fx2d", "relax_passes", "--fx2d-relax", 1, {}, {}},  // unset: the knob's default
      {"chipmunk", "iterations", "--chipmunk-iterations", 1, {2, 5, 10, 20, 40}, {}},  // unset: the knob's
                                                                                       // default
  };
  std::vector<std::string> axis_texts;  // --axis ENGINE.KNOB=v1,v2,...: any engine's integer knob
  std::vector<bool> named;  // per axis: given on the command line (its short form's flag or --axis)
  std::vector<double> dts;  // empty: the scene's own
  int repeats = 3;
  bool json = false;
  std::string out;
  bool force = false;
};

// The largest value a short form's flag takes: far beyond any useful iteration count.
constexpr int max_knob_value = 1000;

// One engine's grid on one scene, and the scene's own value of each of its swept knobs.
struct EngineGrid {
  const EngineInfo* engine;
  Knobs defaults;
  std::vector<GridPoint> points;
};

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

// Shows "point k of n, repeat r of m" on stderr, redrawn in place, only when stderr is a terminal.
void show_progress(std::size_t point_index, std::size_t total, int round, int repeats,
                   const std::string& engine, const SceneSpec& scene, const GridPoint& point) {
  if (isatty(STDERR_FILENO) != 1) return;
  std::fprintf(stderr, "\r\x1b[Ksweep %zu/%zu (repeat %d/%d): %s on %s, %s dt=%g", point_index + 1, total,
               round + 1, repeats, engine.c_str(), scene.name.c_str(), knobs_text(point.knobs).c_str(),
               point.dt);
  std::fflush(stderr);
}

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
        work.costs.push_back(static_cast<double>(std::max(1, bodies_of(scene.base))) * steps_at(scene.base, point.dt));
        keys.push_back(scene.base.hash + " " + grid.engine->name + " " + knobs_text(point.knobs) +
                       formatted(" dt=%.17g", point.dt));
      }
    }
  }
  work.identity = work_list_identity(keys);
  return work;
}

// The points of one engine's grid on one scene that this shard measures: mine[first, last).
struct PointGroup {
  std::size_t first, last;
};

const EngineGrid& grid_of_item(const std::vector<PlannedScene>& plan, const WorkItem& work) {
  return plan[work.scene].grids[work.grid];
}

const GridPoint& point_of_item(const std::vector<PlannedScene>& plan, const WorkItem& work) {
  return grid_of_item(plan, work).points[work.point];
}

std::vector<PointGroup> groups_of(const WorkList& work, const std::vector<std::size_t>& mine) {
  std::vector<PointGroup> groups;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    if (groups.empty() ||
        work.items[mine[i]].pareto_group != work.items[mine[groups.back().first]].pareto_group)
      groups.push_back({i, i});
    groups.back().last = i + 1;
  }
  return groups;
}

Sweep run_sweep(const SweepOptions& options, const std::string& command_line) {
  const std::vector<PlannedScene> plan = plan_sweep(options);
  Sweep sweep;
  sweep.shard = options.shard.shard();
  sweep.work = work_list_of(plan, options.repeats);
  const std::vector<std::size_t> mine = items_of(sweep.shard, sweep.work.costs);
  sweep.results.provenance = collect_provenance(command_line, measure_counter_ghz());
  // The points of a front are compared with each other, so they take their repeats in rounds
  // (interleave.h): a drift of the machine's speed then moves them all alike.
  for (const PointGroup group : groups_of(sweep.work, mine)) {
    std::vector<SceneSpec> specs;
    std::vector<TimedCell> cells;
    specs.reserve(group.last - group.first);  // the cells point into it
    for (std::size_t i = group.first; i < group.last; ++i) {
      const WorkItem& work = sweep.work.items[mine[i]];
      const PlannedScene& scene = plan[work.scene];
      specs.push_back(load_point(options.scenes, scene.argument, scene.base, grid_of_item(plan, work),
                                 point_of_item(plan, work)));
      cells.push_back({&specs.back(), grid_of_item(plan, work).engine});
    }
    const InterleavePlan rounds{options.repeats, 0.0, 0, 0, 10};
    const TurnProgressFn progress = [&](std::size_t cell, int round) {
      show_progress(group.first + cell, mine.size(), round, options.repeats, cells[cell].engine->name,
                    specs[cell], point_of_item(plan, sweep.work.items[mine[group.first + cell]]));
    };
    RoundRobinRuns runs = measure_round_robin(cells, rounds, progress);
    for (std::size_t cell = 0; cell < cells.size(); ++cell) {
      const std::size_t item = mine[group.first + cell];
      const WorkItem& work = sweep.work.items[item];
      const SceneSpec& spec = specs[cell];
      sweep.results.runs.push_back(std::move(runs.runs[cell]));
      sweep.results.scenes.push_back(
          {spec.name, spec.hash, spec.resolved_json, spec.source_path, metric_name(spec.primary_metric)});
      sweep.points.push_back(figures_of(sweep.results.runs.back(), sweep.results.runs.size() - 1, spec,
                                        point_of_item(plan, work)));
      sweep.points.back().pareto_group = work.pareto_group;
      sweep.points.back().work_item = item;
    }
  }
  if (isatty(STDERR_FILENO) == 1) std::fputs("\r\x1b[K", stderr);
  finish_provenance(sweep.results.provenance);
  place_on_fronts(sweep);
  compare_with_defaults(sweep);
  return sweep;
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

// An engine with a knob named on the command line is swept over its named knobs alone; the others
// keep the scene's own values. So `--axis fx2d.workers=1,2,3,4` measures four points, the scaling
// asked for, and not the workers times Fx2D's default grid; with no knob named, the default grids
// make the fronts.
void hold_unnamed_knobs(SweepOptions& options) {
  std::vector<std::string> named_engines;
  for (std::size_t i = 0; i < options.axes.size(); ++i)
    if (options.named[i]) named_engines.push_back(options.axes[i].engine);
  for (std::size_t i = 0; i < options.axes.size(); ++i)
    if (!options.named[i] && std::ranges::find(named_engines, options.axes[i].engine) != named_engines.end())
      options.axes[i].values.clear();
}

// Each --axis ENGINE.KNOB=v1,v2,...: the values of a short form's axis, or a new axis of a plugin's
// knob; then the knobs left out of an engine named there are held (hold_unnamed_knobs), and each
// axis of a plugin's knob takes the knob's default where a scene leaves it unset.
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
    // A short form's axis keeps its flag's bounds, so that --axis takes what the flag takes; any
    // other axis takes its knob's.
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
    if (existing != options.axes.end()) {
      existing->values = std::move(values);
      options.named[static_cast<std::size_t>(existing - options.axes.begin())] = true;
    } else {
      options.axes.push_back({engine, key, "--axis", static_cast<int>(low), std::move(values), {}});
      options.named.push_back(true);
    }
  }
  hold_unnamed_knobs(options);
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
    std::cout << sweep_json(sweep).dump(2) << '\n';
  else
    std::cout << sweep_table(sweep);
  std::cout.flush();
  if (options.out.empty()) return;
  ResultSet results = sweep.results;
  std::vector<SceneRecord> unique;
  for (SceneRecord& scene : results.scenes)
    if (std::ranges::find(unique, scene.hash, &SceneRecord::hash) == unique.end()) unique.push_back(std::move(scene));
  results.scenes = std::move(unique);
  const H5Table table = sweep_table_h5(sweep, options.axes, options.repeats);
  write_results_with_tables_h5(results, std::span(&table, 1), options.out, options.force);
}

}  // namespace

void register_sweep(CLI::App& app, const std::string& command_line) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* sweep = app.add_subcommand("sweep", "Speed against accuracy over each engine's solver settings, with Pareto fronts");
  options->scenes.add_to(*sweep, "pile");
  options->engines.add_to(*sweep);
  options->shard.add_to(*sweep);
  std::vector<const CLI::Option*> short_forms;  // per axis of options->axes, its flag
  for (KnobAxis& axis : options->axes) {
    const std::string what = axis.engine + " " + axis.key + " values to try, comma-separated";
    CLI::Option* option = sweep->add_option(axis.flag, axis.values, axis.values.empty() ? what + " (default: not swept)" : what)
                              ->delimiter(',')
                              ->allow_extra_args(false)
                              ->check(CLI::Range(axis.min_value, max_knob_value));
    if (!axis.values.empty()) option->capture_default_str();
    short_forms.push_back(option);
  }
  sweep
      ->add_option("--axis", options->axis_texts,
                   "Sweep any engine's integer knob, e.g. chipmunk.iterations=5,10,20 (the flags above are "
                   "its short forms). Once any knob of an engine is named, here or by a flag above, only its "
                   "named knobs are swept; the others keep the scene's values instead of their default grids")
      ->allow_extra_args(false);
  sweep->add_option("--dt", options->dts, "Time steps to try, s, comma-separated (default: the scene's)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->check(CLI::Range(1e-6, 1.0));
  sweep->add_option("--repeats", options->repeats, "Timed repeats per point")->check(CLI::Range(1, 1000))->capture_default_str();
  sweep->add_flag("--json", options->json, "Print the points and fronts as one JSON object (fx2d-bench.sweep/1)");
  CLI::Option* out = sweep->add_option("--out", options->out, "Write the runs and the /sweep table to this HDF5 file");
  sweep->add_flag("--force", options->force, "Overwrite the --out file if it exists")->needs(out);
  sweep->callback([options, short_forms, command_line] {
    options->named.clear();
    for (const CLI::Option* flag : short_forms) options->named.push_back(flag->count() > 0);
    sweep_command(*options, command_line);
  });
}

}  // namespace fxbench

// A sweep's points and fronts as a terminal table, JSON and the /sweep table: see sweep_format.h.
#include "format/sweep_format.h"

#include <cmath>
#include <iterator>
#include <limits>

#include "common/number_text.h"
#include "format/summary_format.h"
#include "format/text_table.h"

namespace fxbench {
namespace {

// Named columns of one row per point, from field(point, index).
template <class T, class Field>
H5Column column(const Sweep& sweep, std::string name, std::string units, Field field) {
  std::vector<T> values;
  for (std::size_t i = 0; i < sweep.points.size(); ++i) values.push_back(static_cast<T>(field(sweep.points[i], i)));
  return {std::move(name), std::move(units), std::move(values)};
}

// "value [low-high]", three decimals each.
std::string with_interval(double value, const Interval& interval) {
  return formatted("%.3f", value) + formatted(" [%.3f", interval.low) + formatted("-%.3f]", interval.high);
}

// A point's cost over its default's, with its interval, or "-" when the sweep has none.
std::string vs_default_text(const PointResult& point) {
  return point.vs_default ? with_interval(point.vs_default->ratio, point.vs_default->ci) : "-";
}

// The same as JSON: null when the sweep has none.
nlohmann::ordered_json vs_default_json(const PointResult& point) {
  if (!point.vs_default) return nullptr;
  const RatioEstimate& estimate = *point.vs_default;
  return {{"ratio", estimate.ratio}, {"ci_low", estimate.ci.low}, {"ci_high", estimate.ci.high}};
}

// One figure of a point's vs_default, as a /sweep column's field: NaN when the sweep has none.
template <class Figure>
auto vs_default_column(Figure figure) {
  return [figure](const PointResult& point, std::size_t) {
    return point.vs_default ? figure(*point.vs_default) : std::numeric_limits<double>::quiet_NaN();
  };
}

// Whether a point runs its engine on more than one thread: a knob named for a thread count (Fx2D's
// workers, Chipmunk2D's threads) above 1.
bool runs_threads(const Sweep& sweep) {
  for (const PointResult& point : sweep.points)
    for (const auto& [key, value] : point.grid.knobs)
      if ((key == "workers" || key == "threads") && value > 1) return true;
  return false;
}

// The machine's cross-core round trip as the sweep began and as it ended, which timings of threads
// that hand work to each other move with; "" when it was not measured.
std::string machine_text(const Provenance& provenance) {
  if (provenance.core_round_trip_ns_start <= 0 || provenance.core_round_trip_ns_end <= 0) return "";
  return "the machine: a cache line went from one core to another and back in " +
         formatted("%.0f", provenance.core_round_trip_ns_start) + " ns as the sweep began, " +
         formatted("%.0f", provenance.core_round_trip_ns_end) +
         " ns as it ended; timings of threads move with it (harness/README.md, sweep)\n";
}

}  // namespace

std::string sweep_table(const Sweep& sweep) {
  std::vector<std::vector<std::string>> rows = {{"scene", "engine", "settings", "dt s", "ms/step [95% CI]",
                                                 "cost x default [95% CI]", "max pen mm", "max disp m",
                                                 "escaped", "nan", "front", "default"}};
  for (std::size_t i = 0; i < sweep.points.size(); ++i) {
    const PointResult& point = sweep.points[i];
    const std::string primary = " (primary)";
    const bool by_displacement = point.metric == PrimaryMetric::displacement;
    rows.push_back({point.scene, point.engine, knobs_text(point.grid.knobs), formatted("%.5g", point.grid.dt),
                    with_interval(point.ms_median, point.ms_interval), vs_default_text(point),
                    formatted("%.2f", point.worst.max_penetration * 1e3) + (by_displacement ? "" : primary),
                    formatted("%.3f", point.worst.max_displacement) + (by_displacement ? primary : ""),
                    std::to_string(point.worst.escaped), std::to_string(point.worst.nan),
                    sweep.marks.on_front[i] ? formatted("#%.0f", sweep.marks.front_rank[i] + 1) : "-",
                    point.grid.is_default ? "default" : ""});
  }
  std::string text = aligned_columns(rows);
  for (std::size_t i = 0; i < sweep.points.size(); ++i) {
    const PointResult& point = sweep.points[i];
    if (!point.grid.is_default) continue;
    text += point.scene + ", " + point.engine + " default (" + knobs_text(point.grid.knobs) + "): ";
    if (const auto better = sweep.marks.dominated_by[i]) {
      const PointResult& other = sweep.points[*better];
      text += "off its front; ";
      text += knobs_text(other.grid.knobs) + formatted(" dt=%g", other.grid.dt) +
              " is at least as accurate at " +
              formatted("%.0f%% of its cost", 100.0 * other.cost / point.cost);
      // The medians' ratio decides the front; the rounds' pairs say how sure that is.
      text += other.vs_default ? " (paired by round: " + vs_default_text(other) + ")\n" : "\n";
    } else {
      text += formatted("on its front, #%.0f from the fastest\n", sweep.marks.front_rank[i] + 1);
    }
  }
  if (runs_threads(sweep)) text += machine_text(sweep.results.provenance);
  return text;
}

nlohmann::ordered_json sweep_json(const Sweep& sweep) {
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
        {"ms_per_step",
         {{"median", point.ms_median},
          {"ci_low", point.ms_interval.low},
          {"ci_high", point.ms_interval.high}}},
        {"ms_per_simulated_s", point.cost},
        {"cost_vs_default", vs_default_json(point)},
        {"primary_metric", metric_name(point.metric)},
        {"primary_error",
         std::isinf(point.error) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(point.error)},
        {"accuracy", accuracy_json(worst)},
        {"default", point.grid.is_default},
        {"on_front", static_cast<bool>(sweep.marks.on_front[i])},
        {"dominated_by", sweep.marks.dominated_by[i] ? nlohmann::ordered_json(*sweep.marks.dominated_by[i])
                                                     : nlohmann::ordered_json(nullptr)},
    });
  }
  for (const std::vector<std::size_t>& front : sweep.marks.fronts) {
    const PointResult& first = sweep.points[front.front()];
    fronts.push_back({{"scene", first.scene}, {"engine", first.engine}, {"points", front}});
  }
  return {{"schema", sweep_schema},
          {"points", points},
          {"fronts", fronts},
          {"machine", machine_json(sweep.results.provenance)}};
}

H5Table sweep_table_h5(const Sweep& sweep, std::span<const KnobAxis> axes, int repeats) {
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
  for (const KnobAxis& axis : axes) {
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
      column<std::int32_t>(sweep, "steps", "step",
                           [&](const PointResult& p, std::size_t) { return run(p).steps; }),
      column<double>(sweep, "ms_per_step", "ms",
                     [](const PointResult& p, std::size_t) { return p.ms_median; }),
      column<double>(sweep, "ms_per_step_ci_low", "ms",
                     [](const PointResult& p, std::size_t) { return p.ms_interval.low; }),
      column<double>(sweep, "ms_per_step_ci_high", "ms",
                     [](const PointResult& p, std::size_t) { return p.ms_interval.high; }),
      column<double>(sweep, "ms_per_simulated_s", "ms/s",
                     [](const PointResult& p, std::size_t) { return p.cost; }),
      column<double>(sweep, "cost_vs_default", "ratio",
                     vs_default_column([](const RatioEstimate& e) { return e.ratio; })),
      column<double>(sweep, "cost_vs_default_ci_low", "ratio",
                     vs_default_column([](const RatioEstimate& e) { return e.ci.low; })),
      column<double>(sweep, "cost_vs_default_ci_high", "ratio",
                     vs_default_column([](const RatioEstimate& e) { return e.ci.high; })),
      column<std::string>(sweep, "primary_metric", "",
                          [](const PointResult& p, std::size_t) { return metric_name(p.metric); }),
      column<double>(sweep, "primary_error", "m", [](const PointResult& p, std::size_t) { return p.error; }),
      column<double>(sweep, "max_penetration", "m", worst(&AccuracySample::max_penetration)),
      column<double>(sweep, "mean_penetration", "m", worst(&AccuracySample::mean_penetration)),
      column<double>(sweep, "max_displacement", "m", worst(&AccuracySample::max_displacement)),
      column<double>(sweep, "max_lateral_drift", "m", worst(&AccuracySample::max_lateral_drift)),
      column<double>(sweep, "final_kinetic_energy", "J", worst(&AccuracySample::kinetic_energy)),
      column<std::int32_t>(sweep, "escaped", "bodies",
                           [](const PointResult& p, std::size_t) { return p.worst.escaped; }),
      column<std::int32_t>(sweep, "nan", "bodies",
                           [](const PointResult& p, std::size_t) { return p.worst.nan; }),
      column<std::uint8_t>(sweep, "is_default", "flag",
                           [](const PointResult& p, std::size_t) { return p.grid.is_default; }),
      column<std::uint8_t>(sweep, "on_front", "flag",
                           [&](const PointResult&, std::size_t i) { return sweep.marks.on_front[i]; }),
      column<std::int32_t>(sweep, "front_rank", "rank",
                           [&](const PointResult&, std::size_t i) { return sweep.marks.front_rank[i]; }),
      column<std::int32_t>(sweep, "dominated_by", "index",
                           [&](const PointResult&, std::size_t i) {
                             return sweep.marks.dominated_by[i]
                                        ? static_cast<int>(*sweep.marks.dominated_by[i])
                                        : -1;
                           }),
  };
  columns.insert(columns.end(), std::make_move_iterator(figures.begin()), std::make_move_iterator(figures.end()));
  return {"/sweep",
          {{"schema", std::string(sweep_schema)},
           {"repeats", static_cast<std::int32_t>(repeats)},
           {"interval", std::string("95% percentile bootstrap (2000 resamples) of the median of per-repeat mean ms/step")},
           {"cost", std::string("ms_per_simulated_s = ms_per_step / dt")},
           {"shard", sweep.shard.text()},
           {"work_items", static_cast<std::int32_t>(sweep.work.items.size())},
           {"work_list", sweep.work.identity}},
          std::move(columns)};
}

}  // namespace fxbench

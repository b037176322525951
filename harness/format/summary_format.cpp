// What `fx2d-bench run` prints (summary_format.h): the JSON summary and the terminal table of
// each run's aggregates (analysis/summary.h).
#include "format/summary_format.h"

#include <algorithm>
#include <functional>

#include "analysis/summary.h"
#include "common/number_text.h"
#include "format/text_table.h"

namespace fxbench {
namespace {

std::string primary_metric_of(const ResultSet& results, const RunRecord& run) {
  const auto scene = std::ranges::find(results.scenes, run.scene_hash, &SceneRecord::hash);
  return scene == results.scenes.end() ? std::string() : scene->primary_metric;
}

nlohmann::ordered_json run_json(const RunRecord& run, const std::string& primary_metric) {
  const RunSummary summary = summarise(run);
  nlohmann::ordered_json phases = nlohmann::ordered_json::object();
  for (const auto& [name, ms] : summary.phases_ms) phases[name] = ms;
  const AccuracySample& worst = summary.worst;
  return {
      {"engine", run.engine},
      {"engine_version", run.engine_version},
      {"scene", run.scene},
      {"bodies", run.bodies},
      {"steps", run.steps},
      {"repeats", run.repeats},
      {"ms_per_step",
       {{"median", summary.ms_per_step.median}, {"min", summary.ms_per_step.min}, {"max", summary.ms_per_step.max}}},
      {"cpu_ms_per_step", {{"median", summary.cpu_ms_per_step.median}}},
      {"cycles_per_step", {{"median", summary.cycles_per_step.median}}},
      {"contacts_mean", summary.contacts_mean},
      {"phases_ms", phases},
      {"accuracy", accuracy_json(worst)},
      {"primary_metric", primary_metric},
      {"state_hash", run.final_state_hash},
      {"deterministic", run.deterministic},
  };
}

// With --counter instructions: the exact count per step, after the timing figures.
nlohmann::ordered_json counted_run_json(const RunRecord& run, const std::string& primary_metric) {
  nlohmann::ordered_json json = run_json(run, primary_metric);
  if (run.instruction_count) json["instructions_per_step"] = run.instruction_count->per_step();
  return json;
}

// The three largest phases as "name NN%" of the median step.
std::string top_phases(const RunSummary& summary) {
  std::vector<std::pair<std::string, double>> phases = summary.phases_ms;
  std::ranges::sort(phases, std::greater<>(), &std::pair<std::string, double>::second);
  phases.resize(std::min<std::size_t>(phases.size(), 3));
  std::string text;
  for (const auto& [name, ms] : phases) {
    if (!text.empty()) text += ' ';
    const double share = summary.ms_per_step.median > 0.0 ? 100.0 * ms / summary.ms_per_step.median : 0.0;
    text += name + " " + formatted("%.0f%%", share);
  }
  return text.empty() ? "-" : text;
}

// `counted`: the table has an instructions column (some run was counted); "-" for a run that was not.
std::vector<std::string> table_row(const RunRecord& run, bool counted) {
  const RunSummary summary = summarise(run);
  const Spread& ms = summary.ms_per_step;
  std::vector<std::string> row = {
      run.engine,
      run.scene,
      std::to_string(run.bodies),
      formatted("%.3f", ms.median) + formatted(" [%.3f", ms.min) + formatted("-%.3f]", ms.max),
      formatted("%.0f", summary.cycles_per_step.median)};
  if (counted) row.push_back(run.instruction_count ? formatted("%.0f", run.instruction_count->per_step()) : "-");
  row.insert(row.end(), {formatted("%.1f", summary.contacts_mean), top_phases(summary),
                         formatted("%.2f", summary.worst.max_penetration * 1e3),
                         formatted("%.3f", summary.worst.max_displacement), std::to_string(summary.worst.escaped),
                         std::to_string(summary.worst.nan),
                         run.final_state_hash.substr(0, 8) + (run.deterministic ? "" : " (varies)")});
  return row;
}

}  // namespace

nlohmann::ordered_json accuracy_json(const AccuracySample& worst) {
  return {{"max_penetration", worst.max_penetration},
          {"mean_penetration", worst.mean_penetration},
          {"max_displacement", worst.max_displacement},
          {"max_lateral_drift", worst.max_lateral_drift},
          {"final_kinetic_energy", worst.kinetic_energy},
          {"escaped", worst.escaped},
          {"nan", worst.nan}};
}

nlohmann::ordered_json machine_json(const Provenance& provenance) {
  return {{"core_round_trip_ns_start", provenance.core_round_trip_ns_start},
          {"core_round_trip_ns_end", provenance.core_round_trip_ns_end}};
}

nlohmann::ordered_json summary_json(const ResultSet& results) {
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const RunRecord& run : results.runs) runs.push_back(counted_run_json(run, primary_metric_of(results, run)));
  return {{"schema", summary_schema}, {"runs", runs}, {"machine", machine_json(results.provenance)}};
}

std::string summary_table(const ResultSet& results) {
  const bool counted = std::ranges::any_of(results.runs, [](const RunRecord& run) { return run.instruction_count.has_value(); });
  std::vector<std::string> header = {"engine", "scene", "bodies", "ms/step median [min-max]", "cycles/step"};
  if (counted) header.push_back("instr/step");
  header.insert(header.end(), {"contacts", "top phases (% of step)", "max pen mm", "max disp m", "escaped", "nan", "state hash"});
  std::vector<std::vector<std::string>> rows = {header};
  for (const RunRecord& run : results.runs) rows.push_back(table_row(run, counted));
  return aligned_columns(rows);
}

}  // namespace fxbench

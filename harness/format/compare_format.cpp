// The renderers of a compare report (compare_format.h): the terminal table, Markdown for a pull
// request, and the JSON object (schema fx2d-bench.compare/1) that gate and report read.
#include "format/compare_format.h"

#include <algorithm>
#include <iostream>

#include "common/number_text.h"
#include "format/text_table.h"
#include "stats/statistics.h"

namespace fxbench {
namespace {

std::string value_text(const std::string& metric, double value) {
  if (metric == "cycles_per_step" || metric == instructions_metric) return formatted("%.0f", value);
  return formatted("%.4g ms", value);
}

std::string p_text(const std::optional<RankTest>& test) {
  if (!test) return "-";
  return test->p_value < 0.001 ? std::string("<0.001") : formatted("%.3f", test->p_value);
}

std::string verdict_text(const CompareRow& row) {
  std::string text = row.verdict();
  if (row.speed.speed != Speed::inconclusive) return text;
  return text + (row.speed.repeats_needed ? " (~" + std::to_string(*row.speed.repeats_needed) + " repeats would decide)"
                                          : " (more repeats would not decide)");
}

std::string physics_text(bool same) { return same ? "same physics" : "physics changed"; }

// Penetration in millimetres (it is small), displacement in metres, counts as they are, then
// the change when there is one.
std::string delta_text(const AccuracyDelta& delta) {
  const auto [format, scale] = delta.name == "max_penetration"    ? std::pair{"%.3f", 1e3}
                               : delta.name == "max_displacement" ? std::pair{"%.4f", 1.0}
                                                                  : std::pair{"%.0f", 1.0};
  std::string text = formatted(format, delta.a * scale) + " -> " + formatted(format, delta.b * scale);
  // Appended piece by piece: GCC 12 misreads " " + std::string as an overlapping copy (-Wrestrict).
  if (delta.change != AccuracyChange::same) text.append(" ").append(to_string(delta.change));
  return text;
}

using Table = std::vector<std::vector<std::string>>;

// Physics comes before the verdict, so that an empty cell never ends a line; it is said once
// per pair of runs, on the step-time row.
Table speed_table(const CompareReport& report, bool emphasise_regressions) {
  const bool ab = !report.cross_engine;
  std::vector<std::string> header = {"engine"};
  if (!ab) header.emplace_back("against");
  header.insert(header.end(), {"scene", "bodies", "metric", "A", "B", "B/A", "95% CI", "p"});
  if (ab) header.emplace_back("physics");
  header.emplace_back("verdict");
  Table table = {header};
  for (const CompareRow& row : report.rows) {
    std::vector<std::string> cells = {row.engine};
    if (!ab) cells.push_back(row.against);
    cells.insert(cells.end(), {row.scene, std::to_string(row.bodies), row.metric, value_text(row.metric, row.a),
                               value_text(row.metric, row.b), formatted("%.3f", row.estimate.ratio),
                               formatted("[%.3f, ", row.estimate.ci.low) + formatted("%.3f]", row.estimate.ci.high),
                               p_text(row.test)});
    if (ab) cells.push_back(row.metric == step_metric ? physics_text(row.same_physics.value_or(false)) : "");
    const bool emphasised = emphasise_regressions && report.is_regression(row);
    cells.push_back(emphasised ? "**" + verdict_text(row) + "**" : verdict_text(row));
    table.push_back(std::move(cells));
  }
  return table;
}

Table accuracy_table(const CompareReport& report) {
  Table table = {{"engine", "scene", "bodies", "primary metric", "max penetration mm", "max displacement m", "escaped",
                  "nan", "accuracy"}};
  if (report.cross_engine) table[0].insert(table[0].begin() + 1, "against");
  for (const CompareRow& row : report.rows) {
    if (row.accuracy.empty()) continue;
    std::vector<std::string> cells = {row.engine, row.scene, std::to_string(row.bodies), row.primary_metric};
    for (const AccuracyDelta& delta : row.accuracy) cells.push_back(delta_text(delta));
    cells.push_back(to_string(row.accuracy_change()));
    if (report.cross_engine) cells.insert(cells.begin() + 1, row.against);
    table.push_back(std::move(cells));
  }
  return table;
}

std::string method_note(const CompareReport& report) {
  const CompareSettings& settings = report.settings;
  const bool counted = std::ranges::find(report.rows, instructions_metric, &CompareRow::metric) != report.rows.end();
  const std::string instructions_note =
      counted ? " instructions_per_step: exact counts of the step loop under callgrind; a change counts beyond +-" +
                    formatted("%g%%", 100.0 * settings.instructions_tolerance) + "."
              : "";
  const bool paired = std::ranges::any_of(report.rows, &CompareRow::rounds_paired);
  const std::string estimator =
      paired ? "B/A: the median of the ratios b/a of A's and B's rounds run back to back, with a 95% percentile "
               "bootstrap interval resampling those pairs of rounds ("
             : "B/A: their ratio, with a 95% percentile bootstrap interval resampling A's and B's repeats independently (";
  return "a, b: median over repeats of each repeat's median step; " + estimator +
         std::to_string(bootstrap_resamples) + " resamples, fixed seed); a change counts when p < " +
         formatted("%g", settings.rules.alpha) + " and the interval clears the noise band +-" +
         formatted("%g%%", 100.0 * settings.rules.noise) + ". Accuracy tolerance " +
         formatted("%g%%", 100.0 * settings.accuracy_tolerance) + " + " + formatted("%g mm", accuracy_floor_m * 1e3) +
         "; penetration, escaped and nan are errors everywhere, displacement where it is the primary metric." +
         instructions_note;
}

nlohmann::ordered_json accuracy_json(const CompareRow& row) {
  nlohmann::ordered_json figures = nlohmann::ordered_json::object();
  for (const AccuracyDelta& delta : row.accuracy)
    figures[delta.name] = {{"a", delta.a}, {"b", delta.b}, {"change", to_string(delta.change)}};
  return {{"primary_metric", row.primary_metric}, {"change", to_string(row.accuracy_change())}, {"figures", figures}};
}

nlohmann::ordered_json row_json(const CompareReport& report, const CompareRow& row) {
  nlohmann::ordered_json json = {
      {"engine", row.engine},
      {"against", row.against},
      {"scene", row.scene},
      {"bodies", row.bodies},
      {"metric", row.metric},
      {"a", row.a},
      {"b", row.b},
      {"ratio", row.estimate.ratio},
      {"ci_low", row.estimate.ci.low},
      {"ci_high", row.estimate.ci.high},
      {"p_value", nullptr},
      {"test", row.test_name},
      {"repeats_a", row.repeats_a},
      {"repeats_b", row.repeats_b},
      {"verdict", row.verdict()},
      {"speed", to_string(row.speed.speed)},
      {"repeats_needed", nullptr},
      {"physics", nullptr},
      {"regression", report.is_regression(row)},
  };
  if (row.test) json["p_value"] = row.test->p_value;
  if (row.speed.repeats_needed) json["repeats_needed"] = *row.speed.repeats_needed;
  if (row.same_physics) json["physics"] = *row.same_physics ? "same" : "changed";
  if (!row.accuracy.empty()) json["accuracy"] = accuracy_json(row);
  return json;
}

}  // namespace

nlohmann::ordered_json compare_json(const CompareReport& report) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const CompareRow& row : report.rows) rows.push_back(row_json(report, row));
  const CompareSettings& settings = report.settings;
  return {
      {"schema", compare_schema},
      {"mode", report.cross_engine ? "cross-engine" : "ab"},
      {"noise", settings.rules.noise},
      {"alpha", settings.rules.alpha},
      {"accuracy_tolerance", settings.accuracy_tolerance},
      {"instructions_tolerance", settings.instructions_tolerance},
      {"bootstrap", {{"resamples", bootstrap_resamples}, {"seed", bootstrap_seed}, {"confidence", confidence_level}}},
      {"headline", report.headline()},
      {"rows", rows},
      {"regressions", report.count_regressions()},
  };
}

std::string compare_markdown(const CompareReport& report) {
  return "**fx2d-bench compare**: " + report.headline() + "\n\n" + markdown_table(speed_table(report, true)) + "\n" +
         markdown_table(accuracy_table(report)) + "\n<sub>" + method_note(report) + "</sub>\n";
}

std::string compare_table(const CompareReport& report) {
  return report.headline() + "\n\n" + aligned_columns(speed_table(report, false)) + "\n" +
         aligned_columns(accuracy_table(report)) + "\n" + method_note(report) + "\n";
}

ExitCode print_compare_report(const CompareReport& report, const CompareOutput& output) {
  for (const std::string& warning : report.warnings) std::cerr << "fx2d-bench: warning: " << warning << '\n';
  if (output.json)
    std::cout << compare_json(report).dump(2) << '\n';
  else if (output.markdown)
    std::cout << compare_markdown(report);
  else
    std::cout << compare_table(report);
  std::cout.flush();
  return report.exit_code();
}

}  // namespace fxbench

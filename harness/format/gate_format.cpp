// The nightly gate's verdict as text (gate_format.h): the terminal table with the quarantined
// rows and noisy controls under it, and the JSON object of schema fx2d-bench.gate/1.
#include "format/gate_format.h"

#include <cstdio>

#include "analysis/compare.h"
#include "format/text_table.h"

namespace fxbench {
namespace {

std::string fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

std::string value_text(const GateRow& row, double value) {
  return row.metric == instructions_metric ? fixed(value, 0) : fixed(value, 4);
}

std::string interval_text(const GateRow& row) {
  if (!row.p_value) return fixed(row.ratio, 4) + " (exact)";
  return fixed(row.ratio, 3) + " [" + fixed(row.ci_low, 3) + ", " + fixed(row.ci_high, 3) + "]";
}

}  // namespace

nlohmann::ordered_json ratio_json(const std::string& engine, const std::string& scene, int bodies,
                                  const std::string& metric, double a, double b, double ratio, double ci_low,
                                  double ci_high, std::optional<double> p_value) {
  return {{"engine", engine}, {"scene", scene},     {"bodies", bodies},   {"metric", metric},
          {"a", a},           {"b", b},             {"ratio", ratio},     {"ci_low", ci_low},
          {"ci_high", ci_high}, {"p_value", p_value ? nlohmann::ordered_json(*p_value) : nlohmann::ordered_json()}};
}

std::string gate_table(const GateReport& report, const std::string& policy_path) {
  std::vector<std::vector<std::string>> cells{
      {"engine", "scene", "bodies", "metric", "A", "B", "ratio [95% CI]", "band", "compare said", "gate"}};
  std::string quarantined;
  for (const GateRow& row : report.rows) {
    if (row.quarantined) {
      quarantined += "  " + row.engine + " " + row.scene + " " + std::to_string(row.bodies) + " " + row.metric +
                     ": " + row.reason + "\n";
      continue;
    }
    cells.push_back({row.engine, row.scene, std::to_string(row.bodies), row.metric, value_text(row, row.a),
                     value_text(row, row.b), interval_text(row), "±" + fixed(100.0 * row.band, 1) + "%",
                     row.compare_verdict, row.regression ? row.verdict + " (REGRESSION)" : row.verdict});
  }
  std::string text = report.headline() + "\n\n" + aligned_columns(cells);
  if (!quarantined.empty()) text += "\nquarantined, not gating (" + policy_path + "):\n" + quarantined;
  for (const std::string& control : report.noisy_controls) text += "\nnoisy machine: control " + control;
  if (!report.noisy_controls.empty()) text += "\n";
  return text;
}

nlohmann::ordered_json gate_json(const GateReport& report, const std::vector<std::string>& compare_paths,
                                 const std::string& policy_path) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const GateRow& row : report.rows) {
    nlohmann::ordered_json json = ratio_json(row.engine, row.scene, row.bodies, row.metric, row.a, row.b, row.ratio,
                                             row.ci_low, row.ci_high, row.p_value);
    json.update({{"band", row.band},
                 {"compare_verdict", row.compare_verdict},
                 {"verdict", row.verdict},
                 {"control", row.control},
                 {"quarantined", row.quarantined},
                 {"reason", row.reason},
                 {"regression", row.regression},
                 {"step_detected", row.step_detected}});
    rows.push_back(std::move(json));
  }
  return {{"schema", gate_schema},       {"compare", compare_paths},
          {"policy", policy_path}, {"headline", report.headline()},
          {"rows", rows},                  {"noisy_controls", report.noisy_controls},
          {"regressions", report.regressions()}, {"exit_code", static_cast<int>(report.exit_code())}};
}

}  // namespace fxbench

// The nightly history as a terminal table or JSON: see history_format.h.
#include "format/history_format.h"

#include <cmath>
#include <optional>

#include "common/number_text.h"
#include "format/gate_format.h"
#include "format/text_table.h"

namespace fxbench {

std::string history_table(std::span<const HistoryRow> rows) {
  std::vector<std::vector<std::string>> cells{{"date (UTC)", "candidate", "baseline", "engine", "scene", "bodies",
                                               "metric", "ratio [95% CI]", "verdict", "step", "accepted"}};
  for (const HistoryRow& row : rows) {
    const std::string interval = std::isnan(row.p_value)
                                     ? formatted("%.4f", row.ratio) + " (exact)"
                                     : formatted("%.3f", row.ratio) + " [" + formatted("%.3f", row.ci_low) + ", " +
                                           formatted("%.3f", row.ci_high) + "]";
    cells.push_back({row.date_utc, row.candidate, row.baseline, row.engine, row.scene, std::to_string(row.bodies),
                     row.metric, interval, row.verdict, row.step_detected ? "step" : "", row.accepted ? "yes" : ""});
  }
  return aligned_columns(cells);
}

nlohmann::ordered_json history_json(std::span<const HistoryRow> rows) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const HistoryRow& row : rows) {
    const std::optional<double> p_value = std::isnan(row.p_value) ? std::nullopt : std::optional(row.p_value);
    nlohmann::ordered_json json = {{"date_utc", row.date_utc}, {"candidate", row.candidate}, {"baseline", row.baseline}};
    json.update(ratio_json(row.engine, row.scene, row.bodies, row.metric, row.a, row.b, row.ratio, row.ci_low,
                           row.ci_high, p_value));
    json.update({{"verdict", row.verdict}, {"step_detected", row.step_detected}, {"accepted", row.accepted}});
    list.push_back(std::move(json));
  }
  return {{"schema", history_schema}, {"rows", list}};
}

}  // namespace fxbench

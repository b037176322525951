// `fx2d-bench gate COMPARE.json... --policy ci/gating.json [--json]`: the nightly verdict. Re-judges
// the gating rows of comparisons (`fx2d-bench compare --json`, or the verdict `fx2d-bench ab`
// prints) against the committed policy: each scene's own thresholds, quarantined rows dropped
// with their reason, controls that flag a noisy machine (gate_policy.h holds the rules).
// `--print-suite full|smoke` prints what the nightly job measures, one fact a line, for ci/nightly.
//
// Reads top to bottom: the options, the suite printer, the table and JSON renderers, the command.
// Exit codes as compare's: 0 no regression, 1 a regression, 2 bad input (policy or comparison),
// 3 inconclusive (a gating row undecided, or a control changed).
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "analysis/compare.h"
#include "analysis/gate_policy.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "format/text_table.h"

namespace fxbench {
namespace {

struct GateOptions {
  std::vector<std::string> compare_paths;
  std::string policy_path;
  std::string print_suite;
  bool json = false;
};

// --- the suite, for ci/nightly --------------------------------------------------------------------

std::string suite_lines(const Suite& suite) {
  std::string engines;
  for (const std::string& engine : suite.engines) engines += (engines.empty() ? "" : ",") + engine;
  std::string text = "engines " + engines + "\nrounds " + std::to_string(suite.rounds) + "\nsteps " +
                     std::to_string(suite.steps) + "\n";
  for (const SuiteScene& scene : suite.scenes) text += "scene " + scene.scene + " " + std::to_string(scene.bodies) + "\n";
  return text;
}

// --- output ---------------------------------------------------------------------------------------

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

nlohmann::ordered_json gate_json(const GateReport& report, const GateOptions& options) {
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
  return {{"schema", gate_schema},       {"compare", options.compare_paths},
          {"policy", options.policy_path}, {"headline", report.headline()},
          {"rows", rows},                  {"noisy_controls", report.noisy_controls},
          {"regressions", report.regressions()}, {"exit_code", static_cast<int>(report.exit_code())}};
}

// --- the command ----------------------------------------------------------------------------------

ExitCode gate_command(const GateOptions& options) {
  const Policy policy = read_policy(options.policy_path);
  if (!options.print_suite.empty()) {
    std::cout << suite_lines(options.print_suite == "smoke" ? policy.smoke : policy.suite);
    return exit_ok;
  }
  if (options.compare_paths.empty()) throw InputError("gate: give COMPARE.json to judge, or --print-suite full|smoke");
  const GateReport report = judge_files(options.compare_paths, policy);
  if (options.json)
    std::cout << gate_json(report, options).dump(2) << "\n";
  else
    std::cout << gate_table(report, options.policy_path);
  return report.exit_code();
}

}  // namespace

void register_gate(CLI::App& app, int& exit_status) {
  auto options = std::make_shared<GateOptions>();
  CLI::App* gate = app.add_subcommand(
      "gate", "Judge a comparison against the committed gating policy (thresholds per scene, quarantine, controls)");
  CLI::Option* compare =
      gate->add_option("COMPARE", options->compare_paths,
                       "JSON of `fx2d-bench compare --json` (or of `ab --json`); several are judged as one night");
  gate->add_option("--policy", options->policy_path, "Gating policy (fx2d-bench.gating/1, e.g. ci/gating.json)")
      ->required();
  gate->add_option("--print-suite", options->print_suite, "Print the suite the nightly job measures, one fact a line")
      ->check(CLI::IsMember({"full", "smoke"}))
      ->excludes(compare);
  gate->add_flag("--json", options->json, "Print one JSON object (fx2d-bench.gate/1)");
  gate->callback([options, &exit_status] { exit_status = gate_command(*options); });
}

}  // namespace fxbench

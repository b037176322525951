// `fx2d-bench gate COMPARE.json... --policy ci/gating.json [--json]`: the nightly verdict. Re-judges
// the gating rows of comparisons (`fx2d-bench compare --json`, or the verdict `fx2d-bench ab`
// prints) against the committed policy: each scene's own thresholds, quarantined rows dropped
// with their reason, controls that flag a noisy machine (gate_policy.h holds the rules).
// `--print-suite full|smoke` prints what the nightly job measures, one fact a line, for ci/nightly.
//
// Reads top to bottom: the options, the suite printer, the command; the table and the JSON are
// format/gate_format.cpp.
// Exit codes as compare's: 0 no regression, 1 a regression, 2 bad input (policy or comparison),
// 3 inconclusive (a gating row undecided, or a control changed).
#include <iostream>
#include <memory>
#include <sstream>

#include "analysis/gate_policy.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "format/gate_format.h"

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
    std::cout << gate_json(report, options.compare_paths, options.policy_path).dump(2) << "\n";
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

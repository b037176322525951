// `fx2d-bench gate COMPARE.json... --policy ci/gating.json [--json]`: the nightly verdict. Re-judges
// the gating rows of comparisons (`fx2d-bench compare --json`, or the verdict `fx2d-bench ab`
// prints) against the committed policy: each scene's own thresholds, quarantined rows dropped
// with their reason, controls that flag a noisy machine (gate_policy.h holds the rules).
// `--print-suite full|smoke` prints what the nightly job measures, one fact a line, for ci/nightly
// (`scene pile 600 pile_600`, or `scene FILE - STEM` for a scene run as it stands: the scene, its
// size and what the night's files for it are called);
// with `--shard K/N|auto`, only the scenes of that part of the suite (a scene and its controls are
// one work item: the controls of a comparison run on the machine that measured it), balanced by
// bodies, with the part and the whole suite's identity, which `ci/nightly --collect` checks.
//
// Reads top to bottom: the options, the suite printer, the command; the table and the JSON are
// format/gate_format.cpp.
// Exit codes as compare's: 0 no regression, 1 a regression, 2 bad input (policy or comparison),
// 3 inconclusive (a gating row undecided, or a control changed).
#include <iostream>
#include <memory>
#include <sstream>

#include "analysis/gate_policy.h"
#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "common/shard.h"
#include "format/gate_format.h"
#include "scene/scene_loader.h"

namespace fxbench {
namespace {

struct GateOptions {
  std::vector<std::string> compare_paths;
  std::string policy_path;
  std::string print_suite;
  ShardOptions shard;
  bool json = false;
};

// --- the suite, for ci/nightly --------------------------------------------------------------------

// The bodies of a suite's scene run as it stands, its cost in the balance of the shards.
int bodies_of_suite_scene(const std::string& scene, const std::string& name, const std::string& policy_path) {
  try {
    return bodies_of(load_scene(scene));
  } catch (const InputError& error) {
    throw InputError(policy_path + ": the " + name + " suite's scene: " + error.what() +
                     " (a suite's scene files are read from the working directory)");
  }
}

std::string suite_lines(const std::string& name, const Suite& suite, const Shard& shard,
                        const std::string& policy_path) {
  std::string engines;
  for (const std::string& engine : suite.engines) engines += (engines.empty() ? "" : ",") + engine;
  const std::string settings = "engines " + engines + "\nrounds " + std::to_string(suite.rounds) + "\nsteps " +
                               std::to_string(suite.steps) + "\n";
  std::vector<std::string> keys{"nightly " + name + "\n" + settings};
  std::vector<double> costs;
  for (const SuiteScene& scene : suite.scenes) {
    // `-`: the scene as it stands, weighed by the bodies it holds (which also checks it loads).
    keys.push_back(scene.scene + " " + (scene.bodies > 0 ? std::to_string(scene.bodies) : "-"));
    costs.push_back(scene.bodies > 0 ? scene.bodies : bodies_of_suite_scene(scene.scene, name, policy_path));
  }
  std::string text = settings + "shard " + shard.text() + "\nwork_items " + std::to_string(costs.size()) +
                     "\nwork_list " + work_list_identity(keys) + "\n";
  for (std::size_t item : items_of(shard, costs))
    text += "scene " + keys[item + 1] + " " + suite.scenes[item].name + "\n";
  return text;
}

// --- the command ----------------------------------------------------------------------------------

ExitCode gate_command(const GateOptions& options) {
  const Policy policy = read_policy(options.policy_path);
  if (!options.print_suite.empty()) {
    const Suite& suite = options.print_suite == "smoke" ? policy.smoke : policy.suite;
    std::cout << suite_lines(options.print_suite, suite, options.shard.shard(), options.policy_path);
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
  CLI::Option* print_suite = gate->add_option("--print-suite", options->print_suite, "Print the suite the nightly job measures, one fact a line")
      ->check(CLI::IsMember({"full", "smoke"}))
      ->excludes(compare);
  options->shard.add_to(*gate);
  gate->get_option("--shard")->needs(print_suite);
  gate->add_flag("--json", options->json, "Print one JSON object (fx2d-bench.gate/1)");
  gate->callback([options, &exit_status] { exit_status = gate_command(*options); });
}

}  // namespace fxbench

// `fx2d-bench compare A.h5 [B.h5]`: reads the result files, judges them (analysis/compare.h)
// and prints the report in the chosen format (format/compare_format.h).
#include "commands/compare.h"

#include <memory>

#include "commands/commands.h"
#include "format/compare_format.h"
#include "measure/interleave.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

struct CompareOptions {
  std::string a_path;
  std::string b_path;
  CLI::Option* b_option = nullptr;
  std::string baseline;
  CompareSettings settings;
  CompareOutput output;
};

ExitCode compare_command(const CompareOptions& options) {
  const std::optional<std::string> b_path =
      options.b_option->count() > 0 ? std::optional<std::string>(options.b_path) : std::nullopt;
  const CompareReport report = compare_files(options.a_path, b_path, options.baseline, options.settings);
  return print_compare_report(report, options.output);
}

}  // namespace

CompareReport compare_files(const std::string& a_path, const std::optional<std::string>& b_path,
                            const std::string& baseline, const CompareSettings& settings) {
  const ResultSet a = read_results_h5(a_path);
  if (const auto ab = split_variants(a); ab && !b_path) return compare_variants(*ab, settings);
  if (!b_path) return compare_engines(a, a_path, baseline, settings);
  return compare_results(a, a_path, read_results_h5(*b_path), *b_path, settings);
}

void register_compare(CLI::App& app, int& exit_status) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* compare = app.add_subcommand(
      "compare", "Judge B against A (speed with confidence intervals, accuracy, physics), or the engines within A");
  compare->add_option("A", options->a_path, "Result file of the reference (fx2d-bench.results/1)")->required();
  options->b_option =
      compare->add_option("B", options->b_path, "Result file to judge against A; without it, the engines within A");
  // Any engine the file holds, a plugin's label included: compare_engines refuses one it lacks.
  compare
      ->add_option("--baseline", options->baseline,
                   "Within A alone: every other engine against this one, a built-in engine or a plugin's label "
                   "(default: fx2d against the others)")
      ->excludes(options->b_option);
  VerdictRules& rules = options->settings.rules;
  compare->add_option("--noise", rules.noise, "Ratios within 1 +- noise count as no change")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  compare->add_option("--alpha", rules.alpha, "Significance level of the rank test")
      ->check(CLI::Range(1e-9, 0.5))
      ->capture_default_str();
  compare
      ->add_option("--accuracy-tolerance", options->settings.accuracy_tolerance,
                   "Relative change in an accuracy figure that counts (plus 0.1 mm for lengths)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  compare
      ->add_option("--instructions-tolerance", options->settings.instructions_tolerance,
                   "Relative change in instructions per step that counts (runs with --counter instructions)")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  CLI::Option* json = compare->add_flag("--json", options->output.json, "Print one JSON object (fx2d-bench.compare/1)");
  compare->add_flag("--markdown", options->output.markdown, "Print a Markdown report for a pull-request comment")->excludes(json);
  compare->add_flag("--force", options->settings.force,
                    "Compare runs of different scenes, and do not warn when machine, compiler or flags differ");
  compare->callback([options, &exit_status] { exit_status = compare_command(*options); });
}

}  // namespace fxbench

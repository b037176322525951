// `fx2d-bench ab --a X --b Y [SCENE ...]`: two builds of one engine (Fx2D, or any engine plugin),
// back to back in one process, and the verdict `fx2d-bench compare` gives on them.
//
// Reads top to bottom: the options; the checks made before anything is built (scenes, --out, both
// builds resolved, valgrind for --counter); the two builds turned into loaded plugins
// (ab_builds.h: a plugin file, a build directory, `worktree` or a git revision, built and cached),
// each named on stderr with the plugin file loaded; every scene measured in ABBA rounds
// (interleave.h: why rounds alternate, and what a round is), then with --counter instructions
// each build's step loop counted under callgrind from that same plugin file
// (instruction_counter.h); one result file holding both builds as engines NAME@A and NAME@B
// (fx2d@A and fx2d@B for Fx2D); then the A/B verdict, computed by compare's own functions on the
// same split of that file `fx2d-bench compare ab.h5` makes, with compare's renderers and exit
// codes (0 no regression, 1 regression, 3 inconclusive; 2 bad input, as everywhere).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "analysis/compare.h"
#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "format/compare_format.h"
#include "measure/ab_builds.h"
#include "measure/clocks.h"
#include "measure/instruction_counter.h"
#include "measure/interleave.h"
#include "measure/interrupt.h"
#include "measure/provenance.h"
#include "stats/statistics.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

struct AbOptions {
  std::string a;
  std::string b;
  std::string a_cmake;
  std::string b_cmake;
  std::string source;  // --source: the Fx2D source tree whose plugin project builds revisions
  SceneOptions scenes;
  InterleavePlan plan;
  std::string out;
  std::string counter;  // "instructions": also count each build's step loop under callgrind
  bool force = false;
  bool json = false;
  bool markdown = false;
};

// The engine entry of one build: the plugin's engine named after itself, e.g. fx2d@A or
// chipmunk@B, its version saying which build it is (e.g. "0.1.0 a1b2c3d (HEAD~1) -DFX2D_NATIVE=ON").
EngineInfo variant_engine(const PluginBuild& build, Variant variant) {
  EngineInfo engine = plugin_engine_info(build.plugin, variant_engine_name(build.plugin->name(), variant));
  engine.version = std::string(build.plugin->table().library_version()) + " " + build.description;
  return engine;
}

// Where a build's engine comes from, for the lines naming A and B: its plugin file, or this binary.
std::string origin_of(const PluginBuild& build) {
  return build.path.empty() ? "linked into this fx2d-bench" : "plugin " + build.path;
}

// The build as an engine name another fx2d-bench process (the count under callgrind) loads: the very
// plugin file timed, labelled `label`, or the built-in engine of this binary's name.
std::string engine_name_of(const PluginBuild& build, const std::string& label) {
  return build.path.empty() ? build.plugin->name() : "plugin:" + build.path + "|" + label;
}

SceneRecord scene_record(const SceneSpec& scene) {
  const char* metric = scene.primary_metric == PrimaryMetric::displacement ? "displacement" : "penetration";
  return {scene.name, scene.hash, scene.resolved_json, scene.source_path, metric};
}

// One line on stderr, redrawn in place when stderr is a terminal.
RoundProgressFn round_progress(const SceneSpec& scene) {
  if (isatty(STDERR_FILENO) != 1) return {};
  return [name = scene.name, bodies = bodies_of(scene)](int round, int total) {
    std::fprintf(stderr, "\r\x1b[Kab %s %d: round %d/%d (%s)", name.c_str(), bodies, round + 1, total,
                 variant_of_round(round) == Variant::a ? "A" : "B");
    std::fflush(stderr);
  };
}

// The rounds are judged by a sign test (compare's Method): below its fewest decisive pairs no
// slowdown, however large, could ever be called `slower`.
std::string too_few_rounds(int rounds) {
  const double alpha = CompareSettings{}.rules.alpha;
  std::ostringstream message;
  message << rounds << " rounds: the sign test over fewer than " << sign_test_min_pairs(alpha)
          << " cannot reach p < " << alpha << ", so no slowdown however large can be judged";
  return message.str();
}

ExitCode ab_command(const AbOptions& options, const std::string& command_line) {
  if (!options.out.empty() && !options.force && std::filesystem::exists(options.out))
    throw InputError(options.out + ": exists; pass --force to overwrite it");
  const std::vector<SceneSpec> scenes = options.scenes.load();
  const ResolvedBuild resolved_a = resolve_plugin_build("--a", options.a, options.a_cmake, options.source);
  const ResolvedBuild resolved_b = resolve_plugin_build("--b", options.b, options.b_cmake, options.source);
  // instruction_counter.h: refuses before anything is built when valgrind cannot run.
  const std::optional<InstructionCounter> counter =
      options.counter.empty() ? std::nullopt : std::optional<InstructionCounter>(std::in_place);

  const PluginBuild build_a = prepare_plugin_build(resolved_a);
  const PluginBuild build_b = prepare_plugin_build(resolved_b);
  if (build_a.plugin->name() != build_b.plugin->name())
    throw InputError("--a is " + build_a.plugin->name() + " and --b is " + build_b.plugin->name() +
                     "; ab judges two builds of one engine (compare two engines with run and compare)");
  const EngineInfo engine_a = variant_engine(build_a, Variant::a);
  const EngineInfo engine_b = variant_engine(build_b, Variant::b);
  std::cerr << "fx2d-bench: A = " << engine_a.version << " (" << origin_of(build_a) << ")\nfx2d-bench: B = "
            << engine_b.version << " (" << origin_of(build_b) << ")\n";

  const ScopedInterruptHandler interrupts;  // interrupt.h: Ctrl-C saves what was measured
  ResultSet results;
  results.provenance = collect_provenance(command_line, measure_counter_ghz());
  const auto started = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < scenes.size() && !results.partial; ++i) {
    const SceneSpec& scene = scenes[i];
    InterleavePlan plan = options.plan;
    plan.warmup_steps = scene.steps;  // one discarded trajectory per build, as `run` does
    if (plan.time_budget_s > 0) {  // what is left of the budget, shared by the scenes left
      const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      plan.time_budget_s = std::max(1e-3, (options.plan.time_budget_s - spent) / static_cast<double>(scenes.size() - i));
    }
    InterleavedRuns runs = measure_interleaved(scene, engine_a, engine_b, plan, round_progress(scene));
    if (isatty(STDERR_FILENO) == 1) std::fputs("\r\x1b[K", stderr);
    results.partial = runs.interrupted;
    if (runs.a.repeats < sign_test_min_pairs(CompareSettings{}.rules.alpha) && !results.partial)
      std::cerr << "fx2d-bench: " << scene.name << " " << bodies_of(scene) << ": --time-budget allowed "
                << too_few_rounds(runs.a.repeats) << "\n";
    // The count loads the very plugin files just timed, never another build of the same revision.
    for (auto [run, build] : {std::pair{&runs.a, &build_a}, std::pair{&runs.b, &build_b}}) {
      if (!counter || results.partial) continue;
      run->instruction_count = counter->count(scene, engine_name_of(*build, run->engine));
      results.partial = !run->instruction_count;  // interrupt.h: the SIGINT stopped the counting child
    }
    results.scenes.push_back(scene_record(scene));
    for (RunRecord* run : {&runs.a, &runs.b})
      if (run->repeats > 0) results.runs.push_back(std::move(*run));
  }
  finish_provenance(results.provenance);

  // interrupt.h: a partial result never takes the final name, and gets no verdict.
  if (results.partial) {
    const std::string out = options.out.empty() ? std::string() : options.out + ".partial.h5";
    if (!out.empty()) write_results_h5(results, out, true);
    exit_after_interrupt("interrupted; " + std::to_string(results.runs.size()) + " run(s) measured so far " +
                         (out.empty() ? std::string("not saved (no --out)") : "saved to " + out));
  }
  if (!options.out.empty()) write_results_h5(results, options.out, options.force);

  const std::optional<VariantResults> variants = split_variants(results);
  const CompareReport report = compare_variants(*variants, CompareSettings{});
  return print_compare_report(report, {.json = options.json, .markdown = options.markdown});
}

// --rounds: refused below the fewest the sign test can decide on.
CLI::Validator enough_rounds_to_decide() {
  const int fewest = sign_test_min_pairs(CompareSettings{}.rules.alpha);
  const std::string range = "an integer in [" + std::to_string(fewest) + ", 100000]";
  return CLI::Validator(
      [fewest, range](std::string& text) -> std::string {
        int rounds = 0;
        if (!CLI::detail::lexical_cast(text, rounds) || rounds > 100'000) return "expected " + range + ", got " + text;
        if (rounds < fewest) return "expected " + range + "; " + too_few_rounds(rounds);
        return {};
      },
      range);
}

}  // namespace

void register_ab(CLI::App& app, const std::string& command_line, int& exit_status) {
  auto options = std::make_shared<AbOptions>();
  CLI::App* ab = app.add_subcommand(
      "ab", "Time two builds of one engine back to back in one process and judge B against A");
  const std::string build_help =
      "a plugin file, a build directory holding libfx2d_bench_plugin.so, `worktree`, a git revision, or `built-in` "
      "(this binary's own Fx2D)";
  ab->add_option("--a", options->a, "Build A (the reference): " + build_help)->required();
  ab->add_option("--b", options->b, "Build B (judged against A): " + build_help)->required();
  ab->add_option("--a-cmake", options->a_cmake, "Extra CMake arguments for building A, e.g. \"-DFX2D_NATIVE=ON\"");
  ab->add_option("--b-cmake", options->b_cmake, "Extra CMake arguments for building B");
  ab->add_option("--source", options->source,
                 "The Fx2D source tree whose harness/plugin builds a revision or the worktree (default: $FX2D_SOURCE, "
                 "else the tree this fx2d-bench was built from, while it is there)");
  options->scenes.add_to(*ab, "pile");
  ab->add_option("--rounds", options->plan.rounds, "Timed rounds per build, in the order A B B A A B B A ...")
      ->check(enough_rounds_to_decide())
      ->capture_default_str();
  ab->add_option("--time-budget", options->plan.time_budget_s,
                 "Stop the rounds earlier, once measuring has taken this many seconds (shared by the scenes)")
      ->check(CLI::Range(0.001, 1e7));
  ab->add_option("--counter", options->counter,
                 "Also count each build's step loop exactly: 'instructions' runs each plugin once more under callgrind")
      ->check(CLI::IsMember({"instructions"}));
  CLI::Option* out = ab->add_option("--out", options->out, "Write both builds' samples to this HDF5 file (fx2d@A, fx2d@B)");
  ab->add_flag("--force", options->force, "Overwrite the --out file if it exists")->needs(out);
  CLI::Option* json = ab->add_flag("--json", options->json, "Print the verdict as JSON (fx2d-bench.compare/1)");
  ab->add_flag("--markdown", options->markdown, "Print the verdict as Markdown")->excludes(json);
  ab->callback([options, command_line, &exit_status] { exit_status = ab_command(*options, command_line); });
}

}  // namespace fxbench

// `fx2d-bench run`: times each selected engine on each scene and reports speed and accuracy as a
// table, as JSON (`--json`), and as an HDF5 result file (`--out`).
//
// Reads top to bottom: the options, the checks made before anything is measured (an existing
// --out without --force, valgrind missing for --counter), the measurement of every scene x engine
// in registry order, the engines of one scene in interleaved rounds (runner.h holds the
// measurement invariants and interleave.h those of the rounds; with --counter instructions each
// timed run is then counted in a child under callgrind, instruction_counter.h), then the output.
// Nothing here prints to stderr but the progress bar, which is drawn only when stderr is a
// terminal.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "format/summary_format.h"
#include "measure/clocks.h"
#include "measure/instruction_counter.h"
#include "measure/interleave.h"
#include "measure/interrupt.h"
#include "measure/provenance.h"
#include "measure/runner.h"
#include "storage/h5_tables.h"
#include "storage/results_h5.h"

namespace fxbench {
namespace {

struct RunOptions {
  SceneOptions scenes;
  EngineOptions engines;
  ShardOptions shard;
  RunPlan plan;
  CLI::Option* warmup_option = nullptr;
  bool json = false;
  std::string out;
  bool force = false;
  std::string counter;  // "instructions": also count each run's step loop under callgrind
};

// One line on stderr, redrawn in place: engine, scene, repeat, share done, time left.
class ProgressBar {
 public:
  explicit ProgressBar(long total_steps) : enabled_(isatty(STDERR_FILENO) == 1), total_steps_(total_steps) {}

  // The callback for one run, which starts after `steps_before` steps of earlier runs.
  ProgressFn for_run(long steps_before) {
    if (!enabled_) return {};
    return [this, steps_before](const RunProgress& progress) { draw(progress, steps_before + progress.steps_done); };
  }

  void finish() const {
    if (enabled_) std::fputs("\r\x1b[K", stderr);
  }

 private:
  void draw(const RunProgress& progress, long steps_done) const {
    const double done = total_steps_ > 0 ? static_cast<double>(steps_done) / static_cast<double>(total_steps_) : 1.0;
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    constexpr int width = 20;
    const auto filled = static_cast<int>(std::lround(done * width));
    const std::string bar = std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(width - filled), '.');
    const std::string repeat = progress.repeat == 0 ? std::string("warm-up")
                                                    : "repeat " + std::to_string(progress.repeat) + "/" +
                                                          std::to_string(progress.repeats);
    const std::string eta = steps_done > 0 ? std::to_string(std::lround(elapsed_s * (1.0 - done) / done)) + "s" : "--";
    std::fprintf(stderr, "\r\x1b[K%.*s %.*s %s [%s] %3.0f%% ETA %s", static_cast<int>(progress.engine.size()),
                 progress.engine.data(), static_cast<int>(progress.scene.size()), progress.scene.data(), repeat.c_str(),
                 bar.c_str(), 100.0 * done, eta.c_str());
    std::fflush(stderr);
  }

  bool enabled_;
  long total_steps_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Times `engines` on `scene`: one alone, repeat after repeat; several in rounds, each round one
// repeat of every engine, forward then backward through them (interleave.h), so that a drift in
// the machine's speed over the run lands on every engine alike and their ratio stands. One record
// per engine, in their order.
std::vector<RunRecord> measure_engines(const SceneSpec& scene, std::span<const EngineInfo* const> engines,
                                       const RunPlan& plan, ProgressBar& progress, long steps_before) {
  if (engines.size() == 1) return {measure_engine(scene, *engines[0], plan, progress.for_run(steps_before))};
  const InterleavePlan rounds{plan.repeats, 0.0, plan.warmup_steps, plan.hash_every, plan.accuracy_every};
  std::vector<TimedCell> cells;
  for (const EngineInfo* engine : engines) cells.push_back({&scene, engine});
  long steps_done = 0;
  const TurnProgressFn each_round = [&](std::size_t engine, int round) {
    const ProgressFn draw = progress.for_run(steps_before + steps_done);
    if (draw) draw({engines[engine]->name, scene.name, round + 1, plan.repeats, 0});
    steps_done += scene.steps + (round == 0 ? plan.warmup_steps : 0);
  };
  RoundRobinRuns runs = measure_round_robin(cells, rounds, each_round);
  return std::move(runs.runs);
}

SceneRecord scene_record(const SceneSpec& scene) {
  const char* metric = scene.primary_metric == PrimaryMetric::displacement ? "displacement" : "penetration";
  return {scene.name, scene.hash, scene.resolved_json, scene.source_path, metric};
}

// The plan for one scene: the warm-up defaults to one full discarded trajectory.
RunPlan plan_for(const RunOptions& options, const SceneSpec& scene) {
  RunPlan plan = options.plan;
  if (options.warmup_option->count() == 0) plan.warmup_steps = scene.steps;
  return plan;
}

// Refuses an --out that could not be written, before any measurement is spent on it.
void check_out_path(const RunOptions& options) {
  if (options.out.empty()) return;
  if (!options.force && std::filesystem::exists(options.out))
    throw InputError(options.out + ": exists; pass --force to overwrite it");
  const std::filesystem::path directory = std::filesystem::path(options.out).parent_path();
  if (!directory.empty() && !std::filesystem::is_directory(directory))
    throw InputError(options.out + ": no such directory " + directory.string());
}

// Every timed step keeps about 60 bytes of samples (more with a phase split); refuse a plan whose
// samples would not fit in memory before measuring anything, rather than failing at the end.
void check_sample_budget(const std::vector<SceneSpec>& scenes, const RunOptions& options) {
  constexpr long long max_samples = 100'000'000;  // about 6 GB of per-step records
  for (const SceneSpec& scene : scenes) {
    const long long samples = static_cast<long long>(plan_for(options, scene).repeats) * scene.steps;
    if (samples > max_samples) {
      throw InputError("--repeats x --steps: " + std::to_string(samples) + " timed steps for scene " + scene.name +
                       ", expected at most " + std::to_string(max_samples));
    }
  }
}

// The name the counting child looks `engine` up by: as it was given on the command line, since an
// engine loaded by name (a plugin) may carry another name in its entry; a registry engine's own.
std::string lookup_name(const EngineOptions& options, const EngineInfo& engine) {
  for (const std::string& name : options.names)
    if (find_engine(name) == &engine) return name;
  return engine.name;
}

// Each scene with the engines that run it, settled before anything is measured: an engine that
// cannot build a scene is refused or skipped now (EngineOptions::able_to_build), never after the
// engines before it have been measured.
struct SceneEngines {
  SceneSpec scene;
  std::vector<const EngineInfo*> engines;
};

std::vector<SceneEngines> plan_engines(std::vector<SceneSpec> scenes, const EngineOptions& options) {
  std::vector<SceneEngines> planned;
  for (SceneSpec& scene : scenes) {
    std::vector<const EngineInfo*> engines = options.able_to_build(scene);
    planned.push_back({std::move(scene), std::move(engines)});
  }
  return planned;
}

// The scene x engine cells of the whole run, in the order measured: what --shard splits, each cell
// costing bodies x planned steps, and the identity merge checks.
struct Cells {
  std::vector<double> costs;
  std::string identity;
};

Cells cells_of(const std::vector<SceneEngines>& planned, const RunOptions& options) {
  Cells cells;
  const RunPlan& plan = options.plan;
  std::vector<std::string> keys{"run repeats=" + std::to_string(plan.repeats) + " hash_every=" +
                                std::to_string(plan.hash_every) + " accuracy_every=" +
                                std::to_string(plan.accuracy_every) + " counter=" + options.counter};
  for (const auto& [scene, engines] : planned)
    for (const EngineInfo* engine : engines) {
      const RunPlan scene_plan = plan_for(options, scene);
      cells.costs.push_back(static_cast<double>(std::max(1, bodies_of(scene))) * static_cast<double>(planned_steps(scene, scene_plan)));
      keys.push_back(scene.hash + " " + engine->name + " warmup=" + std::to_string(scene_plan.warmup_steps));
    }
  cells.identity = work_list_identity(keys);
  return cells;
}

// A shard's file: the runs as usual, and /shard saying which cells they are (RESULTS_FORMAT.md).
void write_shard_file(const ResultSet& results, const Shard& shard, const Cells& cells,
                      const std::vector<std::size_t>& mine, const std::string& out, bool force) {
  std::vector<std::int32_t> items;
  for (std::size_t item : mine) items.push_back(static_cast<std::int32_t>(item));
  const H5Table table{"/shard",
                      {{"shard", shard.text()},
                       {"work_items", static_cast<std::int32_t>(cells.costs.size())},
                       {"work_list", cells.identity}},
                      {{"work_item", "index", items}}};
  write_results_with_tables_h5(results, std::span(&table, 1), out, force);
}

void run_command(const RunOptions& options, const std::string& command_line) {
  check_out_path(options);
  // instruction_counter.h: refuses before anything is measured when valgrind cannot run.
  const std::optional<InstructionCounter> counter =
      options.counter.empty() ? std::nullopt : std::optional<InstructionCounter>(std::in_place);
  const ScopedInterruptHandler interrupts;  // interrupt.h: Ctrl-C saves what was measured
  std::vector<SceneSpec> scenes = options.scenes.load();
  check_sample_budget(scenes, options);
  const std::vector<SceneEngines> planned = plan_engines(std::move(scenes), options.engines);
  const Shard shard = options.shard.shard();
  const Cells cells = cells_of(planned, options);
  const std::vector<std::size_t> mine = items_of(shard, cells.costs);
  const auto is_mine = [&](std::size_t cell) { return std::ranges::binary_search(mine, cell); };

  ResultSet results;
  results.provenance = collect_provenance(command_line, measure_counter_ghz());
  long total_steps = 0;
  std::size_t cell = 0;
  for (const auto& [scene, engines] : planned)
    for (std::size_t e = 0; e < engines.size(); ++e)
      if (is_mine(cell++)) total_steps += planned_steps(scene, plan_for(options, scene));

  ProgressBar progress(total_steps);
  long steps_before = 0;
  cell = 0;
  for (const auto& [scene, engines] : planned) {
    if (results.partial) break;  // interrupt.h
    // Unsharded, a scene no engine can build is still recorded; a shard records the scenes it ran.
    const auto first_mine = std::ranges::lower_bound(mine, cell);  // mine is sorted
    const bool scene_is_mine = first_mine != mine.end() && *first_mine < cell + engines.size();
    if ((shard.count == 1 || scene_is_mine) &&
        std::ranges::find(results.scenes, scene.hash, &SceneRecord::hash) == results.scenes.end())
      results.scenes.push_back(scene_record(scene));
    const RunPlan plan = plan_for(options, scene);
    std::vector<const EngineInfo*> timed;
    for (const EngineInfo* engine : engines)
      if (is_mine(cell++)) timed.push_back(engine);
    std::vector<RunRecord> runs = measure_engines(scene, timed, plan, progress, steps_before);
    // interrupt.h: only a SIGINT cuts a run short; every repeat measured before it is kept.
    results.partial =
        std::ranges::any_of(runs, [&](const RunRecord& run) { return run.repeats < plan.repeats; });
    for (std::size_t e = 0; e < runs.size(); ++e) {
      RunRecord& run = runs[e];
      if (counter && !results.partial) {
        run.instruction_count = counter->count(scene, lookup_name(options.engines, *timed[e]));
        results.partial = !run.instruction_count;  // interrupt.h: the SIGINT stopped the counting child
      }
      if (run.repeats > 0) results.runs.push_back(std::move(run));
    }
    steps_before += static_cast<long>(timed.size()) * planned_steps(scene, plan);
  }
  progress.finish();
  finish_provenance(results.provenance);

  if (options.json)
    std::cout << summary_json(results).dump(2) << '\n';
  else
    std::cout << summary_table(results);
  std::cout.flush();
  // interrupt.h: a partial result never takes the final name, and replaces an older partial one.
  const std::string out = results.partial && !options.out.empty() ? options.out + ".partial.h5" : options.out;
  if (!out.empty() && shard.count > 1 && !results.partial)
    write_shard_file(results, shard, cells, mine, out, options.force);
  else if (!out.empty())
    write_results_h5(results, out, options.force || results.partial);
  if (results.partial)
    exit_after_interrupt("interrupted; " + std::to_string(results.runs.size()) + " run(s) measured so far " +
                         (out.empty() ? std::string("not saved (no --out)") : "saved to " + out));
}

}  // namespace

void register_run(CLI::App& app, const std::string& command_line) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* run = app.add_subcommand("run", "Time engines on scenes and measure their accuracy");
  options->scenes.add_to(*run, "pile");
  options->engines.add_to(*run);
  options->shard.add_to(*run);
  run->add_option("--repeats", options->plan.repeats, "Timed repeats, each from a freshly built scene")
      ->check(CLI::Range(1, 100'000))
      ->capture_default_str();
  options->warmup_option =
      run->add_option("--warmup", options->plan.warmup_steps,
                      "Untimed warm-up steps on a discarded instance (default: one full trajectory)")
          ->check(CLI::Range(0, 10'000'000));
  run->add_option("--hash-every", options->plan.hash_every, "State hash after every N-th step, and after the last")
      ->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  run->add_option("--accuracy-every", options->plan.accuracy_every,
                  "Accuracy sample after every N-th step, and after the last")
      ->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  run->add_flag("--json", options->json, "Print the summary as one JSON object (fx2d-bench.summary/1)");
  run->add_option("--counter", options->counter,
                  "Also count each run's step loop exactly: 'instructions' runs it once more under valgrind's callgrind")
      ->check(CLI::IsMember({"instructions"}));
  CLI::Option* out = run->add_option("--out", options->out, "Write every sample to this HDF5 file (fx2d-bench.results/1)");
  run->add_flag("--force", options->force, "Overwrite the --out file if it exists")->needs(out);
  run->callback([options, command_line] { run_command(*options, command_line); });
}

}  // namespace fxbench

// `fx2d-bench stability`: where each engine's solver breaks. For every selected engine and test of
// the suite (stability_tests.h), a bracketing search with bisection finds the hardest stress
// parameter the engine survives, and the result is printed as a table, as JSON
// (`fx2d-bench.stability/1`) and written to HDF5 (`/stability`, harness/RESULTS_FORMAT.md).
//
// Reads top to bottom: the options, the search of one engine x test (each evaluation loads the
// test's scene file with the user's --set and then the parameter's overrides, simulates it untimed
// and judges the sampled poses: stability_tests.h; or one piece of it, when --shard spreads a
// search over shards: stability_pieces.h), the search of every engine x test, then the
// outputs (format/stability_format.h). Nothing is timed, so the table depends only on the engines and the build, never on the
// machine's load.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "analysis/stability_costs.h"
#include "analysis/stability_pieces.h"
#include "analysis/stability_tests.h"
#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "format/stability_format.h"
#include "measure/clocks.h"
#include "measure/provenance.h"
#include "storage/h5_tables.h"

namespace fxbench {
namespace {

struct StabilityOptions {
  EngineOptions engines;
  ShardOptions shard;
  std::vector<std::string> tests;  // empty: the whole suite
  std::vector<std::string> sets;
  std::string suite_dir = FX2D_BENCH_STABILITY_DIR;
  bool quick = false;
  bool json = false;
  std::string out;
  bool force = false;
};

// Every engine x test pair the command would search unsharded, in that order (engine-major):
// what --shard splits, by stability_cost, and what the file records for merge.
struct WorkList {
  std::vector<EngineTest> pairs;
  std::vector<double> costs;
  std::vector<bool> spreadable;  // whose boundary is predicted (stability_costs.h): analysis/stability_pieces.h
  std::string identity;  // work_list_identity of the settings and every pair's key
};

std::vector<std::pair<std::string, std::string>> user_sets(const std::vector<std::string>& sets) {
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const std::string& assignment : sets) {
    const auto equals = assignment.find('=');
    if (equals == std::string::npos) throw InputError("--set " + assignment + ": expected /json/pointer=value");
    pairs.emplace_back(assignment.substr(0, equals), assignment.substr(equals + 1));
  }
  return pairs;
}

std::string assignments_text(const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::string text;
  for (const auto& [pointer, value] : overrides) text += (text.empty() ? "--set '" : " --set '") + pointer + "=" + value + "'";
  return text;
}

void show_progress(const EngineInfo& engine, const StabilityTest& test, double parameter) {
  if (isatty(STDERR_FILENO) != 1) return;
  std::fprintf(stderr, "\r\x1b[Kstability: %s %s %s = %g", engine.name.c_str(), test.name.c_str(), test.parameter.c_str(),
               parameter);
  std::fflush(stderr);
}

// The probes of one engine x test: each parameter's scene loaded with the user's --set, the
// engine's settings noted from the first.
class PairProbes {
 public:
  PairProbes(const StabilityOptions& options, const EngineInfo& engine, const StabilityTest& test, std::string& settings)
      : options_(options), engine_(engine), test_(test), settings_(settings), sets_(user_sets(options.sets)) {}

  Verdict evaluate(double parameter) {
    show_progress(engine_, test_, parameter);
    const auto [scene, refusal] = scene_of(parameter);
    if (refusal) return *refusal;
    return test_.judge(*scene, simulate(*scene, engine_, test_.sample_every, test_.settled_failure));
  }

  // stability_probe_cost of the probe's scene; nothing when the engine cannot build it.
  double cost(double parameter, bool passes) {
    const auto [scene, refusal] = scene_of(parameter);
    return refusal ? 0.0 : stability_probe_cost(*scene, engine_.name, !passes && test_.settled_failure != nullptr);
  }

 private:
  // The parameter's scene, or the verdict when the engine cannot build it: a stress the test's
  // engine_limit does not foresee is where it stops holding.
  std::pair<std::optional<SceneSpec>, std::optional<Verdict>> scene_of(double parameter) {
    SceneSpec scene = load_test_scene(test_, options_.suite_dir, sets_, parameter);
    if (settings_.empty()) settings_ = engine_settings_json(engine_, scene);
    if (const std::optional<std::string> missing = missing_capability(engine_.capabilities, scene))
      return {std::nullopt, Verdict{false, engine_.name + " cannot build " + *missing, "cannot_build", std::nullopt}};
    return {std::move(scene), std::nullopt};
  }

  const StabilityOptions& options_;
  const EngineInfo& engine_;
  const StabilityTest& test_;
  std::string& settings_;
  std::vector<std::pair<std::string, std::string>> sets_;
};

// Piece `piece.piece` of the search of one engine x test, or the whole search when it has one piece.
TestResult search_test(const StabilityOptions& options, const EngineInfo& engine, const StabilityTest& test, const ItemPiece& piece) {
  TestResult outcome{&engine, &test, test.search, {}, {}, {}, piece.item, piece.piece, piece.pieces};
  if (options.quick) outcome.search.limit = test.quick_limit;
  PairProbes probes(options, engine, test, outcome.settings);
  if (piece.pieces == 1) {
    outcome.result = find_engine_boundary(test, outcome.search, engine.capabilities,
                                          [&](double parameter) { return probes.evaluate(parameter); });
  } else {
    const std::optional<double> last_pass = stability_last_pass(test.name, engine.name);
    const ProbeSource source{[&](double parameter) { return last_pass && !is_harder(test.search, parameter, *last_pass); },
                             [&](double parameter) { return probes.evaluate(parameter); },
                             [&](double parameter, bool passes) { return probes.cost(parameter, passes); }};
    outcome.result.evaluations = search_piece(test, outcome.search, engine.capabilities, piece.piece, piece.pieces, source);
  }
  for (const Evaluation& evaluation : outcome.result.evaluations)
    outcome.overrides.push_back(assignments_text(test.overrides(evaluation.parameter)));
  return outcome;
}

std::vector<const StabilityTest*> selected_tests(const StabilityOptions& options) {
  std::vector<const StabilityTest*> tests;
  for (const StabilityTest& test : stability_suite())
    if (options.tests.empty() || std::ranges::find(options.tests, test.name) != options.tests.end()) tests.push_back(&test);
  return tests;
}

WorkList work_list_of(const StabilityOptions& options, const std::vector<const EngineInfo*>& engines,
                      const std::vector<const StabilityTest*>& tests, const std::vector<SceneSpec>& start_scenes) {
  std::vector<std::vector<const EngineInfo*>> able;
  for (const SceneSpec& scene : start_scenes) able.push_back(options.engines.able_to_build(scene));
  WorkList work;
  std::vector<std::string> keys{std::string("stability quick=") + (options.quick ? "1" : "0")};
  for (const std::string& set : options.sets) keys.push_back("--set " + set);
  for (const EngineInfo* engine : engines)
    for (std::size_t t = 0; t < tests.size(); ++t) {
      if (std::ranges::find(able[t], engine) == able[t].end()) continue;
      work.pairs.emplace_back(engine, tests[t]);
      work.costs.push_back(stability_cost(tests[t]->name, engine->name));
      work.spreadable.push_back(stability_last_pass(tests[t]->name, engine->name).has_value());
      keys.push_back(engine->name + " " + engine->version + " " + tests[t]->name + " " + start_scenes[t].hash);
    }
  work.identity = work_list_identity(keys);
  return work;
}

void stability_command(const StabilityOptions& options, const std::string& command_line) {
  if (!options.out.empty() && !options.force && std::filesystem::exists(options.out))
    throw InputError(options.out + ": exists; pass --force to overwrite it");
  const std::vector<const EngineInfo*> engines = options.engines.selected();
  const std::vector<const StabilityTest*> tests = selected_tests(options);
  const Shard shard = options.shard.shard();
  // Which engines can build each test's scene, settled before any search starts.
  std::vector<SceneSpec> start_scenes;
  for (const StabilityTest* test : tests)
    start_scenes.push_back(load_test_scene(*test, options.suite_dir, user_sets(options.sets), test->search.start));
  const WorkList work = work_list_of(options, engines, tests, start_scenes);
  ResultSet file;  // what --out is given, its provenance taken before the searches
  if (!options.out.empty()) file.provenance = collect_provenance(command_line, measure_counter_ghz());
  std::vector<TestResult> results;
  for (const ItemPiece& piece : pieces_of(shard, work.costs, work.spreadable))
    results.push_back(search_test(options, *work.pairs[piece.item].first, *work.pairs[piece.item].second, piece));
  if (isatty(STDERR_FILENO) == 1) std::fputs("\r\x1b[K", stderr);

  if (options.json)
    std::cout << stability_json(results, tests, options.quick).dump(2) << '\n';
  else
    std::cout << stability_table(results, work.pairs, engines, tests);
  std::cout.flush();
  if (options.out.empty()) return;
  finish_provenance(file.provenance);
  std::vector<H5Table> tables = stability_tables(results, options.quick);
  tables.front().attributes.insert(tables.front().attributes.end(),
                                   {{"shard", shard.text()},
                                    {"work_items", static_cast<std::int32_t>(work.pairs.size())},
                                    {"work_list", work.identity}});
  write_results_with_tables_h5(file, tables, options.out, options.force);
}

}  // namespace

void register_stability(CLI::App& app, const std::string& command_line) {
  auto options = std::make_shared<StabilityOptions>();
  CLI::App* stability = app.add_subcommand("stability", "Find where each engine's solver breaks, test by test");
  options->engines.add_to(*stability);
  options->shard.add_to(*stability);
  std::vector<std::string> names;
  for (const StabilityTest& test : stability_suite()) names.push_back(test.name);
  stability->add_option("--test", options->tests, "Tests to run, comma-separated (default: all)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->check(CLI::IsMember(names));
  stability->add_option("--set", options->sets, "Override a field of every test scene, e.g. --set /solver/fx2d/substeps=4")
      ->allow_extra_args(false);
  stability->add_option("--suite", options->suite_dir, "Directory of the suite's scene files")
      ->check(CLI::ExistingDirectory)
      ->capture_default_str();
  stability->add_flag("--quick", options->quick, "Search up to each test's lower quick limit");
  stability->add_flag("--json", options->json, "Print one JSON object (fx2d-bench.stability/1)");
  CLI::Option* out = stability->add_option("--out", options->out, "Write the /stability table to this HDF5 file");
  stability->add_flag("--force", options->force, "Overwrite the --out file if it exists")->needs(out);
  stability->callback([options, command_line] { stability_command(*options, command_line); });
}

}  // namespace fxbench

// `fx2d-bench stability`: where each engine's solver breaks. For every selected engine and test of
// the suite (stability_tests.h), a bracketing search with bisection finds the hardest stress
// parameter the engine survives, and the result is printed as a table, as JSON
// (`fx2d-bench.stability/1`) and written to HDF5 (`/stability`, harness/RESULTS_FORMAT.md).
//
// Reads top to bottom: the options, the search of one engine x test (each evaluation loads the
// test's scene file with the user's --set and then the parameter's overrides, simulates it untimed
// and judges the sampled poses: stability_tests.h), the search of every engine x test, then the
// outputs. Nothing is timed, so the table depends only on the engines and the build, never on the
// machine's load.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "analysis/stability_costs.h"
#include "analysis/stability_tests.h"
#include "commands/cli_options.h"
#include "commands/commands.h"
#include "common/errors.h"
#include "format/text_table.h"
#include "measure/clocks.h"
#include "measure/provenance.h"
#include "storage/h5_tables.h"

namespace fxbench {
namespace {

inline constexpr const char* stability_schema = "fx2d-bench.stability/1";

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

struct TestResult {
  const EngineInfo* engine = nullptr;
  const StabilityTest* test = nullptr;
  SearchSpec search;          // as run: the limit is the quick one under --quick
  std::string settings;       // the engine's /solver entry of the resolved scene, as compact JSON
  SearchResult result;
  std::vector<std::string> overrides;  // per evaluation, the --set assignments of its parameter
  std::size_t work_item = 0;           // the pair's index in the whole work list
};

// Every engine x test pair the command would search unsharded, in that order (engine-major):
// what --shard splits, by stability_cost, and what the file records for merge.
struct WorkList {
  std::vector<std::pair<const EngineInfo*, const StabilityTest*>> pairs;
  std::vector<double> costs;
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

TestResult search_test(const StabilityOptions& options, const EngineInfo& engine, const StabilityTest& test) {
  TestResult outcome{&engine, &test, test.search, {}, {}, {}};
  if (options.quick) outcome.search.limit = test.quick_limit;
  const auto sets = user_sets(options.sets);
  const auto evaluate = [&](double parameter) {
    show_progress(engine, test, parameter);
    outcome.overrides.push_back(assignments_text(test.overrides(parameter)));
    const SceneSpec scene = load_test_scene(test, options.suite_dir, sets, parameter);
    if (outcome.settings.empty()) outcome.settings = engine_settings_json(engine, scene);
    // A stress the engine cannot build that the test's engine_limit does not foresee is where it
    // stops holding.
    if (const std::optional<std::string> missing = missing_capability(engine.capabilities, scene))
      return Verdict{false, engine.name + " cannot build " + *missing, "cannot_build", std::nullopt};
    return test.judge(scene, simulate(scene, engine, test.sample_every));
  };
  const bool capped = test.engine_limit && test.engine_limit(engine.capabilities) < outcome.search.limit;
  if (capped) outcome.search.limit = test.engine_limit(engine.capabilities);
  outcome.result = find_boundary(outcome.search, evaluate);
  if (capped && outcome.result.outcome == Outcome::holds_to_limit) outcome.result.outcome = Outcome::engine_limit;
  return outcome;
}

std::vector<const StabilityTest*> selected_tests(const StabilityOptions& options) {
  std::vector<const StabilityTest*> tests;
  for (const StabilityTest& test : stability_suite())
    if (options.tests.empty() || std::ranges::find(options.tests, test.name) != options.tests.end()) tests.push_back(&test);
  return tests;
}

std::string value_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// "41" for a boundary (the hardest value that passed); the limit with ">=" or "<=" when nothing
// failed; the start with "fails at" when even that failed.
std::string cell(const TestResult& outcome) {
  const bool increasing = outcome.search.harder == Harder::increasing;
  switch (outcome.result.outcome) {
    case Outcome::boundary: return value_text(*outcome.result.last_pass);
    case Outcome::holds_to_limit: return (increasing ? ">= " : "<= ") + value_text(outcome.search.limit) + " (limit)";
    case Outcome::fails_at_start: return "fails at " + value_text(outcome.search.start);
    case Outcome::engine_limit: return "engine limit at " + value_text(outcome.search.limit);
  }
  return {};
}

// The verdict of the easiest value that failed: what failed first there, and when.
Verdict first_failure(const SearchResult& result) {
  for (const Evaluation& evaluation : result.evaluations)
    if (result.first_fail && evaluation.parameter == *result.first_fail) return evaluation.verdict;
  return {};
}

// One line per engine and test that failed: at which value, which criterion, at which step, why.
std::string failures_of(const std::vector<TestResult>& results, const std::vector<const EngineInfo*>& engines,
                        const std::vector<const StabilityTest*>& tests) {
  std::vector<std::vector<std::string>> rows;
  for (const EngineInfo* engine : engines)
    for (const StabilityTest* test : tests)
      for (const TestResult& outcome : results) {
        if (outcome.engine != engine || outcome.test != test || !outcome.result.first_fail) continue;
        const Verdict failure = first_failure(outcome.result);
        rows.push_back({engine->name, test->name, "at " + value_text(*outcome.result.first_fail) + ":", failure.criterion,
                        failure.step ? "step " + std::to_string(*failure.step) : "", failure.reason});
      }
  return rows.empty() ? std::string() : "what failed first:\n" + aligned_columns(rows);
}

std::string table_of(const std::vector<TestResult>& results, const WorkList& work, const std::vector<const EngineInfo*>& engines,
                     const std::vector<const StabilityTest*>& tests) {
  std::vector<std::vector<std::string>> rows{{"test", "parameter"}};
  for (const EngineInfo* engine : engines) rows.front().push_back(engine->name);
  for (const StabilityTest* test : tests) {
    const bool increasing = test->search.harder == Harder::increasing;
    rows.push_back({test->name, test->parameter + " (" + test->units + ", " + (increasing ? "higher" : "lower") + " is better)"});
    for (const EngineInfo* engine : engines) {
      const auto outcome = std::ranges::find_if(
          results, [&](const TestResult& result) { return result.engine == engine && result.test == test; });
      const bool listed = std::ranges::find(work.pairs, std::pair{engine, test}) != work.pairs.end();
      rows.back().push_back(outcome != results.end() ? cell(*outcome) : listed ? "other shard" : "cannot build");
    }
  }
  std::string text = aligned_columns(rows) + failures_of(results, engines, tests);
  for (const EngineInfo* engine : engines)
    for (const TestResult& outcome : results)
      if (outcome.engine == engine) {
        text += engine->name + " " + engine->version + " settings: " + outcome.settings + "\n";
        break;
      }
  return text;
}

nlohmann::ordered_json optional_json(const std::optional<double>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json step_json(const std::optional<int>& step) {
  return step ? nlohmann::ordered_json(*step) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json json_of(const std::vector<TestResult>& results, const std::vector<const StabilityTest*>& tests,
                               bool quick) {
  nlohmann::ordered_json suite = nlohmann::ordered_json::array();
  for (const StabilityTest* test : tests) {
    suite.push_back({{"name", test->name},
                     {"parameter", test->parameter},
                     {"units", test->units},
                     {"harder", test->search.harder == Harder::increasing ? "increasing" : "decreasing"},
                     {"criterion", test->criterion}});
  }
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const TestResult& outcome : results) {
    nlohmann::ordered_json evaluations = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < outcome.result.evaluations.size(); ++i) {
      const Evaluation& evaluation = outcome.result.evaluations[i];
      evaluations.push_back({{"parameter", evaluation.parameter},
                             {"pass", evaluation.verdict.pass},
                             {"reason", evaluation.verdict.reason},
                             {"criterion", evaluation.verdict.criterion},
                             {"step", step_json(evaluation.verdict.step)},
                             {"overrides", outcome.overrides[i]}});
    }
    rows.push_back({{"engine", outcome.engine->name},
                    {"engine_version", outcome.engine->version},
                    {"settings", nlohmann::ordered_json::parse(outcome.settings)},
                    {"test", outcome.test->name},
                    {"start", outcome.search.start},
                    {"limit", outcome.search.limit},
                    {"resolution", outcome.search.resolution},
                    {"scale", outcome.search.scale == Scale::linear ? "linear" : "geometric"},
                    {"outcome", to_string(outcome.result.outcome)},
                    {"last_pass", optional_json(outcome.result.last_pass)},
                    {"first_fail", optional_json(outcome.result.first_fail)},
                    {"failure", first_failure(outcome.result).reason},
                    {"failed_criterion", first_failure(outcome.result).criterion},
                    {"failed_step", step_json(first_failure(outcome.result).step)},
                    {"evaluations", evaluations}});
  }
  return {{"schema", stability_schema}, {"quick", quick}, {"tests", suite}, {"results", rows}};
}

template <class T, class Field>
H5Column column(const std::vector<TestResult>& results, std::string name, std::string units, Field field) {
  std::vector<T> values;
  for (const TestResult& outcome : results) values.push_back(static_cast<T>(field(outcome)));
  return {std::move(name), std::move(units), std::move(values)};
}

std::vector<H5Table> tables_h5(const std::vector<TestResult>& results, bool quick) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  using R = const TestResult&;
  H5Table summary{
      "/stability",
      {{"schema", std::string(stability_schema)}, {"quick", static_cast<std::int32_t>(quick)}},
      {
          column<std::string>(results, "engine", "", [](R r) { return r.engine->name; }),
          column<std::string>(results, "engine_version", "", [](R r) { return r.engine->version; }),
          column<std::string>(results, "settings", "", [](R r) { return r.settings; }),
          column<std::string>(results, "test", "", [](R r) { return r.test->name; }),
          column<std::string>(results, "parameter", "", [](R r) { return r.test->parameter; }),
          column<std::string>(results, "units", "", [](R r) { return r.test->units; }),
          column<std::string>(results, "harder", "", [](R r) {
            return std::string(r.search.harder == Harder::increasing ? "increasing" : "decreasing");
          }),
          column<double>(results, "start", "parameter", [](R r) { return r.search.start; }),
          column<double>(results, "limit", "parameter", [](R r) { return r.search.limit; }),
          column<double>(results, "resolution", "parameter", [](R r) { return r.search.resolution; }),
          column<std::string>(results, "scale", "", [](R r) {
            return std::string(r.search.scale == Scale::linear ? "linear" : "geometric");
          }),
          column<std::string>(results, "outcome", "", [](R r) { return to_string(r.result.outcome); }),
          column<double>(results, "last_pass", "parameter", [&](R r) { return r.result.last_pass.value_or(none); }),
          column<double>(results, "first_fail", "parameter", [&](R r) { return r.result.first_fail.value_or(none); }),
          column<std::string>(results, "failure", "", [](R r) { return first_failure(r.result).reason; }),
          column<std::string>(results, "failed_criterion", "", [](R r) { return first_failure(r.result).criterion; }),
          column<std::int32_t>(results, "failed_step", "step", [](R r) { return first_failure(r.result).step.value_or(-1); }),
          column<std::int32_t>(results, "first_evaluation", "index", [&](R r) {
            std::size_t first = 0;
            for (const TestResult& other : results) {
              if (&other == &r) break;
              first += other.result.evaluations.size();
            }
            return first;
          }),
          column<std::int32_t>(results, "evaluation_count", "count", [](R r) { return r.result.evaluations.size(); }),
          column<std::int32_t>(results, "work_item", "index", [](R r) { return r.work_item; }),
      }};
  std::vector<std::int32_t> owner;
  std::vector<double> parameter;
  std::vector<std::uint8_t> pass;
  std::vector<std::string> reason;
  std::vector<std::string> overrides;
  for (std::size_t row = 0; row < results.size(); ++row) {
    for (std::size_t i = 0; i < results[row].result.evaluations.size(); ++i) {
      const Evaluation& evaluation = results[row].result.evaluations[i];
      owner.push_back(static_cast<std::int32_t>(row));
      parameter.push_back(evaluation.parameter);
      pass.push_back(evaluation.verdict.pass ? 1 : 0);
      reason.push_back(evaluation.verdict.reason);
      overrides.push_back(results[row].overrides[i]);
    }
  }
  H5Table evaluations{"/stability/evaluations",
                      {},
                      {{"row", "index", owner},
                       {"parameter", "parameter", parameter},
                       {"pass", "flag", pass},
                       {"reason", "", reason},
                       {"overrides", "", overrides}}};
  return {std::move(summary), std::move(evaluations)};
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
  std::vector<TestResult> results;
  for (std::size_t item : items_of(shard, work.costs)) {
    results.push_back(search_test(options, *work.pairs[item].first, *work.pairs[item].second));
    results.back().work_item = item;
  }
  if (isatty(STDERR_FILENO) == 1) std::fputs("\r\x1b[K", stderr);

  if (options.json)
    std::cout << json_of(results, tests, options.quick).dump(2) << '\n';
  else
    std::cout << table_of(results, work, engines, tests);
  std::cout.flush();
  if (options.out.empty()) return;
  ResultSet file;
  file.provenance = collect_provenance(command_line, measure_counter_ghz());
  std::vector<H5Table> tables = tables_h5(results, options.quick);
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

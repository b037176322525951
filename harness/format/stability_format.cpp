// The stability suite's results as a terminal table, JSON and the tables of a result file: see
// stability_format.h.
#include "format/stability_format.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "format/text_table.h"

namespace fxbench {
namespace {

std::string value_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// A piece of a spread search holds some verdicts and no result: "piece 1/2".
std::string piece_text(const TestResult& outcome) {
  return "piece " + std::to_string(outcome.piece + 1) + "/" + std::to_string(outcome.pieces);
}

std::string outcome_text(const TestResult& outcome) {
  return outcome.pieces > 1 ? piece_text(outcome) : to_string(outcome.result.outcome);
}

// "41" for a boundary (the hardest value that passed); the limit with ">=" or "<=" when nothing
// failed; the start with "fails at" when even that failed.
std::string cell(const TestResult& outcome) {
  if (outcome.pieces > 1) return piece_text(outcome);
  const bool increasing = outcome.search.harder == Harder::increasing;
  switch (outcome.result.outcome) {
    case Outcome::boundary: return value_text(*outcome.result.last_pass);
    case Outcome::holds_to_limit: return (increasing ? ">= " : "<= ") + value_text(outcome.search.limit) + " (limit)";
    case Outcome::fails_at_start: return "fails at " + value_text(outcome.search.start);
    case Outcome::engine_limit: return "engine limit at " + value_text(outcome.search.limit);
  }
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

nlohmann::ordered_json optional_json(const std::optional<double>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json step_json(const std::optional<int>& step) {
  return step ? nlohmann::ordered_json(*step) : nlohmann::ordered_json(nullptr);
}

template <class T, class Field>
H5Column column(const std::vector<TestResult>& results, std::string name, std::string units, Field field) {
  std::vector<T> values;
  for (const TestResult& outcome : results) values.push_back(static_cast<T>(field(outcome)));
  return {std::move(name), std::move(units), std::move(values)};
}

}  // namespace

std::string stability_table(const std::vector<TestResult>& results, std::span<const EngineTest> listed,
                            const std::vector<const EngineInfo*>& engines, const std::vector<const StabilityTest*>& tests) {
  std::vector<std::vector<std::string>> rows{{"test", "parameter"}};
  for (const EngineInfo* engine : engines) rows.front().push_back(engine->name);
  for (const StabilityTest* test : tests) {
    const bool increasing = test->search.harder == Harder::increasing;
    rows.push_back({test->name, test->parameter + " (" + test->units + ", " + (increasing ? "higher" : "lower") + " is better)"});
    for (const EngineInfo* engine : engines) {
      const auto outcome = std::ranges::find_if(
          results, [&](const TestResult& result) { return result.engine == engine && result.test == test; });
      const bool in_plan = std::ranges::find(listed, EngineTest{engine, test}) != listed.end();
      rows.back().push_back(outcome != results.end() ? cell(*outcome) : in_plan ? "other shard" : "cannot build");
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

nlohmann::ordered_json stability_json(const std::vector<TestResult>& results, const std::vector<const StabilityTest*>& tests,
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
                    {"outcome", outcome_text(outcome)},
                    {"last_pass", optional_json(outcome.result.last_pass)},
                    {"first_fail", optional_json(outcome.result.first_fail)},
                    {"failure", first_failure(outcome.result).reason},
                    {"failed_criterion", first_failure(outcome.result).criterion},
                    {"failed_step", step_json(first_failure(outcome.result).step)},
                    {"evaluations", evaluations}});
  }
  return {{"schema", stability_schema}, {"quick", quick}, {"tests", suite}, {"results", rows}};
}

std::vector<H5Table> stability_tables(const std::vector<TestResult>& results, bool quick) {
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
          column<std::string>(results, "outcome", "", [](R r) { return outcome_text(r); }),
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
          column<std::int32_t>(results, "piece", "index", [](R r) { return r.piece; }),
          column<std::int32_t>(results, "pieces", "count", [](R r) { return r.pieces; }),
      }};
  std::vector<std::int32_t> owner;
  std::vector<double> parameter;
  std::vector<std::uint8_t> pass;
  std::vector<std::string> reason;
  std::vector<std::string> criterion;
  std::vector<std::int32_t> step;
  std::vector<std::string> overrides;
  for (std::size_t row = 0; row < results.size(); ++row) {
    for (std::size_t i = 0; i < results[row].result.evaluations.size(); ++i) {
      const Evaluation& evaluation = results[row].result.evaluations[i];
      owner.push_back(static_cast<std::int32_t>(row));
      parameter.push_back(evaluation.parameter);
      pass.push_back(evaluation.verdict.pass ? 1 : 0);
      reason.push_back(evaluation.verdict.reason);
      criterion.push_back(evaluation.verdict.criterion);
      step.push_back(evaluation.verdict.step.value_or(-1));
      overrides.push_back(results[row].overrides[i]);
    }
  }
  H5Table evaluations{"/stability/evaluations",
                      {},
                      {{"row", "index", owner},
                       {"parameter", "parameter", parameter},
                       {"pass", "flag", pass},
                       {"reason", "", reason},
                       {"criterion", "", criterion},
                       {"step", "step", step},
                       {"overrides", "", overrides}}};
  return {std::move(summary), std::move(evaluations)};
}

}  // namespace fxbench

// The stability suite's results (analysis/stability_tests.h) as text and tables: a terminal table
// of boundaries with what failed first, one JSON object (schema fx2d-bench.stability/1), and the
// /stability and /stability/evaluations tables of a result file (harness/RESULTS_FORMAT.md).
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "analysis/stability_tests.h"
#include "common/column_tables.h"

namespace fxbench {

inline constexpr const char* stability_schema = "fx2d-bench.stability/1";

// One column per engine, one row per test. A pair with no result reads "other shard" when it is
// in `listed` (the whole, unsharded plan) and "cannot build" when it is not.
std::string stability_table(const std::vector<TestResult>& results, std::span<const EngineTest> listed,
                            const std::vector<const EngineInfo*>& engines, const std::vector<const StabilityTest*>& tests);

nlohmann::ordered_json stability_json(const std::vector<TestResult>& results, const std::vector<const StabilityTest*>& tests,
                                      bool quick);

// /stability, one row per result, then /stability/evaluations, one row per evaluation.
std::vector<H5Table> stability_tables(const std::vector<TestResult>& results, bool quick);

}  // namespace fxbench

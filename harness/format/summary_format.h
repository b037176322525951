// What `fx2d-bench run` prints: the aggregates of each run (analysis/summary.h) as the JSON
// summary (schema "fx2d-bench.summary/1", described in harness/README.md) or a terminal table.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "common/results.h"

namespace fxbench {

inline constexpr const char* summary_schema = "fx2d-bench.summary/1";

// The accuracy object of the JSON summaries (run, sweep): the worst figures over the samples.
nlohmann::ordered_json accuracy_json(const AccuracySample& worst);

// The machine object of the JSON summaries (run, sweep): how long a cache line took between two
// cores and back as the measurement began and as it ended, ns; 0 where not measured.
nlohmann::ordered_json machine_json(const Provenance& provenance);

// The summary object; `results.scenes` supplies each run's primary metric, matched by scene hash.
nlohmann::ordered_json summary_json(const ResultSet& results);

// One row per run, columns aligned, ending in a newline.
std::string summary_table(const ResultSet& results);

}  // namespace fxbench

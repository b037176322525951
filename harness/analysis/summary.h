// What `fx2d-bench run` prints: the aggregates of each run as a terminal table or as the JSON
// summary (schema "fx2d-bench.summary/1", described in harness/README.md).
//
// Invariant: every timing aggregate is taken over repeats, never over steps: a repeat's figure is
// its mean per step (its total over its step count), and the median, min and max are across
// repeats, so two runs of the same scene compare like for like whatever the trajectory's early
// cheap steps and late expensive ones. Accuracy figures are the worst over the sampled steps of
// the first repeat, except the kinetic energy, which is the last sample's.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/results.h"
#include "stats/stats.h"

namespace fxbench {

inline constexpr const char* summary_schema = "fx2d-bench.summary/1";

struct RunSummary {
  Spread ms_per_step;
  Spread cpu_ms_per_step;
  Spread cycles_per_step;
  double contacts_mean = 0.0;                              // over every step of every repeat
  std::vector<std::pair<std::string, double>> phases_ms;   // median per-step ms, engine's order
  AccuracySample worst;                                    // step: the last sample's
};

RunSummary summarise(const RunRecord& run);

// The summary object; `results.scenes` supplies each run's primary metric, matched by scene hash.
// The accuracy object of the JSON summaries (run, sweep): the worst figures over the samples.
nlohmann::ordered_json accuracy_json(const AccuracySample& worst);

nlohmann::ordered_json summary_json(const ResultSet& results);

// One row per run, columns aligned, ending in a newline.
std::string summary_table(const ResultSet& results);

}  // namespace fxbench

// The aggregates of a run that `fx2d-bench run` prints (format/summary_format.h) and `compare`
// and `sweep` judge by.
//
// Invariant: every timing aggregate is taken over repeats, never over steps: a repeat's figure is
// its mean per step (its total over its step count), and the median, min and max are across
// repeats, so two runs of the same scene compare like for like whatever the trajectory's early
// cheap steps and late expensive ones. Accuracy figures are the worst over the sampled steps of
// the first repeat, except the kinetic energy, which is the last sample's.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "common/results.h"
#include "stats/statistics.h"

namespace fxbench {

struct RunSummary {
  Spread ms_per_step;
  Spread cpu_ms_per_step;
  Spread cycles_per_step;
  double contacts_mean = 0.0;                              // over every step of every repeat
  std::vector<std::pair<std::string, double>> phases_ms;   // median per-step ms, engine's order
  AccuracySample worst;                                    // step: the last sample's
};

RunSummary summarise(const RunRecord& run);

}  // namespace fxbench

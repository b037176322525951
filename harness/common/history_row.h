// One night's judgement of one gating metric: a row of the nightly history, as the history file
// stores it (storage/history_h5.h), `history show` prints it (format/history_format.h) and
// `history append` makes it from the gate's verdict.
#pragma once

#include <string>

namespace fxbench {

inline constexpr const char* history_schema = "fx2d-bench.history/1";

struct HistoryRow {
  std::string date_utc;   // ISO 8601, e.g. 2024-05-01T02:00:00Z: when the night's gate ran
  std::string candidate;  // the revision judged (B)
  std::string baseline;   // the accepted baseline it was judged against (A)
  std::string engine;
  std::string scene;
  int bodies = 0;
  std::string metric;     // ms_per_step or instructions_per_step
  double a = 0.0;         // the baseline's median
  double b = 0.0;         // the candidate's median
  double ratio = 1.0;     // b / a
  double ci_low = 1.0;
  double ci_high = 1.0;
  double p_value = 0.0;   // NaN for an exact row (instruction counts)
  std::string verdict;    // the gate's
  bool step_detected = false;
  bool accepted = false;  // this night's candidate became the baseline
};

}  // namespace fxbench

// The nightly gate's policy (ci/gating.json, format in ci/README.md) and the judgement it makes of
// a comparison (`fx2d-bench compare --json`, schema fx2d-bench.compare/1): which rows gate, at
// which thresholds, which are quarantined and why, and what the verdict of the night is.
//
// Invariants:
// - A policy is valid or refused whole: parse_policy throws InputError with one line naming the
//   file, the JSON pointer and what was expected; unknown keys are refused, so a typo cannot
//   silently switch a threshold off.
// - The judgement is a pure function of the comparison and the policy. Time rows are re-judged
//   with the two-stage rule of statistics.h (decide_speed: significant AND the whole interval
//   outside the scene's noise band); exact rows (instruction counts: p_value null, ci_low = ci_high
//   = ratio) change when the ratio lies beyond the scene's instructions tolerance.
// - Control engines (Box2D, ODE: the same code in both builds) never regress; a change in one of
//   their time rows means the machine was too noisy to trust any time verdict that night, so every
//   `slower` time verdict of the other engines becomes inconclusive. Exact counts are immune to
//   noise and keep their verdicts.
// - A quarantined row never gates; it is kept, marked with its reason, so the history and the
//   report still show it.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/errors.h"

namespace fxbench {

inline constexpr const char* gating_schema = "fx2d-bench.gating/1";
inline constexpr const char* gate_schema = "fx2d-bench.gate/1";

struct Thresholds {
  double noise = 0.02;                    // time ratios within 1 +- noise are no change
  double alpha = 0.05;                    // significance level of the rank test
  double accuracy_tolerance = 0.05;       // relative change of an accuracy figure that counts
  double instructions_tolerance = 0.005;  // exact ratios within 1 +- this are no change
};

struct SuiteScene {
  std::string scene;  // an embedded scene's name, or a scene file's path from the working directory
  int bodies = 0;     // its size parameter N, or 0 for the scene as it stands (a file listing its bodies)
  std::string name;   // what a night's files for it are called: its file's stem, and _N at a size
};

// What the nightly job measures: ci/nightly reads it through `fx2d-bench gate --print-suite`.
struct Suite {
  std::vector<std::string> engines;
  std::vector<SuiteScene> scenes;
  int rounds = 0;  // interleaved A/B rounds (repeats of each side)
  int steps = 0;   // steps per round
};

// A row held out of the gate. An absent `bodies` or `metric` matches every size or metric.
struct Quarantine {
  std::string engine;
  std::string scene;
  std::optional<int> bodies;
  std::optional<std::string> metric;
  std::string reason;
};

struct Policy {
  Suite suite;
  Suite smoke;
  std::vector<std::string> controls;
  Thresholds defaults;
  std::vector<std::pair<std::string, Thresholds>> scene_thresholds;  // scene name -> its thresholds
  std::vector<Quarantine> quarantine;

  const Thresholds& thresholds_for(const std::string& scene) const;
  const Quarantine* quarantined(const std::string& engine, const std::string& scene, int bodies,
                                const std::string& metric) const;
  bool is_control(const std::string& engine) const;
};

// Reads and validates a policy file. Throws InputError (one line: file, JSON pointer, expectation).
Policy read_policy(const std::string& path);
Policy parse_policy(const std::string& text, const std::string& label);

// One gating row of a comparison, as judged by the policy.
struct GateRow {
  std::string engine;  // as compare wrote it, e.g. "fx2d" or "fx2d@B"
  std::string scene;
  int bodies = 0;
  std::string metric;
  double a = 0.0;
  double b = 0.0;
  double ratio = 1.0;
  double ci_low = 1.0;
  double ci_high = 1.0;
  std::optional<double> p_value;  // absent for exact rows
  double band = 0.0;              // the threshold the row was judged against: noise or instructions tolerance
  std::string compare_verdict;    // compare's own verdict, for the reader
  std::string verdict;            // the gate's: "slower", "faster, less accurate", "quarantined", ...
  bool control = false;
  bool quarantined = false;
  std::string reason;             // the quarantine's
  bool regression = false;
  bool step_detected = false;     // a change the gate believes: faster, slower, or accuracy moved
};

struct GateReport {
  std::vector<GateRow> rows;
  std::vector<std::string> noisy_controls;  // e.g. "box2d pile 600: slower (1.041)"

  int regressions() const;
  ExitCode exit_code() const;  // exit_regression, else exit_inconclusive, else exit_ok
  std::string headline() const;
};

// Judges compare JSON against `policy`. Throws InputError (naming `label`) on anything but an A/B
// fx2d-bench.compare/1 object with well-formed rows.
GateReport judge(const nlohmann::json& compare, const std::string& label, const Policy& policy);

// Reads compare JSON files (one per scene, as ci/nightly makes them) and judges their rows as one
// night. Throws InputError.
GateReport judge_files(const std::vector<std::string>& compare_paths, const Policy& policy);

// The engine without the build label that `fx2d-bench ab` appends ("fx2d@B" -> "fx2d").
std::string base_engine(const std::string& engine);

}  // namespace fxbench

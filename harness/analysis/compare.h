// `fx2d-bench compare`: speed and accuracy of two result files (A/B: every engine, scene and size
// present in both), or of the engines within one file (the cross-engine view). The comparison
// returns rows and an exit code and prints nothing; the renderers (format/compare_format.h) turn
// that into a terminal table, JSON (schema fx2d-bench.compare/1) or Markdown, and
// commands/compare.h reads the files. Row meanings: harness/README.md.
//
// Invariants: a verdict is a deterministic function of the two files and the settings
// (statistics.h); two runs of the same scene name and size but different scene hashes are never
// compared without `force`; the A/B exit code is exit_regression when any gating row (ms_per_step,
// and instructions_per_step where both files have instruction counts) is slower or less accurate
// beyond tolerance, else exit_inconclusive when any gating row is inconclusive, else exit_ok; the
// cross-engine view is a report, not a gate, and exits exit_ok. Instruction counts are exact, so
// their rows have no test and are never inconclusive.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/errors.h"
#include "common/results.h"
#include "measure/interleave.h"
#include "stats/statistics.h"

namespace fxbench {

inline constexpr const char* compare_schema = "fx2d-bench.compare/1";

// The metrics that gate: wall time per step and, where both files were counted, exact
// instructions per step. Every other row (cycles, phases) is information.
inline constexpr const char* step_metric = "ms_per_step";
inline constexpr const char* instructions_metric = "instructions_per_step";
// Information beside the step: each repeat's MEAN step in thread CPU time. It follows the total
// work, as `run`'s ms/step (the speed table's figure) does, where the median step misses a change
// confined to fewer than half the steps (a broad phase that spikes every fourth step); CPU time,
// because preemption inflates a mean of wall time.
inline constexpr const char* mean_step_metric = "mean_cpu_ms_per_step";

struct CompareSettings {
  VerdictRules rules;
  double accuracy_tolerance = 0.05;  // relative; a metre figure also gets accuracy_floor_m
  double instructions_tolerance = 0.005;  // relative change in instructions per step that counts
  bool force = false;                // compare different scenes; no provenance warnings
};

// Below this, a change in a length (penetration, displacement) is rounding, not accuracy: a
// tenth of a millimetre, so that two near-zero figures never make a large relative change.
inline constexpr double accuracy_floor_m = 1e-4;

enum class AccuracyChange { same, better, worse, changed };

std::string to_string(AccuracyChange change);

// One accuracy figure of a run, worst over its samples (summary.h). Penetration, escaped and
// NaN bodies are errors in every scene, so larger is worse; a displacement is an error only in a
// scene whose primary metric it is (a stack should not move, a pile must fall), and elsewhere a
// change beyond tolerance is reported as `changed`, neither better nor worse.
struct AccuracyDelta {
  std::string name;  // max_penetration, max_displacement, escaped, nan
  double a = 0.0;
  double b = 0.0;
  AccuracyChange change = AccuracyChange::same;
};

struct CompareRow {
  std::string engine;    // B's engine
  std::string against;   // A's engine: the same in A/B mode, the baseline in the cross-engine view
  std::string scene;
  int bodies = 0;
  std::string metric;    // ms_per_step, cycles_per_step, phase:<name>, instructions_per_step
  double a = 0.0;        // median over repeats of each repeat's median step (what is judged, statistics.h);
                         // for instructions, the exact count per step
  double b = 0.0;
  RatioEstimate estimate;         // for instructions, the exact ratio: ci.low = ci.high = ratio
  std::optional<RankTest> test;   // empty for instructions: an exact figure has nothing to test
  std::string test_name; // sign-test-rounds (ab), wilcoxon-signed-rank-paired, mann-whitney-u, or exact
  bool rounds_paired = false;  // estimate by bootstrap_paired_median_ratio: the rounds of one `ab`
  std::optional<RatiosByRoundSpeed> ratios_by_round_speed;  // paired rounds only
  int repeats_a = 0;     // for instructions, 1: one counted loop
  int repeats_b = 0;
  SpeedVerdict speed;
  std::optional<bool> same_physics;   // A/B only: same state hashes
  std::vector<AccuracyDelta> accuracy;  // ms_per_step rows only
  std::string primary_metric;         // the scene's, on ms_per_step rows

  AccuracyChange accuracy_change() const;  // worst of the deltas that judge: worse > better > same
  std::string verdict() const;             // e.g. "faster", "faster, less accurate"
};

struct CompareReport {
  bool cross_engine = false;
  CompareSettings settings;
  std::vector<CompareRow> rows;
  std::vector<std::string> warnings;  // one line each, for stderr

  bool is_regression(const CompareRow& row) const;  // a gating row, slower or less accurate
  int count_regressions() const;
  ExitCode exit_code() const;
  std::string headline() const;  // e.g. "2 regressions, 1 improvement, 9 unchanged, 0 inconclusive"
};

// A/B: B against A. Throws InputError (naming the labels, usually file paths) on a scene hash
// mismatch without force, duplicate runs of one engine, scene and size in a file, or nothing to
// compare.
CompareReport compare_results(const ResultSet& a, const std::string& a_label, const ResultSet& b,
                              const std::string& b_label, const CompareSettings& settings);

// The two builds of one `fx2d-bench ab` file (split_variants), labelled A and B: as
// compare_results, except that A's round k and B's round k ran back to back, so where both runs
// have the same number of rounds the intervals resample the rounds as pairs (statistics.h).
CompareReport compare_variants(const VariantResults& variants, const CompareSettings& settings);

// Cross-engine: on each scene, with an empty `baseline` Fx2D against every other engine (B = fx2d),
// otherwise every other engine against `baseline` (A = baseline). Throws InputError when no
// scene has both sides.
CompareReport compare_engines(const ResultSet& results, const std::string& label, const std::string& baseline,
                              const CompareSettings& settings);

}  // namespace fxbench

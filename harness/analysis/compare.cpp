// `fx2d-bench compare A.h5 [B.h5]`'s judgement: is B faster, slower or less accurate than A, and
// may CI trust the answer (compare.h states the invariants, statistics.h the method).
//
// Reads top to bottom: the samples each row compares, one row per metric of a pair of runs with
// the accuracy deltas beside the step time, the exact instructions row where both runs were
// counted (--counter instructions), the A/B pairing of runs by engine, scene and size
// (with its refusals and warnings), the verdict counts, and the cross-engine pairing within one
// file. The renderers are in format/compare_format.cpp, the command line in commands/compare.cpp.
#include "analysis/compare.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "analysis/summary.h"
#include "common/number_text.h"

namespace fxbench {
namespace {

// Fewer pairs of rounds than this are too few to split into halves that say anything.
constexpr int min_rounds_to_split = 8;

// One metric of one run, repeat-major [repeats x steps] like RunRecord's own series, and whether
// a repeat's figure is the mean of its steps rather than their median.
struct MetricSamples {
  std::string name;
  std::vector<double> values;
  bool per_repeat_mean = false;
};

// Fx2D's phases before each stage function had a timer of its own, each the sum of the stages
// that now split it (RESULTS_FORMAT.md, "Fx2D's phase names"): a run recorded with the old names
// compares with a newer one through these sums.
struct FoldedPhase {
  std::string name;
  std::vector<std::string> stages;
};
const std::vector<FoldedPhase> old_fx2d_phases = {
    {"integration", {"integrate"}},
    {"narrow_phase", {"collide"}},
    {"velocity_passes", {"prepare", "colour_and_pack", "warm_start", "solve", "relax", "restitution"}},
    {"bookkeeping", {"store", "sleep"}}};

// The samples of phase `name` of `run`, repeat-major like its own series; empty when it has none.
std::vector<double> phase_samples(const RunRecord& run, const std::string& name) {
  const auto found = std::ranges::find(run.phase_names, name);
  if (found == run.phase_names.end()) return {};
  const std::size_t phase_count = run.phase_names.size();
  std::vector<double> values;
  for (auto i = static_cast<std::size_t>(found - run.phase_names.begin()); i < run.phase_ms.size(); i += phase_count) {
    values.push_back(run.phase_ms[i]);
  }
  return values;
}

// An old phase `other` names and `run` lacks, as the sum of `run`'s stages that it covered.
std::optional<std::vector<double>> folded_phase(const RunRecord& run, const RunRecord& other, const FoldedPhase& old) {
  if (std::ranges::count(run.phase_names, old.name) > 0 || std::ranges::count(other.phase_names, old.name) == 0) {
    return std::nullopt;
  }
  std::vector<double> sums;
  for (const std::string& stage : old.stages) {
    const std::vector<double> values = phase_samples(run, stage);
    if (values.empty()) return std::nullopt;
    sums.resize(values.size(), 0.0);
    for (std::size_t i = 0; i < values.size(); ++i) sums[i] += values[i];
  }
  return sums;
}

// The step time, the mean CPU time per step, cycles and, with phases, each of `run`'s phases, then any old
// phase `other` names folded from `run`'s stages.
std::vector<MetricSamples> metrics_of(const RunRecord& run, const RunRecord& other, bool with_phases) {
  std::vector<MetricSamples> metrics = {
      {step_metric, run.wall_ms},
      {mean_step_metric, run.cpu_ms, true},
      {"cycles_per_step", std::vector<double>(run.cycles.begin(), run.cycles.end())}};
  if (!with_phases) return metrics;
  for (const std::string& name : run.phase_names) metrics.push_back({"phase:" + name, phase_samples(run, name)});
  for (const FoldedPhase& old : old_fx2d_phases) {
    if (auto sums = folded_phase(run, other, old)) metrics.push_back({"phase:" + old.name, std::move(*sums)});
  }
  return metrics;
}

// A metric that measured nothing (a phase timer compiled out, a counter the machine lacks, a
// phase that takes no time in most steps) has no ratio: its row is left out rather than shown as 0/0.
bool measured(const std::vector<double>& repeat_figures) {
  return !repeat_figures.empty() && std::ranges::all_of(repeat_figures, [](double figure) { return figure > 0.0; });
}

// --- accuracy -----------------------------------------------------------------------------------

AccuracyChange accuracy_change_of(double a, double b, double allowance, bool larger_is_worse) {
  if (std::abs(b - a) <= allowance) return AccuracyChange::same;
  if (!larger_is_worse) return AccuracyChange::changed;
  return b > a ? AccuracyChange::worse : AccuracyChange::better;
}

// Lengths get the relative tolerance plus the floor; counts of bodies lost must not grow at all.
std::vector<AccuracyDelta> accuracy_deltas(const RunRecord& a, const RunRecord& b, const std::string& primary_metric,
                                           double tolerance) {
  const AccuracySample worst_a = summarise(a).worst;
  const AccuracySample worst_b = summarise(b).worst;
  const auto length = [&](const char* name, double AccuracySample::*field, bool larger_is_worse) {
    const double allowance = tolerance * std::abs(worst_a.*field) + accuracy_floor_m;
    return AccuracyDelta{name, worst_a.*field, worst_b.*field,
                         accuracy_change_of(worst_a.*field, worst_b.*field, allowance, larger_is_worse)};
  };
  const auto count = [&](const char* name, int AccuracySample::*field) {
    const auto value_a = static_cast<double>(worst_a.*field);
    const auto value_b = static_cast<double>(worst_b.*field);
    return AccuracyDelta{name, value_a, value_b, accuracy_change_of(value_a, value_b, 0.0, true)};
  };
  return {length("max_penetration", &AccuracySample::max_penetration, true),
          length("max_displacement", &AccuracySample::max_displacement, primary_metric == "displacement"),
          count("escaped", &AccuracySample::escaped), count("nan", &AccuracySample::nan)};
}

// --- rows -------------------------------------------------------------------------------------

struct RunPair {
  const RunRecord& a;
  const RunRecord& b;
  std::string primary_metric;
  std::optional<bool> same_physics;  // A/B only
  bool with_phases = false;          // phases are named alike only within one engine
  bool rounds_paired = false;        // repeat k of A and of B ran back to back (one `ab`)
};

// Step i of A and B did the same work when both runs stepped one deterministic trajectory.
bool steps_correspond(const RunPair& pair) {
  return pair.same_physics.value_or(false) && pair.a.deterministic && pair.b.deterministic &&
         pair.a.steps == pair.b.steps;
}

// The row of `metric` for this pair, with only what names it filled in.
CompareRow row_for(const RunPair& pair, const std::string& metric) {
  CompareRow row;
  row.engine = pair.b.engine;
  row.against = pair.a.engine;
  row.scene = pair.a.scene;
  row.bodies = pair.a.bodies;
  row.metric = metric;
  row.same_physics = pair.same_physics;
  return row;
}

std::optional<CompareRow> speed_row(const RunPair& pair, const MetricSamples& a, const MetricSamples& b,
                                    const CompareSettings& settings) {
  const auto steps_a = static_cast<std::size_t>(pair.a.steps);
  const auto steps_b = static_cast<std::size_t>(pair.b.steps);
  // Each repeat's median step, not its mean: statistics.h says why (preemption); the mean only for
  // the metric that asks for it, of CPU time.
  const auto per_repeat = a.per_repeat_mean ? row_means : row_medians;
  const std::vector<double> repeats_a = per_repeat(a.values, steps_a);
  const std::vector<double> repeats_b = per_repeat(b.values, steps_b);
  if (!measured(repeats_a) || !measured(repeats_b)) return std::nullopt;

  CompareRow row = row_for(pair, a.name);
  row.a = median(repeats_a);
  row.b = median(repeats_b);
  // An interrupted `ab` may leave one side a round ahead: its rounds no longer pair one to one.
  row.rounds_paired = pair.rounds_paired && repeats_a.size() == repeats_b.size();
  row.estimate = row.rounds_paired ? bootstrap_paired_median_ratio(repeats_a, repeats_b)
                                   : bootstrap_median_ratio(repeats_a, repeats_b);
  // The rounds of one `ab` are tested as the pairs the interval resamples, by the test of their
  // median. A neighbour whose activity keeps time with the rounds can bias the per-step medians
  // across them while leaving each round's median alone; one that slows some of one build's
  // rounds a lot outweighs the rest in a signed-rank test, not in a count of signs (compare_test
  // shows both).
  if (row.rounds_paired) {
    row.ratios_by_round_speed = ratios_by_round_speed(repeats_a, repeats_b);
    row.test = paired_sign_test(repeats_a, repeats_b);
    row.test_name = "sign-test-rounds";
  } else if (steps_correspond(pair) && !a.per_repeat_mean) {
    // Step against step asks whether most steps changed; a mean moves with a few that did.
    row.test = paired_log_ratio_test(column_medians(a.values, steps_a), column_medians(b.values, steps_b));
    row.test_name = "wilcoxon-signed-rank-paired";
  } else {
    row.test = mann_whitney_u(repeats_a, repeats_b);
    row.test_name = "mann-whitney-u";
  }
  row.repeats_a = static_cast<int>(repeats_a.size());
  row.repeats_b = static_cast<int>(repeats_b.size());
  row.speed = decide_speed(row.estimate, *row.test, std::min(row.repeats_a, row.repeats_b), settings.rules);
  if (a.name == step_metric) {
    row.accuracy = accuracy_deltas(pair.a, pair.b, pair.primary_metric, settings.accuracy_tolerance);
    row.primary_metric = pair.primary_metric;
  }
  return row;
}

// One count per run, exact: the ratio is its own interval and there is nothing to test.
std::optional<CompareRow> instructions_row(const RunPair& pair, const CompareSettings& settings) {
  const std::optional<InstructionCount>& a = pair.a.instruction_count;
  const std::optional<InstructionCount>& b = pair.b.instruction_count;
  if (!a || !b || a->per_step() <= 0.0) return std::nullopt;
  CompareRow row = row_for(pair, instructions_metric);
  row.a = a->per_step();
  row.b = b->per_step();
  const double ratio = row.b / row.a;
  row.estimate = {ratio, {ratio, ratio}};
  row.test_name = "exact";
  row.repeats_a = row.repeats_b = 1;
  row.speed = {decide_exact(row.a, row.b, settings.instructions_tolerance), std::nullopt};
  return row;
}

// One row per metric measured in both runs, in A's order, then the instruction counts.
void append_rows(const RunPair& pair, const CompareSettings& settings, std::vector<CompareRow>& rows) {
  const std::vector<MetricSamples> metrics_b = metrics_of(pair.b, pair.a, pair.with_phases);
  for (const MetricSamples& a : metrics_of(pair.a, pair.b, pair.with_phases)) {
    const auto b = std::ranges::find(metrics_b, a.name, &MetricSamples::name);
    if (b == metrics_b.end()) continue;
    if (auto row = speed_row(pair, a, *b, settings)) rows.push_back(std::move(*row));
  }
  if (auto row = instructions_row(pair, settings)) rows.push_back(std::move(*row));
}

bool counted_on_one_side(const RunPair& pair) {
  return pair.a.instruction_count.has_value() != pair.b.instruction_count.has_value();
}

// Said once per comparison, however many pairs it concerns.
void warn_on_one_sided_counts(int pairs, const std::string& label, std::vector<std::string>& warnings) {
  if (pairs == 0) return;
  warnings.push_back(label + ": " + std::to_string(pairs) + (pairs == 1 ? " pair" : " pairs") +
                     " of runs with instruction counts on one side only, so no instructions_per_step row for " +
                     (pairs == 1 ? "it" : "them") + "; run both with --counter instructions");
}

std::string primary_metric_of(const ResultSet& results, const RunRecord& run) {
  const auto scene = std::ranges::find(results.scenes, run.scene_hash, &SceneRecord::hash);
  return scene == results.scenes.end() ? std::string("penetration") : scene->primary_metric;
}

std::string describe(const RunRecord& run) {
  return run.engine + " on " + run.scene + " (" + std::to_string(run.bodies) + " bodies)";
}

// --- A/B ------------------------------------------------------------------------------------------

using RunKey = std::tuple<std::string, std::string, int>;  // engine, scene, bodies

std::map<RunKey, const RunRecord*> runs_by_key(const ResultSet& results, const std::string& label) {
  std::map<RunKey, const RunRecord*> runs;
  for (const RunRecord& run : results.runs)
    if (!runs.emplace(RunKey{run.engine, run.scene, run.bodies}, &run).second)
      throw InputError(label + ": " + describe(run) + " appears twice; compare takes one run of each");
  return runs;
}

// Intermediate hashes compare only when they were taken after the same steps.
bool same_physics(const RunRecord& a, const RunRecord& b) {
  return a.final_state_hash == b.final_state_hash && (a.hash_every != b.hash_every || a.state_hashes == b.state_hashes);
}

void warn_on_provenance(const Provenance& a, const Provenance& b, const std::string& pair_label,
                        std::vector<std::string>& warnings) {
  const std::pair<const char*, std::string Provenance::*> facts[] = {{"cpu_model", &Provenance::cpu_model},
                                                                     {"hostname", &Provenance::hostname},
                                                                     {"compiler", &Provenance::compiler},
                                                                     {"build_flags", &Provenance::build_flags}};
  for (const auto& [name, field] : facts)
    if (a.*field != b.*field)
      warnings.push_back(pair_label + " differ in " + name + " (\"" + a.*field + "\" vs \"" + b.*field +
                         "\"); pass --force to compare without this warning");
}

// How a warning names a row's engine, scene and size: "fx2d pile 300".
std::string cell_of(const CompareRow& row) {
  return row.engine + " " + row.scene + " " + std::to_string(row.bodies);
}

// Paired rounds whose faster and slower halves disagree by more than the noise band: the machine
// ran in two states that change the builds unequally, so the verdict depends on which it was in.
void warn_on_state_dependent_ratios(CompareReport& report) {
  for (const CompareRow& row : report.rows) {
    if (row.metric != step_metric || !row.ratios_by_round_speed || row.repeats_a < min_rounds_to_split) continue;
    const RatiosByRoundSpeed& halves = *row.ratios_by_round_speed;
    if (std::abs(halves.slowest_half - halves.fastest_half) <= report.settings.rules.noise) continue;
    report.warnings.push_back(
        cell_of(row) + ": B/A is " + formatted("%.3f", halves.fastest_half) +
        " over the half of the rounds that ran fastest and " + formatted("%.3f", halves.slowest_half) +
        " over the slowest half; the change may depend on the machine's state (a busy "
        "neighbouring hardware thread, say): pin with taskset and read the per-round ratios "
        "(harness/README, ab)");
  }
}

// A step that ran faster or slower while its exact instruction count held: the same work at a
// different speed, which in an A/B of two builds is most often code placement (where the build
// put the hot loops), not the change itself. The next edit can move it back; the count holds.
void warn_on_time_without_instructions(CompareReport& report) {
  for (const CompareRow& step : report.rows) {
    if (step.metric != step_metric ||
        (step.speed.speed != Speed::faster && step.speed.speed != Speed::slower))
      continue;
    const auto count = std::ranges::find_if(report.rows, [&](const CompareRow& row) {
      return row.metric == instructions_metric && row.engine == step.engine && row.scene == step.scene &&
             row.bodies == step.bodies;
    });
    if (count == report.rows.end() || count->speed.speed != Speed::no_change) continue;
    report.warnings.push_back(
        cell_of(step) + ": the step is " + to_string(step.speed.speed) + " (B/A " +
        formatted("%.3f", step.estimate.ratio) + ") on " + formatted("%.3f", count->estimate.ratio) +
        " of A's instructions; the same work at another speed is most often code placement, "
        "which the next edit can undo: credit the change with what the count shows");
  }
}

// A/B, by both commands: `rounds_paired` when A and B are the two builds of one `ab` file.
CompareReport compare_ab(const ResultSet& a, const std::string& a_label, const ResultSet& b, const std::string& b_label,
                         const CompareSettings& settings, bool rounds_paired) {
  const std::string pair_label = a_label + " and " + b_label;
  CompareReport report{.cross_engine = false, .settings = settings, .rows = {}, .warnings = {}};
  if (!settings.force) warn_on_provenance(a.provenance, b.provenance, pair_label, report.warnings);
  const std::map<RunKey, const RunRecord*> runs_a = runs_by_key(a, a_label);
  const std::map<RunKey, const RunRecord*> runs_b = runs_by_key(b, b_label);
  int one_sided_counts = 0;
  for (const RunRecord& run_a : a.runs) {
    const auto match = runs_b.find(RunKey{run_a.engine, run_a.scene, run_a.bodies});
    if (match == runs_b.end()) {
      report.warnings.push_back(describe(run_a) + " is only in " + a_label);
      continue;
    }
    const RunRecord& run_b = *match->second;
    if (run_a.scene_hash != run_b.scene_hash && !settings.force)
      throw InputError(pair_label + ": " + describe(run_a) + " is a different scene in each (scene hash " +
                       run_a.scene_hash + " vs " + run_b.scene_hash + "); pass --force to compare them anyway");
    const RunPair pair{run_a, run_b, primary_metric_of(a, run_a), same_physics(run_a, run_b), true, rounds_paired};
    one_sided_counts += counted_on_one_side(pair) ? 1 : 0;
    append_rows(pair, settings, report.rows);
  }
  warn_on_one_sided_counts(one_sided_counts, pair_label, report.warnings);
  warn_on_state_dependent_ratios(report);
  warn_on_time_without_instructions(report);
  for (const auto& [key, run_b] : runs_b)
    if (!runs_a.contains(key)) report.warnings.push_back(describe(*run_b) + " is only in " + b_label);
  if (report.rows.empty())
    throw InputError(pair_label + ": no engine, scene and size measured in both; nothing to compare");
  return report;
}

// --- verdict counts -------------------------------------------------------------------------------

bool gates(const CompareReport& report, const CompareRow& row) {
  return !report.cross_engine && (row.metric == step_metric || row.metric == instructions_metric);
}

std::string counted(int count, const std::string& singular, const std::string& plural) {
  return std::to_string(count) + " " + (count == 1 ? singular : plural);
}

}  // namespace

std::string to_string(AccuracyChange change) {
  switch (change) {
    case AccuracyChange::same: return "same";
    case AccuracyChange::better: return "better";
    case AccuracyChange::worse: return "worse";
    case AccuracyChange::changed: return "changed";
  }
  return "same";
}

bool CompareReport::is_regression(const CompareRow& row) const {
  return gates(*this, row) && (row.speed.speed == Speed::slower || row.accuracy_change() == AccuracyChange::worse);
}

AccuracyChange CompareRow::accuracy_change() const {
  const auto any = [&](AccuracyChange change) { return std::ranges::find(accuracy, change, &AccuracyDelta::change) != accuracy.end(); };
  if (any(AccuracyChange::worse)) return AccuracyChange::worse;
  if (any(AccuracyChange::better)) return AccuracyChange::better;
  return AccuracyChange::same;
}

std::string CompareRow::verdict() const {
  const AccuracyChange change = accuracy_change();
  const char* qualifier = change == AccuracyChange::worse ? ", less accurate"
                          : change == AccuracyChange::better ? ", more accurate"
                                                             : "";
  return to_string(speed.speed) + qualifier;
}

int CompareReport::count_regressions() const {
  return static_cast<int>(std::ranges::count_if(rows, [&](const CompareRow& row) { return is_regression(row); }));
}

ExitCode CompareReport::exit_code() const {
  if (count_regressions() > 0) return exit_regression;
  const bool undecided = std::ranges::any_of(
      rows, [&](const CompareRow& row) { return gates(*this, row) && row.speed.speed == Speed::inconclusive; });
  return undecided ? exit_inconclusive : exit_ok;
}

// A/B: each gating row falls in the first of regression, inconclusive, improvement, unchanged.
// Cross-engine: the step-time verdicts of engine against baseline.
std::string CompareReport::headline() const {
  std::map<std::string, int> counts;
  for (const CompareRow& row : rows) {
    if (cross_engine ? row.metric != step_metric : !gates(*this, row)) continue;
    if (cross_engine)
      ++counts[to_string(row.speed.speed)];
    else if (is_regression(row))
      ++counts["regression"];
    else if (row.speed.speed == Speed::inconclusive)
      ++counts["inconclusive"];
    else if (row.speed.speed == Speed::faster || row.accuracy_change() == AccuracyChange::better)
      ++counts["improvement"];
    else
      ++counts["unchanged"];
  }
  if (cross_engine)
    return std::to_string(counts["faster"]) + " faster, " + std::to_string(counts["slower"]) + " slower, " +
           std::to_string(counts["no change"]) + " no change, " + std::to_string(counts["inconclusive"]) +
           " inconclusive (ms/step, engine against baseline)";
  return counted(counts["regression"], "regression", "regressions") + ", " +
         counted(counts["improvement"], "improvement", "improvements") + ", " + std::to_string(counts["unchanged"]) +
         " unchanged, " + std::to_string(counts["inconclusive"]) + " inconclusive";
}

CompareReport compare_results(const ResultSet& a, const std::string& a_label, const ResultSet& b,
                              const std::string& b_label, const CompareSettings& settings) {
  return compare_ab(a, a_label, b, b_label, settings, false);
}

CompareReport compare_variants(const VariantResults& variants, const CompareSettings& settings) {
  return compare_ab(variants.a, "A", variants.b, "B", settings, true);
}

CompareReport compare_engines(const ResultSet& results, const std::string& label, const std::string& baseline,
                              const CompareSettings& settings) {
  CompareReport report{.cross_engine = true, .settings = settings, .rows = {}, .warnings = {}};
  runs_by_key(results, label);  // rejects a file that holds two runs of one engine, scene and size
  const std::string subject = baseline.empty() ? std::string("fx2d") : baseline;
  const auto same_scene = [](const RunRecord& x, const RunRecord& y) {
    return x.scene == y.scene && x.bodies == y.bodies && x.scene_hash == y.scene_hash;
  };
  int one_sided_counts = 0;
  for (const RunRecord& subject_run : results.runs) {
    if (subject_run.engine != subject) continue;
    for (const RunRecord& other : results.runs) {
      if (other.engine == subject || !same_scene(other, subject_run)) continue;
      const RunRecord& a = baseline.empty() ? other : subject_run;
      const RunRecord& b = baseline.empty() ? subject_run : other;
      const RunPair pair{a, b, primary_metric_of(results, a), std::nullopt, false};
      one_sided_counts += counted_on_one_side(pair) ? 1 : 0;
      append_rows(pair, settings, report.rows);
    }
  }
  warn_on_one_sided_counts(one_sided_counts, label, report.warnings);
  if (report.rows.empty())
    throw InputError(label + ": no scene has a " + subject + " run and a run of another engine; nothing to compare");
  return report;
}


}  // namespace fxbench

// Aggregates of a run; the rules are in summary.h, the JSON and the table in
// format/summary_format.cpp.
#include "analysis/summary.h"

#include <algorithm>
#include <functional>

namespace fxbench {
namespace {

// The mean per step of each repeat, of the per-step value at(sample index).
std::vector<double> per_repeat_means(const RunRecord& run, const std::function<double(std::size_t)>& at) {
  std::vector<double> means(static_cast<std::size_t>(run.repeats));
  const auto steps = static_cast<std::size_t>(run.steps);
  for (std::size_t repeat = 0; repeat < means.size(); ++repeat) {
    double total = 0.0;
    for (std::size_t step = 0; step < steps; ++step) total += at(repeat * steps + step);
    means[repeat] = steps == 0 ? 0.0 : total / static_cast<double>(steps);
  }
  return means;
}

AccuracySample worst_of(const std::vector<AccuracySample>& samples) {
  AccuracySample worst;
  for (const AccuracySample& sample : samples) {
    worst.max_penetration = std::max(worst.max_penetration, sample.max_penetration);
    worst.mean_penetration = std::max(worst.mean_penetration, sample.mean_penetration);
    worst.max_displacement = std::max(worst.max_displacement, sample.max_displacement);
    worst.max_lateral_drift = std::max(worst.max_lateral_drift, sample.max_lateral_drift);
    worst.escaped = std::max(worst.escaped, sample.escaped);
    worst.nan = std::max(worst.nan, sample.nan);
  }
  if (!samples.empty()) {
    worst.step = samples.back().step;
    worst.kinetic_energy = samples.back().kinetic_energy;
  }
  return worst;
}

}  // namespace

RunSummary summarise(const RunRecord& run) {
  RunSummary summary;
  summary.ms_per_step = spread_of(per_repeat_means(run, [&](std::size_t i) { return run.wall_ms[i]; }));
  summary.cpu_ms_per_step = spread_of(per_repeat_means(run, [&](std::size_t i) { return run.cpu_ms[i]; }));
  summary.cycles_per_step =
      spread_of(per_repeat_means(run, [&](std::size_t i) { return static_cast<double>(run.cycles[i]); }));
  summary.contacts_mean =
      mean_of(per_repeat_means(run, [&](std::size_t i) { return static_cast<double>(run.contacts[i]); }));
  const std::size_t phase_count = run.phase_names.size();
  for (std::size_t phase = 0; phase < phase_count; ++phase) {
    const auto means = per_repeat_means(run, [&](std::size_t i) { return run.phase_ms[i * phase_count + phase]; });
    summary.phases_ms.emplace_back(run.phase_names[phase], spread_of(means).median);
  }
  summary.worst = worst_of(run.accuracy);
  return summary;
}

}  // namespace fxbench

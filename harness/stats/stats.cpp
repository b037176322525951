// Spreads and means of the few hundred values a run summarises, taken once per run, outside
// any timed region.
#include "stats/stats.h"

#include <algorithm>
#include <numeric>

#include "stats/statistics.h"

namespace fxbench {

Spread spread_of(std::span<const double> sample) {
  if (sample.empty()) return {};
  const auto [min, max] = std::minmax_element(sample.begin(), sample.end());
  return {median(sample), *min, *max};
}

double mean_of(std::span<const double> sample) {
  if (sample.empty()) return 0.0;
  return std::accumulate(sample.begin(), sample.end(), 0.0) / static_cast<double>(sample.size());
}

}  // namespace fxbench

// The spread of a sample, as the run summary reports it: median, min and max.
//
// Invariant: an empty sample has every figure 0; otherwise min <= median <= max, the median
// being statistics.h's (the mean of the two middle values for an even count), so `run` and
// `compare` report the same median of the same numbers.
#pragma once

#include <span>

namespace fxbench {

struct Spread {
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
};

Spread spread_of(std::span<const double> sample);
double mean_of(std::span<const double> sample);

}  // namespace fxbench

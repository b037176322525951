// The three clocks a timed step is read with: wall time (steady_clock), the thread's CPU time, and
// the time-stamp counter.
//
// Invariant: the readings nest, CPU time outermost and the counter innermost, so the counter
// interval is the tightest around the step and no clock's own cost lands inside a tighter one.
// On x86-64 the counter is the TSC read between lfence fences: it counts reference cycles at a
// constant rate, not the core's actual cycles, so it is comparable across frequency changes. On
// other targets it is steady_clock nanoseconds, and counter_kind() says so.
//
// Cost, measured on the 2-core KVM machine this was written on with an empty step between the
// reads: 80 ns of wall time and about 60 reference cycles inside the measured intervals (under
// 0.3% of the cheapest canonical step), but about 1.3 us inside the CPU-time interval, because the
// thread CPU clock is a system call there; cpu_ms is biased up by that much and no more.
#pragma once

#include <cstdint>
#include <string>

namespace fxbench {

struct ClockReading {
  std::int64_t cpu_ns = 0;
  std::int64_t wall_ns = 0;
  std::uint64_t counter = 0;
};

struct StepTiming {
  double wall_ms = 0.0;
  double cpu_ms = 0.0;
  std::uint64_t cycles = 0;
};

ClockReading start_clocks();
StepTiming stop_clocks(const ClockReading& start);

// "tsc-reference-cycles" on x86-64, "steady-clock-ns" elsewhere.
std::string counter_kind();

// Counter ticks per nanosecond, measured by spinning for `interval_ms` against steady_clock.
// Busy rather than asleep, so the core cannot drop into a state where the counter behaves
// differently from a running step.
double measure_counter_ghz(int interval_ms = 50);

}  // namespace fxbench

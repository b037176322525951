// Reads the step clocks; see clocks.h for the nesting invariant and what the counter counts.
#include "measure/clocks.h"

#include <time.h>

#include <chrono>

#if defined(__x86_64__)
#include <x86intrin.h>
#endif

namespace fxbench {
namespace {

std::int64_t thread_cpu_ns() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

#if defined(__x86_64__)
// The fences keep the step's loads from being reordered across the read: without them rdtsc may
// execute before earlier instructions retire and the interval would miss part of the work.
std::uint64_t read_counter() {
  _mm_lfence();
  const std::uint64_t ticks = __rdtsc();
  _mm_lfence();
  return ticks;
}
#else
std::uint64_t read_counter() { return static_cast<std::uint64_t>(steady_ns()); }
#endif

}  // namespace

ClockReading start_clocks() {
  ClockReading start;
  start.cpu_ns = thread_cpu_ns();
  start.wall_ns = steady_ns();
  start.counter = read_counter();
  return start;
}

StepTiming stop_clocks(const ClockReading& start) {
  const std::uint64_t counter = read_counter();
  const std::int64_t wall_ns = steady_ns();
  const std::int64_t cpu_ns = thread_cpu_ns();
  StepTiming timing;
  timing.cycles = counter - start.counter;
  timing.wall_ms = static_cast<double>(wall_ns - start.wall_ns) * 1e-6;
  timing.cpu_ms = static_cast<double>(cpu_ns - start.cpu_ns) * 1e-6;
  return timing;
}

std::string counter_kind() {
#if defined(__x86_64__)
  return "tsc-reference-cycles";
#else
  return "steady-clock-ns";
#endif
}

double measure_counter_ghz(int interval_ms) {
  const std::int64_t interval_ns = static_cast<std::int64_t>(interval_ms) * 1'000'000;
  const std::uint64_t counter_start = read_counter();
  const std::int64_t wall_start = steady_ns();
  std::int64_t wall_now = wall_start;
  while (wall_now - wall_start < interval_ns) wall_now = steady_ns();
  const std::uint64_t counter_end = read_counter();
  return static_cast<double>(counter_end - counter_start) / static_cast<double>(wall_now - wall_start);
}

}  // namespace fxbench

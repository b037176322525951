// Stage timers for FxProfile: a StageClock reads the time-stamp counter where the step moves from
// one stage to the next and charges each stage the cycles it ran. With FX2D_PROFILE off it does
// nothing, so an unprofiled build pays nothing.
#pragma once

#include <chrono>
#include <cstdint>

#include "fx2d/Profile.h"

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace fx2d::detail {

// Reference cycles on x86 (rdtsc: constant rate, unaffected by frequency scaling) and the virtual
// counter on aarch64; elsewhere nanoseconds of the steady clock stand in.
inline std::uint64_t read_cycle_counter() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#elif defined(__aarch64__)
  std::uint64_t value;
  asm volatile("mrs %0, cntvct_el0" : "=r"(value));
  return value;
#else
  return static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
}

// Charges the time between two switches to the stage that ran in between, and the time from the
// last switch to its own end. One counter read per change of stage, and none for a switch to the
// stage already running: a substep without joints changes stage five times (integrate, warm
// start, solve, integrate, relax), where a scope around each of its sections would read the
// counter twice per section and pass (rdtsc takes 20 ns on these virtual machines).
#if FX2D_PROFILE
class StageClock {
 public:
  StageClock(FxProfile& profile, FxStage first) : profile_(profile), stage_(first), start_(read_cycle_counter()) {}
  ~StageClock() { charge(read_cycle_counter()); }
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

  void switch_to(FxStage stage) {
    if (stage == stage_) return;
    const std::uint64_t now = read_cycle_counter();
    charge(now);
    stage_ = stage;
    start_ = now;
  }

 private:
  void charge(std::uint64_t now) { profile_.stage_cycles[static_cast<int>(stage_)] += now - start_; }

  FxProfile& profile_;
  FxStage stage_;
  std::uint64_t start_;
};
#else
class StageClock {
 public:
  StageClock(FxProfile&, FxStage) {}
  void switch_to(FxStage) {}
};
#endif

}  // namespace fx2d::detail

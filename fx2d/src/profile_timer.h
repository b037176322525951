// Stage timers for FxProfile. A scope reads the time-stamp counter at entry and exit and adds the
// difference to its stage; with FX2D_PROFILE off, FX2D_TIME_STAGE expands to nothing, so an
// unprofiled build pays nothing.
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

class StageScope {
 public:
  StageScope(FxProfile& profile, FxStage stage)
      : cycles_(profile.stage_cycles[static_cast<int>(stage)]), start_(read_cycle_counter()) {}
  ~StageScope() { cycles_ += read_cycle_counter() - start_; }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  std::uint64_t& cycles_;
  std::uint64_t start_;
};

}  // namespace fx2d::detail

#define FX2D_CONCAT_INNER(a, b) a##b
#define FX2D_CONCAT(a, b) FX2D_CONCAT_INNER(a, b)
#if FX2D_PROFILE
#define FX2D_TIME_STAGE(profile, stage) \
  ::fx2d::detail::StageScope FX2D_CONCAT(fx2d_stage_scope_, __LINE__)((profile), (stage))
#else
#define FX2D_TIME_STAGE(profile, stage) static_cast<void>(0)
#endif

// A flag handed between two threads (core_latency.h).
#include "measure/core_latency.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace fxbench {
namespace {

constexpr int batches = 9;
constexpr int round_trips_per_batch = 128;
// Spins before a waiting thread yields its core: well past a slow round trip, so a yield only
// happens when the other thread is not running.
constexpr int spins_before_yield = 4096;

// Waits until `flag` holds `value`.
void await(const std::atomic<int>& flag, int value) {
  for (int spins = 0; flag.load(std::memory_order_acquire) != value; ++spins) {
    if (spins >= spins_before_yield) std::this_thread::yield();
  }
}

}  // namespace

double measure_core_round_trip_ns() {
  if (std::thread::hardware_concurrency() < 2) return 0.0;
  // Invariant: an odd value is the partner's turn, an even one the caller's; each hand-over adds 1.
  alignas(64) std::atomic<int> flag{0};
  constexpr int hand_overs = 2 * batches * round_trips_per_batch;
  std::thread partner([&flag] {
    for (int value = 1; value < hand_overs; value += 2) {
      await(flag, value);
      flag.store(value + 1, std::memory_order_release);
    }
  });
  std::vector<double> per_round_trip;
  int value = 0;
  for (int batch = 0; batch < batches; ++batch) {
    const auto start = std::chrono::steady_clock::now();
    for (int trip = 0; trip < round_trips_per_batch; ++trip) {
      flag.store(value + 1, std::memory_order_release);
      value += 2;
      await(flag, value);
    }
    const std::chrono::duration<double, std::nano> took = std::chrono::steady_clock::now() - start;
    per_round_trip.push_back(took.count() / round_trips_per_batch);
  }
  partner.join();
  std::ranges::nth_element(per_round_trip, per_round_trip.begin() + batches / 2);
  return per_round_trip[batches / 2];
}

}  // namespace fxbench

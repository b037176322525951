// The scene's threads: the default pool behind FxTaskScheduler, and Tasks, through which a stage
// runs a loop over its items in ranges (tasks.cpp).
//
// Invariants:
// - the pool's threads start with the scene (or when `workers` changes) and live until it is
//   destroyed; a step creates no thread and allocates nothing;
// - an idle thread blocks on a condition variable after a bounded spin (spin_budget), so a scene
//   that is not stepping costs no core;
// - a range is a whole number of blocks of a size the stage fixes, the same for every worker
//   count: results never depend on how the ranges fall on threads (fx2d/Tasks.h).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "fx2d/Scene.h"
#include "fx2d/Tasks.h"

namespace fx2d::detail {

// workers - 1 threads that, with the thread that waits, run one task at a time. Between the
// tasks of a step the threads spin, so a colour's barrier costs tens of nanoseconds rather than a
// futex wake-up; after spin_budget without a task they block, and a scene at rest costs no core.
class TaskPool {
 public:
  explicit TaskPool(int workers);
  ~TaskPool();
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;

  // enqueue and wait over this pool; the waiting thread runs items too.
  FxTaskScheduler scheduler();

 private:
  struct Job {
    FxTaskFunction task = nullptr;
    std::uint32_t item_count = 0;
    void* context = nullptr;
  };

  static void* enqueue(FxTaskFunction task, std::uint32_t item_count, void* task_context, void* pool);
  static void wait(void* handle, void* pool);
  void work();
  // Spins, then blocks, until a job newer than `seen` is posted; false once the pool stops.
  bool await_job(std::uint32_t seen);
  // The job of an even `sequence`, or false when a newer one is being posted (sequence lock).
  bool read_job(std::uint32_t sequence, Job& job) const;
  // Claims and runs items of the job posted as `sequence` until none is left.
  void run_items(std::uint32_t sequence, const Job& job);
  void wait_until_done() const;

  // The job's fields, written only by the posting thread while `sequence_` is odd.
  std::atomic<FxTaskFunction> task_{nullptr};
  std::atomic<std::uint32_t> item_count_{0};
  std::atomic<void*> context_{nullptr};
  // Even once a job is posted, odd while one is being written: a reader that sees the same even
  // value before and after copying the fields holds one job, never a mix of two.
  std::atomic<std::uint32_t> sequence_{0};
  // sequence << 32 | next unclaimed item: a thread still holding an older job can claim nothing.
  alignas(64) std::atomic<std::uint64_t> next_claim_{0};
  alignas(64) std::atomic<std::uint32_t> unfinished_{0};
  alignas(64) std::atomic<int> sleepers_{0};
  std::mutex mutex_;
  std::condition_variable job_posted_;
  bool stopping_ = false;  // guarded by mutex_
  const bool oversubscribed_;  // more threads than cores: waits yield rather than spin
  std::vector<std::thread> threads_;
};

// A stage's view of the step's threads: runs a loop over ranges on one thread or many.
class Tasks {
 public:
  // (Re)starts the pool when the worker count or the scheduler changed; a step never calls this.
  void configure(const FxSceneSettings& settings);

  int workers() const { return workers_; }

  // Whether for_each_range() spreads this many items over threads.
  bool runs_in_parallel(std::uint32_t item_count, std::uint32_t min_parallel) const {
    return workers_ > 1 && item_count >= min_parallel;
  }

  // One range per worker, in whole granules: a block size for for_each_range() under which the
  // stepping thread claims the first range and a worker the next, so each thread sweeps the same
  // share of a list every time and keeps it in its cache. Blocks claimed one by one fall on the
  // threads differently each time, and each core reads back the bodies the other wrote: on
  // settling_boxes 3000, two workers integrated in 0.76 of one's time that way, 0.59 so. Items of
  // a loop so split must be independent, as the split then changes no bit.
  std::uint32_t per_worker(std::uint32_t item_count, std::uint32_t granule) const {
    const auto workers = static_cast<std::uint32_t>(workers_);
    const std::uint32_t granules = (item_count + granule - 1) / granule;
    return (granules + workers - 1) / workers * granule;
  }

  // Calls body(first, last) over [0, item_count) in ranges of whole blocks of `block` items. On
  // the calling thread alone, as one range, when there is one worker or fewer than `min_parallel`
  // items: there, waking threads would cost more than they take over.
  template <class Body>
  void for_each_range(std::uint32_t item_count, std::uint32_t block, std::uint32_t min_parallel, const Body& body) const {
    if (!runs_in_parallel(item_count, min_parallel)) {
      if (item_count > 0) body(std::uint32_t{0}, item_count);
      return;
    }
    BlockLoop<Body> loop{item_count, block, body};
    const std::uint32_t blocks = (item_count + block - 1) / block;
    scheduler_.wait(scheduler_.enqueue(&BlockLoop<Body>::run, blocks, &loop, scheduler_.user_context),
                    scheduler_.user_context);
  }

 private:
  template <class Body>
  struct BlockLoop {
    std::uint32_t item_count, block;
    const Body& body;
    static void run(std::uint32_t first_block, std::uint32_t end_block, void* context) {
      const auto& loop = *static_cast<const BlockLoop*>(context);
      const std::uint32_t end = end_block * loop.block;
      loop.body(first_block * loop.block, end < loop.item_count ? end : loop.item_count);
    }
  };

  int workers_ = 1;
  FxTaskScheduler user_scheduler_;  // as the settings gave it; empty for the pool
  FxTaskScheduler scheduler_;       // what the loops call: the user's or the pool's
  std::unique_ptr<TaskPool> pool_;
};

}  // namespace fx2d::detail

// The scene's threads: the default pool behind FxTaskScheduler, and Tasks, through which a stage
// runs a loop over its items in ranges (tasks.cpp).
//
// Invariants:
// - the pool's threads start with the scene (or when `workers` changes) and live until it is
//   destroyed; a step creates no thread and allocates nothing;
// - an idle thread blocks on a condition variable after a short bounded spin, so a scene that is
//   not stepping costs no core;
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

// workers - 1 threads that, with the thread that waits, run one task at a time.
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
  // Claims and runs items of job `generation` until none is left or a newer job was posted.
  void run_items(std::uint32_t generation, const Job& job);
  void wait_until_done();

  std::mutex mutex_;
  std::condition_variable job_posted_;
  // Signalled, under mutex_, when the last item of a job finishes. Not std::atomic::wait: without a
  // futex (MinGW) libstdc++ 12 can lose that wake-up, and a step waited forever under Wine.
  std::condition_variable job_done_;
  Job job_;                 // guarded by mutex_
  bool stopping_ = false;   // guarded by mutex_
  std::atomic<std::uint32_t> generation_{0};
  // generation << 32 | next unclaimed item: a thread still holding an older job can claim nothing.
  std::atomic<std::uint64_t> next_claim_{0};
  std::atomic<std::uint32_t> unfinished_{0};
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

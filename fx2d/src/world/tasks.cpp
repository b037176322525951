// The default pool (tasks.h): one task at a time, its items claimed one by one from a counter
// tagged with the task's generation, so a thread that wakes late for a finished task claims
// nothing of the next one.
#include "world/tasks.h"

namespace fx2d::detail {
namespace {

// Polls before blocking: the substep loops post tasks microseconds apart, and a thread that
// is still polling takes the next one without a futex wake-up. Bounded, so an idle scene sleeps.
constexpr int polls_before_blocking = 64;

constexpr std::uint64_t claim_of(std::uint32_t generation, std::uint32_t item) {
  return static_cast<std::uint64_t>(generation) << 32 | item;
}

}  // namespace

TaskPool::TaskPool(int workers) {
  threads_.reserve(static_cast<std::size_t>(workers - 1));
  for (int i = 1; i < workers; ++i) threads_.emplace_back([this] { work(); });
}

TaskPool::~TaskPool() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  job_posted_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

FxTaskScheduler TaskPool::scheduler() { return {&TaskPool::enqueue, &TaskPool::wait, this}; }

void* TaskPool::enqueue(FxTaskFunction task, std::uint32_t item_count, void* task_context, void* pool_pointer) {
  TaskPool& pool = *static_cast<TaskPool*>(pool_pointer);
  {
    const std::lock_guard lock(pool.mutex_);
    pool.job_ = {task, item_count, task_context};
    const std::uint32_t generation = pool.generation_.load(std::memory_order_relaxed) + 1;
    pool.unfinished_.store(item_count, std::memory_order_relaxed);
    pool.next_claim_.store(claim_of(generation, 0), std::memory_order_relaxed);
    pool.generation_.store(generation, std::memory_order_release);
  }
  pool.job_posted_.notify_all();
  return nullptr;
}

void TaskPool::wait(void*, void* pool_pointer) {
  TaskPool& pool = *static_cast<TaskPool*>(pool_pointer);
  // Only this thread posts jobs, so job_ and generation_ cannot change under it.
  pool.run_items(pool.generation_.load(std::memory_order_relaxed), pool.job_);
  pool.wait_until_done();
}

void TaskPool::work() {
  std::uint32_t seen = 0;
  for (;;) {
    for (int poll = 0; poll < polls_before_blocking && generation_.load(std::memory_order_acquire) == seen; ++poll) {
      std::this_thread::yield();
    }
    Job job;
    {
      std::unique_lock lock(mutex_);
      job_posted_.wait(lock, [&] { return stopping_ || generation_.load(std::memory_order_relaxed) != seen; });
      if (stopping_) return;
      seen = generation_.load(std::memory_order_relaxed);
      job = job_;
    }
    run_items(seen, job);
  }
}

void TaskPool::run_items(std::uint32_t generation, const Job& job) {
  std::uint64_t claim = next_claim_.load(std::memory_order_relaxed);
  for (;;) {
    const auto item = static_cast<std::uint32_t>(claim);
    if (claim >> 32 != generation || item >= job.item_count) return;
    if (!next_claim_.compare_exchange_weak(claim, claim + 1, std::memory_order_relaxed)) continue;
    job.task(item, item + 1, job.context);
    // Release: the waiting thread reads what the item wrote once it sees the count reach zero.
    if (unfinished_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      const std::lock_guard lock(mutex_);
      job_done_.notify_all();
    }
    claim = next_claim_.load(std::memory_order_relaxed);
  }
}

void TaskPool::wait_until_done() {
  for (int poll = 0;; ++poll) {
    const std::uint32_t unfinished = unfinished_.load(std::memory_order_acquire);
    if (unfinished == 0) return;
    if (poll < polls_before_blocking) {
      std::this_thread::yield();
    } else {
      std::unique_lock lock(mutex_);
      job_done_.wait(lock, [&] { return unfinished_.load(std::memory_order_acquire) == 0; });
    }
  }
}

void Tasks::configure(const FxSceneSettings& settings) {
  const FxTaskScheduler& wanted = settings.scheduler;
  if (settings.workers == workers_ && wanted.enqueue == user_scheduler_.enqueue && wanted.wait == user_scheduler_.wait &&
      wanted.user_context == user_scheduler_.user_context) {
    return;
  }
  pool_.reset();
  workers_ = settings.workers;
  user_scheduler_ = wanted;
  if (wanted.enqueue == nullptr && workers_ > 1) pool_ = std::make_unique<TaskPool>(workers_);
  scheduler_ = pool_ ? pool_->scheduler() : wanted;
}

}  // namespace fx2d::detail

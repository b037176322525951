// The default pool (tasks.h): one task at a time, posted under a sequence lock, its items claimed
// one by one from a counter tagged with the task's sequence, so a thread that wakes late for a
// finished task claims nothing of the next one.
#include "world/tasks.h"

#include <algorithm>
#include <chrono>

namespace fx2d::detail {
namespace {

// How long an idle thread spins for the next task before it blocks: longer than the serial stages
// between two tasks of a step (colouring a large scene takes tens of microseconds), so the threads
// stay awake through a step, and a thousandth of a 60 Hz frame once the step is over.
constexpr auto spin_budget = std::chrono::microseconds(200);
// Spins between two readings of the clock.
constexpr int spins_per_clock_reading = 64;

// Tells the core that this thread is spinning (it saves power and frees the pipeline).
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

constexpr std::uint64_t claim_of(std::uint32_t sequence, std::uint32_t item) {
  return static_cast<std::uint64_t>(sequence) << 32 | item;
}

// Spins until done() holds (true) or spin_budget has passed (false). With more threads than
// cores a spinning thread may hold the core the thread it waits for needs, so it yields instead.
template <class Done>
bool spin_until(bool oversubscribed, const Done& done) {
  const auto deadline = std::chrono::steady_clock::now() + spin_budget;
  for (;;) {
    for (int spin = 0; spin < spins_per_clock_reading; ++spin) {
      if (done()) return true;
      if (oversubscribed) {
        std::this_thread::yield();
      } else {
        cpu_relax();
      }
    }
    if (std::chrono::steady_clock::now() > deadline) return false;
  }
}

}  // namespace

TaskPool::TaskPool(int workers)
    : oversubscribed_(static_cast<unsigned>(workers) > std::max(1u, std::thread::hardware_concurrency())) {
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
  // Only this thread posts, and only once the last job finished: no thread is inside a job.
  const std::uint32_t writing = pool.sequence_.load(std::memory_order_relaxed) + 1;
  pool.sequence_.store(writing, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  pool.task_.store(task, std::memory_order_relaxed);
  pool.item_count_.store(item_count, std::memory_order_relaxed);
  pool.context_.store(task_context, std::memory_order_relaxed);
  pool.unfinished_.store(item_count, std::memory_order_relaxed);
  pool.next_claim_.store(claim_of(writing + 1, 0), std::memory_order_relaxed);
  // Sequentially consistent with the load of sleepers_ below and a blocking thread's increment of
  // it before its own load of sequence_: one of the two sees the other, so no wake-up is lost.
  pool.sequence_.store(writing + 1, std::memory_order_seq_cst);
  if (pool.sleepers_.load(std::memory_order_seq_cst) > 0) {
    { const std::lock_guard lock(pool.mutex_); }
    pool.job_posted_.notify_all();
  }
  return nullptr;
}

void TaskPool::wait(void*, void* pool_pointer) {
  TaskPool& pool = *static_cast<TaskPool*>(pool_pointer);
  const std::uint32_t sequence = pool.sequence_.load(std::memory_order_relaxed);
  Job job;
  pool.read_job(sequence, job);  // the posting thread's own job: always whole
  pool.run_items(sequence, job);
  pool.wait_until_done();
}

void TaskPool::work() {
  std::uint32_t seen = 0;
  while (await_job(seen)) {
    seen = sequence_.load(std::memory_order_acquire);
    Job job;
    if (read_job(seen, job)) run_items(seen, job);
  }
}

bool TaskPool::await_job(std::uint32_t seen) {
  const auto posted = [&] { return sequence_.load(std::memory_order_seq_cst) != seen; };
  if (spin_until(oversubscribed_, posted)) return true;
  std::unique_lock lock(mutex_);
  sleepers_.fetch_add(1, std::memory_order_seq_cst);
  job_posted_.wait(lock, [&] { return stopping_ || posted(); });
  sleepers_.fetch_sub(1, std::memory_order_relaxed);
  return !stopping_;
}

bool TaskPool::read_job(std::uint32_t sequence, Job& job) const {
  if (sequence % 2 != 0) return false;
  job = {task_.load(std::memory_order_relaxed), item_count_.load(std::memory_order_relaxed),
         context_.load(std::memory_order_relaxed)};
  std::atomic_thread_fence(std::memory_order_acquire);
  return sequence_.load(std::memory_order_relaxed) == sequence;
}

void TaskPool::run_items(std::uint32_t sequence, const Job& job) {
  std::uint64_t claim = next_claim_.load(std::memory_order_relaxed);
  for (;;) {
    const auto item = static_cast<std::uint32_t>(claim);
    if (claim >> 32 != sequence || item >= job.item_count) return;
    if (!next_claim_.compare_exchange_weak(claim, claim + 1, std::memory_order_relaxed)) continue;
    job.task(item, item + 1, job.context);
    // Release: the waiting thread reads what the item wrote once it sees the count reach zero.
    unfinished_.fetch_sub(1, std::memory_order_release);
    claim = next_claim_.load(std::memory_order_relaxed);
  }
}

void TaskPool::wait_until_done() const {
  const auto done = [&] { return unfinished_.load(std::memory_order_acquire) == 0; };
  while (!spin_until(oversubscribed_, done)) std::this_thread::yield();
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

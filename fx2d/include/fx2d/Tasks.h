// How a step spreads its work over threads: a worker count and, optionally, the user's own task
// scheduler (a job system of a game or a tool), in the style of Box2D's enqueue and finish callbacks.
//
// Invariant: the results do not depend on the threads. A parallel stage cuts its items (contact
// pairs, bodies) into ranges by a rule that depends only on the scene, each range writes only its
// own items, and whatever the stage then adds up runs on the stepping thread in a fixed order. Any
// worker count and any scheduler, run in any order on any threads, give the same bits.
#pragma once

#include <cstdint>

namespace fx2d {

// Runs items [begin, end) of a task. Ranges of one task never overlap; any thread may run them.
using FxTaskFunction = void (*)(std::uint32_t begin, std::uint32_t end, void* task_context);

// A scheduler the scene hands its parallel stages to, instead of its own pool. A step enqueues
// one task at a time and waits for it before enqueuing the next, always from the thread that
// called FxScene::step().
struct FxTaskScheduler {
  // Runs task(begin, end, task_context) over ranges that together cover [0, item_count) once,
  // on any threads, now or before `wait` returns; returns a handle for `wait` (may be null).
  void* (*enqueue)(FxTaskFunction task, std::uint32_t item_count, void* task_context, void* user_context) = nullptr;
  // Returns once every range of the task `enqueue` returned `handle` for has run.
  void (*wait)(void* handle, void* user_context) = nullptr;
  void* user_context = nullptr;  // passed to both callbacks as they are
};

}  // namespace fx2d

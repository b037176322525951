// SIGINT handling; the invariant is in interrupt.h.
#include "measure/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace fxbench {
namespace {

std::atomic<bool> interrupt_flag{false};
static_assert(std::atomic<bool>::is_always_lock_free, "only a lock-free atomic may be touched in a signal handler");

void on_sigint(int) {
  // The user asked twice: nothing more is saved, and _exit runs no destructor or atexit hook.
  if (interrupt_flag.exchange(true, std::memory_order_relaxed)) _exit(exit_interrupted);
}

}  // namespace

ScopedInterruptHandler::ScopedInterruptHandler() {
  interrupt_flag.store(false, std::memory_order_relaxed);
  struct sigaction action {};
  action.sa_handler = on_sigint;
  sigemptyset(&action.sa_mask);
  // Restart interrupted system calls, so a Ctrl-C never turns a file write into an I/O error.
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &previous_);
}

ScopedInterruptHandler::~ScopedInterruptHandler() { sigaction(SIGINT, &previous_, nullptr); }

bool interrupt_requested() { return interrupt_flag.load(std::memory_order_relaxed); }

void exit_after_interrupt(const std::string& message) {
  std::fflush(stdout);
  std::fprintf(stderr, "fx2d-bench: %s\n", message.c_str());
  std::exit(exit_interrupted);
}

}  // namespace fxbench

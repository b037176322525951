// Ctrl-C for long measurements: the first SIGINT asks the running command to stop at its next
// safe point (between two steps), so that what was measured so far can still be saved; a second
// SIGINT ends the process at once, exit code 130, without writing anything.
//
// Invariant: the signal handler does nothing but set a lock-free atomic flag or call _exit, both
// async-signal-safe; every other reaction to an interruption happens on the normal control path
// of whoever polls interrupt_requested().
#pragma once

#include <csignal>
#include <string>

namespace fxbench {

// The shell's convention for "ended by SIGINT" (128 + 2), for scripts that wrap fx2d-bench.
inline constexpr int exit_interrupted = 130;

// Installs the SIGINT handler for its lifetime and clears any earlier request; the previous
// disposition comes back when it is destroyed.
class ScopedInterruptHandler {
 public:
  ScopedInterruptHandler();
  ScopedInterruptHandler(const ScopedInterruptHandler&) = delete;
  ScopedInterruptHandler& operator=(const ScopedInterruptHandler&) = delete;
  ~ScopedInterruptHandler();

 private:
  struct sigaction previous_ {};
};

// True once a SIGINT has arrived while a ScopedInterruptHandler was installed. Cheap enough to
// poll between steps: one relaxed atomic load.
bool interrupt_requested();

// Prints "fx2d-bench: <message>" as the command's one line on stderr and exits with
// exit_interrupted, after flushing stdout.
[[noreturn]] void exit_after_interrupt(const std::string& message);

}  // namespace fxbench

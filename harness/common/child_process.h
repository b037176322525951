// Starting a program as a child process and waiting for it: the one piece of code behind every
// program fx2d-bench runs (cmake and git for `ab` builds, valgrind for --counter instructions,
// python3 for `report`).
//
// Invariants: the program is looked up on PATH unless its name holds a '/'; it gets this
// process's environment; its streams are the given file descriptors or, where none is given,
// this process's own; the wait survives signals (EINTR) and returns only once the child ended.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace fxbench {

// Where a child's standard streams go: a file descriptor of this process, or -1 to share this
// process's own. The descriptors stay open here; the caller closes them.
struct ChildStreams {
  int in = -1;
  int out = -1;
  int err = -1;
};

struct ChildEnding {
  int spawn_error = 0;   // errno of a child that could not start (program not found, say), else 0
  int exit_status = -1;  // its exit status; -1 when it could not start or a signal ended it
  int signal = 0;        // the signal that ended it, or 0

  bool started() const { return spawn_error == 0; }
};

// Starts argv[0] with the arguments argv[1...]; the child's pid, or -1 with `spawn_error` set.
// For a caller that has to read the child's output while it runs; wait_for_child ends it.
pid_t spawn_child(const std::vector<std::string>& argv, const ChildStreams& streams, int& spawn_error);

// Waits for a started child to end and says how it ended.
ChildEnding wait_for_child(pid_t child);

// Both: starts argv and waits for it.
ChildEnding run_child(const std::vector<std::string>& argv, const ChildStreams& streams);

// The running program's own file, absolute (/proc/self/exe): what a child that runs fx2d-bench
// again starts, and where the engine plugins an install puts beside it are found from.
std::string own_executable();

}  // namespace fxbench

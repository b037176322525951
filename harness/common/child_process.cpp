// Children by posix_spawnp; the contracts are in child_process.h.
#include "common/child_process.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <utility>

extern char** environ;

namespace fxbench {

pid_t spawn_child(const std::vector<std::string>& argv, const ChildStreams& streams, int& spawn_error) {
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::pair<int, int> redirections[] = {
      {streams.in, STDIN_FILENO}, {streams.out, STDOUT_FILENO}, {streams.err, STDERR_FILENO}};
  for (const auto& [from, to] : redirections)
    if (from >= 0) posix_spawn_file_actions_adddup2(&actions, from, to);
  pid_t child = -1;
  spawn_error = posix_spawnp(&child, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return spawn_error == 0 ? child : -1;
}

ChildEnding wait_for_child(pid_t child) {
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) return {};  // not our child, or already waited for: its ending is lost
  ChildEnding ending;
  if (WIFEXITED(status)) ending.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) ending.signal = WTERMSIG(status);
  return ending;
}

ChildEnding run_child(const std::vector<std::string>& argv, const ChildStreams& streams) {
  int spawn_error = 0;
  const pid_t child = spawn_child(argv, streams, spawn_error);
  if (child < 0) return {.spawn_error = spawn_error, .exit_status = -1, .signal = 0};
  return wait_for_child(child);
}

std::string own_executable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

}  // namespace fxbench

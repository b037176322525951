// The fx2d-bench binary as a child process, for the tests that need a real process: one to kill,
// interrupt, or measure (exit status, stdout, stderr, peak memory, wall time).
//
// Invariant: every child started is waited for exactly once, by finish(), which also collects its
// own resource usage (wait4), so the peak memory reported is that child's alone.
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace fxbench::bench_test {

// How a child ended: by a signal (`signal` != 0) or with `exit_code`.
struct Ending {
  int signal = 0;
  int exit_code = -1;
  std::string out;
  std::string err;
  long peak_rss_kib = 0;  // the child's high-water resident set
  double seconds = 0;     // from start to reaped
};

class BenchProcess {
 public:
  // Starts FX2D_BENCH_EXE with `arguments`, in this process's environment plus `extra_environment`
  // ("NAME=value" each); stdout and stderr go to stdout.txt and stderr.txt in `directory`.
  BenchProcess(std::vector<std::string> arguments, const std::filesystem::path& directory,
               std::vector<std::string> extra_environment = {})
      : out_path_(directory / "stdout.txt"), err_path_(directory / "stderr.txt") {
    arguments.insert(arguments.begin(), FX2D_BENCH_EXE);
    std::vector<char*> argv;
    for (std::string& argument : arguments) argv.push_back(argument.data());
    argv.push_back(nullptr);
    std::vector<char*> environment;
    for (char** variable = environ; *variable != nullptr; ++variable) environment.push_back(*variable);
    for (std::string& variable : extra_environment) environment.push_back(variable.data());
    environment.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&files, STDERR_FILENO, err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int failed = posix_spawn(&pid_, FX2D_BENCH_EXE, &files, nullptr, argv.data(), environment.data());
    posix_spawn_file_actions_destroy(&files);
    if (failed != 0) throw std::runtime_error(std::string("cannot start ") + FX2D_BENCH_EXE);
  }

  pid_t pid() const { return pid_; }

  // Without reaping it, so finish() still gets its status.
  bool running() const {
    siginfo_t info{};
    return waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == 0;
  }

  void send(int signal) const { kill(pid_, signal); }

  Ending finish() const {
    int status = 0;
    rusage usage{};
    wait4(pid_, &status, 0, &usage);
    Ending ending;
    ending.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    if (WIFSIGNALED(status)) ending.signal = WTERMSIG(status);
    if (WIFEXITED(status)) ending.exit_code = WEXITSTATUS(status);
    ending.peak_rss_kib = usage.ru_maxrss;  // Linux reports kibibytes
    ending.out = contents(out_path_);
    ending.err = contents(err_path_);
    return ending;
  }

 private:
  static std::string contents(const std::filesystem::path& path) {
    std::ifstream file(path);
    return {std::istreambuf_iterator<char>(file), {}};
  }

  std::filesystem::path out_path_;
  std::filesystem::path err_path_;
  pid_t pid_ = -1;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

// Runs fx2d-bench with `arguments` to the end.
inline Ending run_bench(std::vector<std::string> arguments, const std::filesystem::path& directory) {
  return BenchProcess(std::move(arguments), directory).finish();
}

// The same, from `working_directory`, where the relative paths it reads are found (`worktree` and
// revisions name its git checkout; a policy's scene files).
inline Ending run_bench_from(const std::filesystem::path& working_directory,
                             std::vector<std::string> arguments, const std::filesystem::path& directory) {
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(working_directory);
  Ending ending = run_bench(std::move(arguments), directory);
  std::filesystem::current_path(before);
  return ending;
}

}  // namespace fxbench::bench_test

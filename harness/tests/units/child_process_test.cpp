// Tests of the child-process helper behind `ab` builds, --counter instructions and `report`: the
// exit status, a program that cannot start, a signal, streams sent to the descriptors given, and
// a wait that outlasts signals delivered to this process.
#include "common/child_process.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace fxbench {
namespace {

namespace fs = std::filesystem;

std::string file_text(const fs::path& path) {
  std::ifstream file(path);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

TEST(ChildProcess, ExitStatusIsTheChildsAndPathIsSearched) {
  EXPECT_EQ(run_child({"sh", "-c", "exit 0"}, {}).exit_status, 0);
  const ChildEnding ending = run_child({"sh", "-c", "exit 7"}, {});
  EXPECT_TRUE(ending.started());
  EXPECT_EQ(ending.exit_status, 7);
  EXPECT_EQ(ending.signal, 0);
}

TEST(ChildProcess, AProgramThatCannotStartIsMinusOneWithItsError) {
  const ChildEnding ending = run_child({"fx2d-bench-no-such-program"}, {});
  EXPECT_FALSE(ending.started());
  EXPECT_EQ(ending.spawn_error, ENOENT);
  EXPECT_EQ(ending.exit_status, -1);
}

TEST(ChildProcess, ASignalEndingTheChildIsNamedAndItsStatusIsMinusOne) {
  const ChildEnding ending = run_child({"sh", "-c", "kill -TERM $$"}, {});
  EXPECT_TRUE(ending.started());
  EXPECT_EQ(ending.exit_status, -1);
  EXPECT_EQ(ending.signal, SIGTERM);
}

TEST(ChildProcess, StreamsGoToTheDescriptorsGiven) {
  const fs::path out_path = fs::temp_directory_path() / ("fx2d_child_out_" + std::to_string(getpid()));
  const fs::path err_path = fs::temp_directory_path() / ("fx2d_child_err_" + std::to_string(getpid()));
  const int in = open("/dev/null", O_RDONLY | O_CLOEXEC);
  const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  ASSERT_TRUE(in >= 0 && out >= 0 && err >= 0);
  // `cat` copies stdin (empty: /dev/null) before the two lines.
  const ChildEnding ending =
      run_child({"sh", "-c", "cat; echo to-out; echo to-err >&2"}, {.in = in, .out = out, .err = err});
  close(in);
  close(out);
  close(err);
  EXPECT_EQ(ending.exit_status, 0);
  EXPECT_EQ(file_text(out_path), "to-out\n");
  EXPECT_EQ(file_text(err_path), "to-err\n");
  fs::remove(out_path);
  fs::remove(err_path);
}

TEST(ChildProcess, TheWaitOutlastsSignalsToThisProcess) {
  struct sigaction handler = {};
  handler.sa_handler = [](int) {};  // no SA_RESTART: waitpid fails with EINTR
  struct sigaction previous = {};
  ASSERT_EQ(sigaction(SIGALRM, &handler, &previous), 0);
  int spawn_error = 0;
  const pid_t child = spawn_child({"sh", "-c", "sleep 0.3; exit 3"}, {}, spawn_error);
  ASSERT_GT(child, 0);
  ualarm(50'000, 50'000);  // several interruptions during the wait
  const ChildEnding ending = wait_for_child(child);
  ualarm(0, 0);
  sigaction(SIGALRM, &previous, nullptr);
  EXPECT_EQ(ending.exit_status, 3);
}

}  // namespace
}  // namespace fxbench

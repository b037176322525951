// Tests of ci/nightly's command line: every usage error (a missing value, options that conflict,
// a path of the wrong kind) is one line on stderr and exit code 2, as ci/README.md promises, never
// 1 (the regression code) nor 4, and is found before anything is built or measured.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "common/child_process.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

class NightlyCommandLine : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("fx2d_nightly_test_" + std::to_string(getpid()));
    fs::create_directories(directory_);
    // Should a misuse get past the checks, the night must not build into the checkout.
    setenv("FX2D_BENCH", FX2D_BENCH_EXE, 1);
    setenv("FX2D_NIGHTLY_DIR", (directory_ / "work").c_str(), 1);
  }
  void TearDown() override {
    unsetenv("FX2D_BENCH");
    unsetenv("FX2D_NIGHTLY_DIR");
    fs::remove_all(directory_);
  }

  // ci/nightly's exit status, with its stderr in `err`.
  int nightly(const std::vector<std::string>& arguments, std::string& err) const {
    std::vector<std::string> argv = {std::string(FX2D_SOURCE_DIR) + "/ci/nightly"};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    const fs::path err_path = directory_ / "stderr.txt";
    const int err_fd = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    const int out_fd = open("/dev/null", O_WRONLY | O_CLOEXEC);
    const ChildEnding ending = run_child(argv, {.in = -1, .out = out_fd, .err = err_fd});
    close(err_fd);
    close(out_fd);
    std::ifstream file(err_path);
    err.assign(std::istreambuf_iterator<char>(file), {});
    return ending.exit_status;
  }

  fs::path directory_;
};

TEST_F(NightlyCommandLine, EveryUsageErrorIsOneLineAndExitCodeTwo) {
  const std::string file = (directory_ / "a-file").string();
  std::ofstream(file) << "not a directory";
  const std::vector<std::pair<std::vector<std::string>, std::string>> misuses = {
      {{"--why"}, "--why needs a value"},                           // missing value
      {{"--accept", "--why"}, "--why needs a value"},
      {{"--why", "--accept"}, "--why needs a value"},               // the value is the next option
      {{"--history"}, "--history needs a value"},
      {{"--out"}, "--out needs a value"},
      {{"--nightly"}, "unknown option '--nightly'"},
      {{"--smoke", "--accept"}, "--smoke measures too little"},     // conflicting options
      {{"--why", "faster"}, "--why explains an --accept"},
      {{"--smoke", "--history", file}, "--history does not apply to --smoke"},
      {{"--out", file}, "--out " + file + ": exists and is not a directory"},  // wrong kind of path
      {{"--history", directory_.string()}, "--history " + directory_.string() + ": a directory, expected a file"},
      {{"--shard"}, "--shard needs a value"},
      {{"--collect"}, "--collect needs a value"},
      {{"--shard", "1/2", "--collect", directory_.string()}, "--shard measures one part, --collect judges them all"},
      {{"--shard", "1/2", "--accept"}, "--accept needs the whole night"},
      {{"--shard", "1/2", "--history", file}, "--history: a part writes no history"},
      {{"--collect", directory_.string()}, "--collect " + directory_.string() + ": no shard.txt"},
  };
  for (const auto& [arguments, expected] : misuses) {
    std::string err;
    EXPECT_EQ(nightly(arguments, err), 2) << arguments.front() << ": " << err;
    EXPECT_EQ(std::ranges::count(err, '\n'), 1) << err;
    EXPECT_NE(err.find("ci/nightly: " + expected), std::string::npos) << err;
  }
  EXPECT_FALSE(fs::exists(directory_ / "work"));
}

TEST_F(NightlyCommandLine, AnFx2dBenchThatIsNotAProgramIsOneLineAndExitCodeTwo) {
  const std::string scene = std::string(FX2D_SOURCE_DIR) + "/scenes/pile.json";
  setenv("FX2D_BENCH", scene.c_str(), 1);
  std::string err;
  EXPECT_EQ(nightly({"--smoke", "--out", (directory_ / "smoke").string()}, err), 2) << err;
  EXPECT_EQ(std::ranges::count(err, '\n'), 1) << err;
  EXPECT_NE(err.find("ci/nightly: no fx2d-bench at " + scene), std::string::npos) << err;
}

}  // namespace
}  // namespace fxbench

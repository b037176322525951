// Tests of write_atomically (atomic_file.h): the new content replaces the old only as a whole, the
// stages come in their documented order, and a failure at any stage before the rename leaves the
// old file as it was and no temporary behind. (That the fsyncs reach the disk is not observable
// without cutting the power; crash_safety_test kills writers at random moments instead.)
#include "storage/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/errors.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() /
                 ("fx2d_atomic_file_test." + std::to_string(getpid()) + "." +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
    path_ = (directory_ / "history.h5").string();
  }
  void TearDown() override { fs::remove_all(directory_); }

  static void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }
  static std::string text_of(const std::string& path) {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(directory_)) names.push_back(entry.path().filename().string());
    return names;
  }

  fs::path directory_;
  std::string path_;
};

TEST_F(AtomicFile, ReplacesTheFileThroughATemporaryBesideIt) {
  write_text(path_, "old");
  std::vector<std::string> seen;
  write_atomically(
      path_,
      [&](const std::string& temporary) {
        EXPECT_EQ(fs::path(temporary).parent_path(), directory_) << "same directory, so rename is atomic";
        EXPECT_EQ(text_of(path_), "old") << "the target is untouched while the new content is written";
        write_text(temporary, "new");
      },
      [&](std::string_view stage) { seen.emplace_back(stage); });
  EXPECT_EQ(text_of(path_), "new");
  EXPECT_EQ(seen, (std::vector<std::string>{"written", "synced", "renamed"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"history.h5"});
}

TEST_F(AtomicFile, FailureAtAnyStageBeforeTheRenameKeepsTheOldFileAndNoTemporary) {
  for (const std::string failing : {"write", "written", "synced"}) {
    SCOPED_TRACE(failing);
    write_text(path_, "old");
    EXPECT_THROW(write_atomically(
                     path_,
                     [&](const std::string& temporary) {
                       write_text(temporary, "half");
                       if (failing == "write") throw std::runtime_error("disk full");
                     },
                     [&](std::string_view stage) {
                       if (stage == failing) throw std::runtime_error("interrupted");
                     }),
                 std::runtime_error);
    EXPECT_EQ(text_of(path_), "old");
    EXPECT_EQ(entries(), std::vector<std::string>{"history.h5"});
  }
}

TEST_F(AtomicFile, UnwritableDirectoryIsAnInputErrorNamingThePath) {
  const std::string nowhere = (directory_ / "missing" / "history.h5").string();
  try {
    write_atomically(nowhere, [](const std::string& temporary) { write_text(temporary, "new"); });
    ADD_FAILURE() << "wrote into a missing directory";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind(nowhere + ": ", 0), 0u) << error.what();
  }
}

}  // namespace
}  // namespace fxbench

// A test fixture with a scratch directory for plugin copies. dlopen() of one path twice returns
// the same library, so loading two builds at once (an A/A pair) needs the plugin under two names.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace fxbench::test {

class PluginCopies : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 (std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "." +
                  std::to_string(::getpid()));
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  // `library` copied into the scratch directory as `name`.
  std::string copy_of(const std::string& library, const std::string& name) const {
    const std::filesystem::path copy = directory_ / name;
    std::filesystem::copy_file(library, copy, std::filesystem::copy_options::overwrite_existing);
    return copy.string();
  }

  std::filesystem::path directory_;
};

}  // namespace fxbench::test

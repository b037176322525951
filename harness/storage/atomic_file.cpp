// Temporary, fsync, rename, fsync the directory; the invariant is in atomic_file.h.
#include "storage/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include "common/errors.h"

namespace fxbench {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError(path + ": " + what + ": " + std::strerror(errno));
}

// Flushes `name` (a file, or a directory opened read-only, as Linux allows) to disk.
void sync_to_disk(const std::string& path, const std::string& name) {
  const int descriptor = ::open(name.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor < 0) fail(path, "cannot open " + name + " to sync it");
  const int synced = ::fsync(descriptor);
  const int saved_errno = errno;
  ::close(descriptor);
  errno = saved_errno;
  if (synced != 0) fail(path, "cannot sync " + name + " to disk");
}

// Test-only and undocumented for users: crash_safety_test sets FX2D_ATOMIC_FILE_TEST_PAUSE_MS in
// the fx2d-bench it signals during a write, so that the moment between a complete temporary file
// and the rename lasts long enough for its signals to land there on a slow, loaded machine.
void pause_before_rename_for_tests() {
  if (const char* milliseconds = std::getenv("FX2D_ATOMIC_FILE_TEST_PAUSE_MS"))
    std::this_thread::sleep_for(std::chrono::milliseconds(std::atoi(milliseconds)));
}

std::string directory_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

}  // namespace

void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& write,
                      const AtomicWriteStage& at_stage) {
  const auto stage = [&](std::string_view name) {
    if (at_stage) at_stage(name);
  };
  const std::string temporary = path + ".tmp." + std::to_string(::getpid());
  try {
    write(temporary);
    stage("written");
    sync_to_disk(path, temporary);
    stage("synced");
    pause_before_rename_for_tests();
    if (std::rename(temporary.c_str(), path.c_str()) != 0) fail(path, "cannot rename " + temporary + " into place");
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  sync_to_disk(path, directory_of(path));
  stage("renamed");
}

}  // namespace fxbench

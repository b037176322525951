// Whole-file reads of user input, bounded by the bytes read; see bounded_read.h.
#include "common/bounded_read.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>

#include "common/errors.h"

namespace fxbench {
namespace {

// Closes the descriptor on every path out, including a throw.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

std::string size_text(std::size_t bytes) {
  return bytes % (std::size_t{1} << 20) == 0 ? std::to_string(bytes >> 20) + " MiB" : std::to_string(bytes) + " bytes";
}

}  // namespace

std::string read_bounded_file(const std::string& path, const std::string& kind, std::size_t max_bytes) {
  const FileDescriptor file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (file.get() < 0) throw InputError(path + ": cannot open: " + std::strerror(errno));
  const auto too_large = [&] {
    return InputError(path + ": more than " + size_text(max_bytes) + ", expected " + kind + " of at most " +
                      size_text(max_bytes));
  };
  // A regular file's size is known: one too large is refused without reading a byte of it.
  struct stat status {};
  if (::fstat(file.get(), &status) == 0 && S_ISREG(status.st_mode) && static_cast<std::uintmax_t>(status.st_size) > max_bytes)
    throw too_large();
  // Room for one byte past the bound, reserved once: pages are touched only as bytes arrive, and no
  // regrowth copies the text, so the peak is the bytes read plus one chunk.
  std::string text;
  text.reserve(max_bytes + 1);
  std::array<char, 64 * 1024> chunk;
  while (text.size() <= max_bytes) {
    const ssize_t got = ::read(file.get(), chunk.data(), std::min(chunk.size(), max_bytes + 1 - text.size()));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw InputError(path + ": cannot read: " + std::strerror(errno));
    if (got == 0) return text;
    text.append(chunk.data(), static_cast<std::size_t>(got));
  }
  throw too_large();
}

}  // namespace fxbench

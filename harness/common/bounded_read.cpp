// Whole-file reads of user input, bounded by the bytes read; see bounded_read.h. C's stdio, so the
// portable part of the harness reads files the same way on every platform it is built for.
#include "common/bounded_read.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "common/errors.h"

namespace fxbench {
namespace {

// Closes the file on every path out, including a throw.
class OpenFile {
 public:
  explicit OpenFile(std::FILE* file) : file_(file) {}
  OpenFile(const OpenFile&) = delete;
  OpenFile& operator=(const OpenFile&) = delete;
  ~OpenFile() {
    if (file_ != nullptr) std::fclose(file_);
  }
  std::FILE* get() const { return file_; }

 private:
  std::FILE* file_;
};

std::string size_text(std::size_t bytes) {
  return bytes % (std::size_t{1} << 20) == 0 ? std::to_string(bytes >> 20) + " MiB" : std::to_string(bytes) + " bytes";
}

}  // namespace

std::string read_bounded_file(const std::string& path, const std::string& kind, std::size_t max_bytes) {
  const OpenFile file(std::fopen(path.c_str(), "rb"));
  if (file.get() == nullptr) throw InputError(path + ": cannot open: " + std::strerror(errno));
  const auto too_large = [&] {
    return InputError(path + ": more than " + size_text(max_bytes) + ", expected " + kind + " of at most " +
                      size_text(max_bytes));
  };
  // A regular file's size is known: one too large is refused without reading a byte of it.
  std::error_code error;
  if (std::filesystem::is_regular_file(path, error) && std::filesystem::file_size(path, error) > max_bytes && !error)
    throw too_large();
  // Room for one byte past the bound, reserved once: pages are touched only as bytes arrive, and no
  // regrowth copies the text, so the peak is the bytes read plus one chunk.
  std::string text;
  text.reserve(max_bytes + 1);
  std::array<char, 64 * 1024> chunk;
  while (text.size() <= max_bytes) {
    const std::size_t got = std::fread(chunk.data(), 1, std::min(chunk.size(), max_bytes + 1 - text.size()), file.get());
    text.append(chunk.data(), got);
    if (got > 0) continue;
    if (std::ferror(file.get())) throw InputError(path + ": cannot read: " + std::strerror(errno));
    return text;
  }
  throw too_large();
}

void require_regular_file(const std::string& path, const std::string& named) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw InputError(named + ": no such file");
  if (!std::filesystem::is_regular_file(status)) throw InputError(named + ": not a regular file");
}

}  // namespace fxbench

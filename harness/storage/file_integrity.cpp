// Writing and checking the seal in an HDF5 user block; the format and invariant are in
// file_integrity.h.
#include "storage/file_integrity.h"

#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "common/errors.h"
#include "common/hash.h"

namespace fxbench {
namespace {

constexpr std::string_view magic_line = "fx2d-bench sealed HDF5 file\n";
constexpr unsigned seal_format = 1;
// HDF5's format signature, which libhdf5 looks for at byte 0, 512, 1024, ...: a sealable file
// has it right after the user block.
constexpr std::string_view hdf5_signature = "\x89HDF\r\n\x1a\n";

using SealBlock = std::array<char, h5_seal_bytes>;

struct Seal {
  unsigned format = 0;
  std::uint64_t length = 0;
  std::uint64_t checksum = 0;
};

SealBlock render(const Seal& seal) {
  SealBlock block{};
  std::snprintf(block.data(), block.size(), "%.*sformat %u\nlength %020" PRIu64 "\nchecksum fnv1a64 %016" PRIx64 "\n",
                static_cast<int>(magic_line.size()), magic_line.data(), seal.format, seal.length, seal.checksum);
  return block;
}

// The seal `block` states, or nothing when it is not in exactly the form render() writes.
bool parse(const SealBlock& block, Seal& seal) {
  const std::string text(block.data(), block.size());  // NUL-terminated for sscanf, whatever the block holds
  const std::string pattern =
      std::string(magic_line) + "format %u\nlength %" SCNu64 "\nchecksum fnv1a64 %" SCNx64 "\n";
  if (std::sscanf(text.c_str(), pattern.c_str(), &seal.format, &seal.length, &seal.checksum) != 3) return false;
  return render(seal) == block;  // refuses signs, spaces, short digits and anything in the padding
}

// Reads `file` from its current position to its end, `chunk` bytes at a time, so memory does not
// grow with the file; hashes the length first so that it is covered too.
std::uint64_t checksum_of_rest(std::istream& file, std::uint64_t length) {
  Fnv1a64 hash;
  std::array<unsigned char, 8> length_bytes{};
  for (std::size_t i = 0; i < length_bytes.size(); ++i) length_bytes[i] = static_cast<unsigned char>(length >> (8 * i));
  hash.add_bytes(length_bytes.data(), length_bytes.size());
  std::array<char, 1 << 16> chunk{};
  while (file.read(chunk.data(), chunk.size()) || file.gcount() > 0)
    hash.add_bytes(chunk.data(), static_cast<std::size_t>(file.gcount()));
  return hash.value();
}

std::uint64_t length_of(std::istream& file) {
  file.seekg(0, std::ios::end);
  const auto length = static_cast<std::uint64_t>(file.tellg());
  file.seekg(0, std::ios::beg);
  return length;
}

}  // namespace

void seal_h5_file(const std::string& path) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  if (!file) throw std::runtime_error(path + ": cannot open to seal it");
  const std::uint64_t length = length_of(file);
  std::array<char, hdf5_signature.size()> signature{};
  file.seekg(h5_seal_bytes);
  if (!file.read(signature.data(), signature.size()) ||
      std::string_view(signature.data(), signature.size()) != hdf5_signature) {
    throw std::runtime_error(path + ": cannot seal: not an HDF5 file with a " + std::to_string(h5_seal_bytes) +
                             "-byte user block");
  }
  file.seekg(h5_seal_bytes);
  const std::uint64_t checksum = checksum_of_rest(file, length);
  file.clear();  // reading to the end set eof
  const SealBlock block = render({seal_format, length, checksum});
  file.seekp(0);
  file.write(block.data(), block.size());
  file.close();
  if (!file) throw std::runtime_error(path + ": could not write its seal");
}

bool carries_h5_seal(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::array<char, magic_line.size()> start{};
  return file.read(start.data(), start.size()) && std::string_view(start.data(), start.size()) == magic_line;
}

void verify_h5_seal(const std::string& path) {
  if (!carries_h5_seal(path)) throw InputError(path + ": not an fx2d-bench result file (no fx2d-bench header)");
  std::ifstream file(path, std::ios::binary);
  const std::uint64_t length = length_of(file);
  SealBlock block{};
  Seal seal;
  const bool canonical = file.read(block.data(), block.size()) && parse(block, seal);
  if (seal.format != 0 && seal.format != seal_format) {
    throw InputError(path + ": fx2d-bench header format " + std::to_string(seal.format) +
                     " is not supported; expected " + std::to_string(seal_format));
  }
  if (!canonical) throw InputError(path + ": corrupt or truncated (damaged fx2d-bench header)");
  if (seal.length != length) {
    throw InputError(path + ": corrupt or truncated (" + std::to_string(length) +
                     " bytes; its fx2d-bench header says " + std::to_string(seal.length) + ")");
  }
  if (checksum_of_rest(file, length) != seal.checksum)
    throw InputError(path + ": corrupt or truncated (checksum mismatch)");
}

}  // namespace fxbench

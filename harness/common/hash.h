// FNV-1a, 64 bit: a fast, dependency-free hash for identifying scenes and states. Not for
// security; collisions between two scenes or states a user compares are vanishingly unlikely.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>

namespace fxbench {

class Fnv1a64 {
 public:
  void add_bytes(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      state_ ^= bytes[i];
      state_ *= 0x100000001b3ull;
    }
  }
  void add(std::string_view text) { add_bytes(text.data(), text.size()); }
  // Hashes the exact bit pattern, so -0.0 and 0.0 differ, as they do for determinism.
  void add(double value) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    add_bytes(&bits, sizeof bits);
  }
  std::uint64_t value() const { return state_; }
  std::string hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(state_));
    return text;
  }

 private:
  std::uint64_t state_ = 0xcbf29ce484222325ull;
};

}  // namespace fxbench

// Replaces the global allocator of the test program that includes this header (include it in
// exactly one translation unit per test binary) with one that counts every allocation, so a test
// can prove a region of code allocates nothing.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace fxbench::test {

inline std::atomic<long long> heap_allocations{0};

}  // namespace fxbench::test

// Kept out of line so that GCC does not inline the pair into callers and mistake free() for a
// mismatched delete.
[[gnu::noinline]] void* operator new(std::size_t size) {
  ++fxbench::test::heap_allocations;
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
[[gnu::noinline]] void* operator new[](std::size_t size) { return operator new(size); }
[[gnu::noinline]] void operator delete(void* memory) noexcept { std::free(memory); }
[[gnu::noinline]] void operator delete[](void* memory) noexcept { std::free(memory); }
[[gnu::noinline]] void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
[[gnu::noinline]] void operator delete[](void* memory, std::size_t) noexcept { std::free(memory); }

// Noise-free counts for `fx2d-bench run --counter instructions`: the exact number of instructions
// an engine executes stepping a scene, counted by valgrind's callgrind.
//
// Why: this machine, like most CI machines, offers no hardware performance counters, and wall time
// on a shared machine is noisy. Callgrind counts every instruction the program executes (its
// event `Ir`), which for a deterministic scene on one binary is the same number on every run: a
// figure `compare` can judge exactly, with no statistics. Nothing is ever timed under valgrind
// (it runs the program 20-100x slower); the parent times natively as always and starts one extra
// child per engine and scene only for the count.
//
// Invariants: the count covers exactly scene.steps steps of one freshly built instance. Process
// start-up, scene loading and building are outside it: callgrind starts with collection off
// (--collect-atstart=no) and the child, `fx2d-bench count-instructions` (count_instructions.cpp),
// turns collection on and off around the step loop alone. The child is this same fx2d-bench
// binary, finds its engine through find_engine() by the name it is given (so a plugin name,
// "plugin:PATH|LABEL", counts a plugin build), and steps the parent's resolved scene, checked by
// its hash. Callgrind's files live in a private temporary directory that is removed afterwards.
#pragma once

#include <cstdint>
#include <istream>
#include <optional>
#include <string>

#include "common/child_process.h"
#include "common/results.h"
#include "scene/scene_spec.h"

namespace fxbench {

// Valgrind cannot run a program built with AddressSanitizer: both want the same address space.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool built_with_address_sanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool built_with_address_sanitizer = true;
#else
inline constexpr bool built_with_address_sanitizer = false;
#endif
#else
inline constexpr bool built_with_address_sanitizer = false;
#endif

// The tool counts are taken with, as recorded in InstructionCount::tool.
inline constexpr const char* instruction_count_tool = "callgrind";

class InstructionCounter {
 public:
  // Checks that valgrind runs and notes its version. `bench_executable` is the fx2d-bench binary
  // the child runs: by default this process's own. Throws InputError (one line) when valgrind is
  // not installed, or this is a sanitizer build.
  explicit InstructionCounter(std::string bench_executable = own_executable());

  // Counts scene.steps steps of `engine_name` (a name find_engine() takes) on `scene`, which must
  // have its resolved JSON. Empty when a SIGINT stopped the child (interrupt.h). Throws
  // InputError when the child refuses its input (exit 2, e.g. a plugin that does not load),
  // std::runtime_error on any other failure of the child.
  std::optional<InstructionCount> count(const SceneSpec& scene, const std::string& engine_name) const;

  const std::string& valgrind_version() const { return valgrind_version_; }  // e.g. "valgrind-3.19.0"

 private:
  std::string bench_executable_;
  std::string valgrind_version_;
};

// The total of callgrind's first event, which must be Ir, from its output file (the `totals:`
// line, else the `summary:` line). `origin` names the file in errors. Throws std::runtime_error.
std::uint64_t callgrind_total_instructions(std::istream& output, const std::string& origin);

}  // namespace fxbench

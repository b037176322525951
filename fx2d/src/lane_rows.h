// Eight body states read as rows and turned into eight-lane columns, and back: what the solver's
// lane loops (contact batches, body integration) gather before they run and scatter after.
//
// An FxBodyState is 32 bytes, two 16-byte rows: (vx, vy, w, flags) and (dpx, dpy, dqc, dqs). Four
// rows become four four-lane columns in one 4x4 transpose of shuffles, so eight bodies cost eight
// row loads and a dozen shuffles per half instead of 32 single-float inserts. GCC and Clang
// vector extensions, not intrinsics: they lower to SSE, AVX or NEON.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fx2d/Constraint.h"

namespace fx2d::detail {

inline constexpr int fx_lanes = 8;

// Where the CPU allows more than the build's baseline instruction set, a lane kernel is compiled
// a second time for AVX2 and the loader picks the version (an ifunc), so a portable binary still
// gets eight-wide lanes. The result is the same to the bit: AVX2 brings no fused multiply-add
// (that is the separate FMA extension), and lanes are independent. Every helper a kernel calls is
// always_inline, so each version holds its own copy.
#if defined(__x86_64__) && !defined(__AVX2__)
#define FX2D_LANE_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define FX2D_LANE_KERNEL
#endif

using LaneRow = float __attribute__((vector_size(16)));
using LaneColumn = float __attribute__((vector_size(32)));

// The rows of FxBodyState, by byte offset.
inline constexpr std::size_t velocity_row = 0;  // vx, vy, w, flags
inline constexpr std::size_t pose_row = 16;     // dpx, dpy, dqc, dqs
static_assert(offsetof(FxBodyState, linear_velocity) == velocity_row && offsetof(FxBodyState, angular_velocity) == 8 &&
                  offsetof(FxBodyState, flags) == 12,
              "the velocity row is velocity, spin and flags");
static_assert(offsetof(FxBodyState, delta_position) == pose_row && offsetof(FxBodyState, delta_rotation) == 24,
              "the pose row is displacement and rotation");
static_assert(fx_lanes == 8, "gather_columns and scatter_columns transpose eight rows");

// One row of eight bodies, as four columns.
struct LaneColumns {
  LaneColumn c0, c1, c2, c3;
};

template <std::size_t Row>
[[gnu::always_inline]] inline LaneRow load_row(const FxBodyState& state) {
  LaneRow row;
  std::memcpy(&row, reinterpret_cast<const unsigned char*>(&state) + Row, sizeof row);
  return row;
}

// Four rows into four columns: a 4x4 transpose, which is its own inverse.
[[gnu::always_inline]] inline void transpose_rows(LaneRow r0, LaneRow r1, LaneRow r2, LaneRow r3, LaneRow& c0, LaneRow& c1,
                                                  LaneRow& c2, LaneRow& c3) {
  const LaneRow low01 = __builtin_shufflevector(r0, r1, 0, 4, 1, 5);
  const LaneRow high01 = __builtin_shufflevector(r0, r1, 2, 6, 3, 7);
  const LaneRow low23 = __builtin_shufflevector(r2, r3, 0, 4, 1, 5);
  const LaneRow high23 = __builtin_shufflevector(r2, r3, 2, 6, 3, 7);
  c0 = __builtin_shufflevector(low01, low23, 0, 1, 4, 5);
  c1 = __builtin_shufflevector(low01, low23, 2, 3, 6, 7);
  c2 = __builtin_shufflevector(high01, high23, 0, 1, 4, 5);
  c3 = __builtin_shufflevector(high01, high23, 2, 3, 6, 7);
}

// Row `Row` of the eight bodies `body[0..8)`, as columns. Filled through a reference: a 32-byte
// vector by value changes the ABI between the AVX2 and default clones.
template <std::size_t Row>
[[gnu::always_inline]] inline void gather_columns(const FxBodyState* __restrict states, const std::uint32_t* body,
                                                  LaneColumns& c) {
  LaneRow c0[2], c1[2], c2[2], c3[2];
  for (int half = 0; half < 2; ++half) {
    const std::uint32_t* b = body + 4 * half;
    transpose_rows(load_row<Row>(states[b[0]]), load_row<Row>(states[b[1]]), load_row<Row>(states[b[2]]),
                   load_row<Row>(states[b[3]]), c0[half], c1[half], c2[half], c3[half]);
  }
  c.c0 = __builtin_shufflevector(c0[0], c0[1], 0, 1, 2, 3, 4, 5, 6, 7);
  c.c1 = __builtin_shufflevector(c1[0], c1[1], 0, 1, 2, 3, 4, 5, 6, 7);
  c.c2 = __builtin_shufflevector(c2[0], c2[1], 0, 1, 2, 3, 4, 5, 6, 7);
  c.c3 = __builtin_shufflevector(c3[0], c3[1], 0, 1, 2, 3, 4, 5, 6, 7);
}

// The inverse: columns back into row `Row` of each body, each row written whole. Bodies that
// appear in more than one lane must carry the same values in each (the caller's invariant).
template <std::size_t Row>
[[gnu::always_inline]] inline void scatter_columns(FxBodyState* __restrict states, const std::uint32_t* body,
                                                   const LaneColumns& c) {
  LaneRow rows[8];
  transpose_rows(__builtin_shufflevector(c.c0, c.c0, 0, 1, 2, 3), __builtin_shufflevector(c.c1, c.c1, 0, 1, 2, 3),
                 __builtin_shufflevector(c.c2, c.c2, 0, 1, 2, 3), __builtin_shufflevector(c.c3, c.c3, 0, 1, 2, 3),
                 rows[0], rows[1], rows[2], rows[3]);
  transpose_rows(__builtin_shufflevector(c.c0, c.c0, 4, 5, 6, 7), __builtin_shufflevector(c.c1, c.c1, 4, 5, 6, 7),
                 __builtin_shufflevector(c.c2, c.c2, 4, 5, 6, 7), __builtin_shufflevector(c.c3, c.c3, 4, 5, 6, 7),
                 rows[4], rows[5], rows[6], rows[7]);
  for (int lane = 0; lane < fx_lanes; ++lane) {
    std::memcpy(reinterpret_cast<unsigned char*>(&states[body[lane]]) + Row, &rows[lane], sizeof(LaneRow));
  }
}

// A column's lanes as a plain array, for loops the compiler vectorises, and back.
[[gnu::always_inline]] inline void to_lanes(const LaneColumn& column, float* lanes) { std::memcpy(lanes, &column, sizeof column); }
[[gnu::always_inline]] inline void from_lanes(const float* lanes, LaneColumn& column) { std::memcpy(&column, lanes, sizeof column); }

}  // namespace fx2d::detail

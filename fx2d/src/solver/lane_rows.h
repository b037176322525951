// Eight body states read as rows and turned into eight-lane columns, and back: what the solver's
// lane loops (contact batches, body integration) gather before they run and scatter after. The
// same transposes read and write any other per-body record in 16-byte rows (a BodySim).
//
// An FxBodyState is 32 bytes, two 16-byte rows: (vx, vy, w, flags) and (dpx, dpy, dqc, dqs). Eight
// rows become four eight-lane columns in eight row loads and eight in-half shuffles, instead of 32
// single-float inserts. GCC and Clang vector extensions, not intrinsics: they lower to SSE, AVX or
// NEON.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "fx2d/Constraint.h"
#include "fx2d/Scene.h"
#include "world/bodies.h"

namespace fx2d::detail {

inline constexpr int lane_count = 8;

// Where the CPU allows more than the build's baseline instruction set, a lane kernel is compiled
// a second time for AVX2 and the loader picks the version (an ifunc), so a portable binary still
// gets eight-wide lanes. The result is the same to the bit: AVX2 brings no fused multiply-add
// (that is the separate FMA extension), and lanes are independent. Every helper a kernel calls is
// FX2D_LANE_INLINE, so each version holds its own copy. Ifuncs are an ELF feature: a Windows (PE)
// build keeps the baseline version alone. So does an instrumented build (FX2D_INSTRUMENTED:
// sanitizers, fuzzing): under ThreadSanitizer the loader runs the resolver before the sanitizer is
// set up, and its instrumented entry crashes.
#if defined(__x86_64__) && !defined(__AVX2__) && defined(__ELF__) && !FX2D_INSTRUMENTED
#define FX2D_LANE_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define FX2D_LANE_KERNEL
#endif

// The helpers of the lane kernels are inlined whole, so that each kernel is one loop the
// vectoriser sees entire. Instrumented builds leave inlining to the compiler: forced, it made
// functions that took minutes to instrument (contact_batch.cpp under Clang's fuzzing flags: 411 s
// with two versions and forced inlining, 4 s with one and none). Inlining moves no result:
// contraction is off.
#if FX2D_INSTRUMENTED
#define FX2D_LANE_INLINE inline
#else
#define FX2D_LANE_INLINE [[gnu::always_inline]] inline
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
// The rows of BodySim, by byte offset (body write-back, contact packing).
constexpr std::size_t sim_place_row = 0;      // origin, carry
constexpr std::size_t sim_turn_row = 16;      // rotation, local_center
constexpr std::size_t sim_velocity_row = 32;  // linear_velocity, angular_velocity, inv_mass
static_assert(offsetof(BodySim, origin) == sim_place_row && offsetof(BodySim, carry) == 8,
              "the place row is origin and carry");
static_assert(offsetof(BodySim, rotation) == sim_turn_row && offsetof(BodySim, local_center) == 24,
              "the turn row is rotation and local centre");
static_assert(offsetof(BodySim, linear_velocity) == sim_velocity_row && offsetof(BodySim, angular_velocity) == 40 &&
                  offsetof(BodySim, inv_mass) == 44,
              "the velocity row is velocity, spin and inverse mass");

static_assert(lane_count == 8, "gather_columns and scatter_columns transpose eight rows");

// One row of eight bodies, as four columns.
struct LaneColumns {
  LaneColumn c0, c1, c2, c3;
};

// How a list names the bodies whose records a gather or a scatter reads: by index, or by the byte
// offset of the record (its index times the record's size), which the address takes as it is
// where an index of a 32-byte record needs a shift first (ContactBatch keeps offsets).
enum class BodyList { indices, offsets };

// The byte offset of body `index`'s state among the solver's states. The padding state, one past
// the last body, has the largest.
static_assert(std::uint64_t{fx_max_entities} * sizeof(FxBodyState) <= std::uint64_t{UINT32_MAX},
              "every state's byte offset fits 32 bits");
constexpr std::uint32_t state_offset(std::uint32_t index) {
  return index * static_cast<std::uint32_t>(sizeof(FxBodyState));
}
constexpr std::uint32_t state_index(std::uint32_t offset) {
  return offset / static_cast<std::uint32_t>(sizeof(FxBodyState));
}

// Where the record of the body `body` names starts.
template <BodyList List, typename Record>
FX2D_LANE_INLINE auto* record_bytes(Record* records, std::uint32_t body) {
  using Byte = std::conditional_t<std::is_const_v<Record>, const unsigned char, unsigned char>;
  if constexpr (List == BodyList::offsets) {
    return reinterpret_cast<Byte*>(records) + body;
  } else {
    return reinterpret_cast<Byte*>(records + body);
  }
}

// Row `Row` (a byte offset) of a body's record: an FxBodyState, or any record with 16-byte rows.
template <std::size_t Row>
FX2D_LANE_INLINE LaneRow load_row(const unsigned char* record) {
  LaneRow row;
  std::memcpy(&row, record + Row, sizeof row);
  return row;
}

// Row `Row` of the eight bodies `body[0..8)`, as columns: bodies i and i + 4 share a vector, one
// per half, and each half is transposed 4x4 on its own (interleave pairs of rows, then pairs of
// pairs), as the 256-bit unpack and shuffle instructions work, so no shuffle crosses the halves.
// Written out, not in helper functions: a 32-byte vector passed by value changes the ABI between
// the AVX2 and default clones, and so does `c` returned instead of filled.
template <std::size_t Row, BodyList List = BodyList::indices, typename Record>
FX2D_LANE_INLINE void gather_columns(const Record* __restrict states, const std::uint32_t* body,
                                     LaneColumns& c) {
  LaneColumn r[4];
  for (int i = 0; i < 4; ++i) {
    r[i] = __builtin_shufflevector(load_row<Row>(record_bytes<List>(states, body[i])),
                                   load_row<Row>(record_bytes<List>(states, body[i + 4])), 0, 1, 2, 3, 4, 5,
                                   6, 7);
  }
  const LaneColumn t0 = __builtin_shufflevector(r[0], r[1], 0, 8, 1, 9, 4, 12, 5, 13);
  const LaneColumn t1 = __builtin_shufflevector(r[0], r[1], 2, 10, 3, 11, 6, 14, 7, 15);
  const LaneColumn t2 = __builtin_shufflevector(r[2], r[3], 0, 8, 1, 9, 4, 12, 5, 13);
  const LaneColumn t3 = __builtin_shufflevector(r[2], r[3], 2, 10, 3, 11, 6, 14, 7, 15);
  c.c0 = __builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13);
  c.c1 = __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15);
  c.c2 = __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13);
  c.c3 = __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15);
}

template <std::size_t Row>
FX2D_LANE_INLINE void store_row(unsigned char* record, const unsigned char* row) {
  std::memcpy(record + Row, row, sizeof(LaneRow));
}

// FxBodyState::flags of a body whose state contacts change (a dynamic, awake one); zero for the
// others (static, kinematic, sleeping) and the padding body. Set by prepare_solver().
inline constexpr std::uint32_t movable_flag = 1;

// Whether a velocity row (vx, vy, w, flags), as bytes, belongs to a body with movable_flag.
FX2D_LANE_INLINE bool is_movable_row(const unsigned char* row) {
  std::uint32_t flags;
  std::memcpy(&flags, row + offsetof(FxBodyState, flags), sizeof flags);
  return (flags & movable_flag) != 0;
}

// The inverse: columns back into row `Row` of each body, each row written whole. Bodies that
// appear in more than one lane must carry the same values in each (the caller's invariant), as
// the rows are written in the order 0, 4, 1, 5, ... With `MovableOnly` (velocity rows only), the
// rows of bodies without movable_flag, which those shared lanes carry unchanged, are not written
// at all: other threads may be reading or writing those same bodies at once.
template <std::size_t Row, bool MovableOnly = false, BodyList List = BodyList::indices, typename Record>
FX2D_LANE_INLINE void scatter_columns(Record* __restrict states, const std::uint32_t* body,
                                      const LaneColumns& c) {
  static_assert(!MovableOnly || (Row == velocity_row && std::is_same_v<Record, FxBodyState>),
                "only a state's velocity row carries the flags");
  // The same two rounds of in-half interleaving, which undo each other.
  const LaneColumn t0 = __builtin_shufflevector(c.c0, c.c1, 0, 8, 1, 9, 4, 12, 5, 13);
  const LaneColumn t1 = __builtin_shufflevector(c.c0, c.c1, 2, 10, 3, 11, 6, 14, 7, 15);
  const LaneColumn t2 = __builtin_shufflevector(c.c2, c.c3, 0, 8, 1, 9, 4, 12, 5, 13);
  const LaneColumn t3 = __builtin_shufflevector(c.c2, c.c3, 2, 10, 3, 11, 6, 14, 7, 15);
  LaneColumn rows[4];
  rows[0] = __builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13);
  rows[1] = __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15);
  rows[2] = __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13);
  rows[3] = __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15);
  for (int i = 0; i < 4; ++i) {
    // Each half stored straight from the vector's bytes: one 128-bit extract to memory, where
    // shuffling the upper half down first cost an extra instruction per row.
    const auto* halves = reinterpret_cast<const unsigned char*>(&rows[i]);
    const unsigned char* upper = halves + sizeof(LaneRow);
    if (!MovableOnly || is_movable_row(halves)) store_row<Row>(record_bytes<List>(states, body[i]), halves);
    if (!MovableOnly || is_movable_row(upper)) store_row<Row>(record_bytes<List>(states, body[i + 4]), upper);
  }
}

// A column's lanes as a plain array, for loops the compiler vectorises, and back.
FX2D_LANE_INLINE void to_lanes(const LaneColumn& column, float* lanes) {
  std::memcpy(lanes, &column, sizeof column);
}
FX2D_LANE_INLINE void from_lanes(const float* lanes, LaneColumn& column) {
  std::memcpy(&column, lanes, sizeof column);
}

// What the batched passes gather of a batch's two bodies per lane, for any batch that names them by
// state byte offsets in `state_a` and `state_b` (ContactBatch, PinBatch, RodBatch).
//
// The velocities as unit-stride arrays, for the solve loop; the bodies' flags (the rows' fourth
// column) ride along unchanged.
struct LaneVelocities {
  alignas(32) float avx[lane_count], avy[lane_count], aw[lane_count], bvx[lane_count], bvy[lane_count],
      bw[lane_count];
  LaneColumn a_flags, b_flags;
};

template <class Batch>
FX2D_LANE_INLINE void gather_velocities(const Batch& k, const FxBodyState* __restrict states,
                                        LaneVelocities& v) {
  LaneColumns a_side, b_side;
  gather_columns<velocity_row, BodyList::offsets>(states, k.state_a, a_side);
  gather_columns<velocity_row, BodyList::offsets>(states, k.state_b, b_side);
  to_lanes(a_side.c0, v.avx), to_lanes(a_side.c1, v.avy), to_lanes(a_side.c2, v.aw);
  to_lanes(b_side.c0, v.bvx), to_lanes(b_side.c1, v.bvy), to_lanes(b_side.c2, v.bw);
  v.a_flags = a_side.c3, v.b_flags = b_side.c3;
}

// Lanes that share a body (only static or kinematic ones, or the padding body) carry the same
// unchanged values, so the order of the writes is moot; `Shared` leaves those bodies unwritten.
template <bool Shared, class Batch>
FX2D_LANE_INLINE void scatter_velocities(const Batch& k, FxBodyState* __restrict states,
                                         const LaneVelocities& v) {
  LaneColumns a_side, b_side;
  from_lanes(v.avx, a_side.c0), from_lanes(v.avy, a_side.c1), from_lanes(v.aw, a_side.c2);
  from_lanes(v.bvx, b_side.c0), from_lanes(v.bvy, b_side.c1), from_lanes(v.bw, b_side.c2);
  a_side.c3 = v.a_flags, b_side.c3 = v.b_flags;
  scatter_columns<velocity_row, Shared, BodyList::offsets>(states, k.state_a, a_side);
  scatter_columns<velocity_row, Shared, BodyList::offsets>(states, k.state_b, b_side);
}

// Relative pose of the two bodies of every lane since the step began, gathered into columns, and
// (for contacts, contact_batch.cpp) the normal as it has turned since then with the body whose face
// it is.
struct LanePoses {
  alignas(32) float dpx[lane_count], dpy[lane_count], aqc[lane_count], aqs[lane_count], bqc[lane_count],
      bqs[lane_count];
  alignas(32) float nx[lane_count], ny[lane_count];
};

// Both bodies' displacements and turns since the step began, for every lane of one batch.
template <class Batch>
FX2D_LANE_INLINE void gather_poses(const Batch& __restrict k, const FxBodyState* __restrict states,
                                   LanePoses& __restrict q) {
  LaneColumns a, b;
  gather_columns<pose_row, BodyList::offsets>(states, k.state_a, a);
  gather_columns<pose_row, BodyList::offsets>(states, k.state_b, b);
  to_lanes(b.c0 - a.c0, q.dpx), to_lanes(b.c1 - a.c1, q.dpy);
  to_lanes(a.c2, q.aqc), to_lanes(a.c3, q.aqs), to_lanes(b.c2, q.bqc), to_lanes(b.c3, q.bqs);
}

}  // namespace fx2d::detail

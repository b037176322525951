// Small fixed-size math for a 2D engine: vectors, rotations, transforms, boxes, and the
// compensated addition that keeps poses precise far from the origin.
//
// Everything is single precision. Determinism relies on IEEE arithmetic with no fused
// multiply-add (the build pins -ffp-contract=off) and on avoiding libm in the step: rotations are
// advanced by normalising, which uses only sqrt, so results agree to the bit across compilers and
// architectures.
#pragma once

#include <cmath>
#include <cstdint>

namespace fx2d {

struct FxVec2f {
  float x = 0.0f;
  float y = 0.0f;

  constexpr FxVec2f operator-() const { return {-x, -y}; }
  constexpr FxVec2f& operator+=(FxVec2f v) { x += v.x; y += v.y; return *this; }
  constexpr FxVec2f& operator-=(FxVec2f v) { x -= v.x; y -= v.y; return *this; }
  constexpr FxVec2f& operator*=(float s) { x *= s; y *= s; return *this; }
  friend constexpr bool operator==(FxVec2f a, FxVec2f b) = default;
};

constexpr FxVec2f operator+(FxVec2f a, FxVec2f b) { return {a.x + b.x, a.y + b.y}; }
constexpr FxVec2f operator-(FxVec2f a, FxVec2f b) { return {a.x - b.x, a.y - b.y}; }
constexpr FxVec2f operator*(float s, FxVec2f v) { return {s * v.x, s * v.y}; }
constexpr FxVec2f operator*(FxVec2f v, float s) { return {s * v.x, s * v.y}; }

constexpr float dot(FxVec2f a, FxVec2f b) { return a.x * b.x + a.y * b.y; }
// z-component of the 3D cross product of (a, 0) and (b, 0).
constexpr float cross(FxVec2f a, FxVec2f b) { return a.x * b.y - a.y * b.x; }
// cross((0, 0, w), (v, 0)): the velocity of a point at offset v on a body spinning at w.
constexpr FxVec2f cross(float w, FxVec2f v) { return {-w * v.y, w * v.x}; }
constexpr FxVec2f cross(FxVec2f v, float s) { return {s * v.y, -s * v.x}; }
// Counter-clockwise perpendicular.
constexpr FxVec2f left_perp(FxVec2f v) { return {-v.y, v.x}; }
constexpr FxVec2f right_perp(FxVec2f v) { return {v.y, -v.x}; }
constexpr float length_squared(FxVec2f v) { return dot(v, v); }
inline float length(FxVec2f v) { return std::sqrt(dot(v, v)); }
inline float distance(FxVec2f a, FxVec2f b) { return length(b - a); }
constexpr FxVec2f min(FxVec2f a, FxVec2f b) { return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y}; }
constexpr FxVec2f max(FxVec2f a, FxVec2f b) { return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y}; }
constexpr FxVec2f lerp(FxVec2f a, FxVec2f b, float t) { return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; }
inline bool is_finite(FxVec2f v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// Unit vector along v, or the zero vector when v is too short to have a direction.
inline FxVec2f normalize(FxVec2f v) {
  const float len = length(v);
  if (len < 1.0e-12f) return {0.0f, 0.0f};
  const float inv = 1.0f / len;
  return {inv * v.x, inv * v.y};
}

// std::atan2(y, x) to within a unit in the last place, the same to the bit on every platform
// (libm's is not): what reads an angle back out of a rotation.
float fx_atan2(float y, float x);

// A rotation stored as its cosine and sine. Invariant: c*c + s*s == 1 to within rounding.
struct FxRot {
  float c = 1.0f;
  float s = 0.0f;

  static FxRot from_angle(float radians) { return {std::cos(radians), std::sin(radians)}; }
  float angle() const { return fx_atan2(s, c); }
  friend constexpr bool operator==(FxRot a, FxRot b) = default;
};

constexpr FxVec2f rotate(FxRot q, FxVec2f v) { return {q.c * v.x - q.s * v.y, q.s * v.x + q.c * v.y}; }
constexpr FxVec2f inv_rotate(FxRot q, FxVec2f v) { return {q.c * v.x + q.s * v.y, -q.s * v.x + q.c * v.y}; }
// q * r: rotate by r, then by q.
constexpr FxRot mul(FxRot q, FxRot r) { return {q.c * r.c - q.s * r.s, q.s * r.c + q.c * r.s}; }
// q^-1 * r: the rotation that takes q to r.
constexpr FxRot inv_mul(FxRot q, FxRot r) { return {q.c * r.c + q.s * r.s, q.c * r.s - q.s * r.c}; }

// Advances q by the small angle `delta` (radians) without trigonometry: normalise
// q + delta * perp(q). The angle advanced is atan(delta), within delta^3/3 of delta, which is
// below 1e-6 rad for the angular steps of a substep.
inline FxRot integrate_rotation(FxRot q, float delta) {
  const float c = q.c - delta * q.s;
  const float s = q.s + delta * q.c;
  const float inv = 1.0f / std::sqrt(c * c + s * s);
  return {c * inv, s * inv};
}

// A rigid placement: rotate, then translate.
struct FxTransform {
  FxVec2f p;
  FxRot q;
};

constexpr FxVec2f transform_point(const FxTransform& xf, FxVec2f v) { return rotate(xf.q, v) + xf.p; }
constexpr FxVec2f inv_transform_point(const FxTransform& xf, FxVec2f v) { return inv_rotate(xf.q, v - xf.p); }
// A^-1 * B: B expressed in A's frame.
constexpr FxTransform inv_mul(const FxTransform& a, const FxTransform& b) {
  return {inv_rotate(a.q, b.p - a.p), inv_mul(a.q, b.q)};
}

// Axis-aligned bounding box. Invariant: lower <= upper componentwise.
struct FxAABB {
  FxVec2f lower;
  FxVec2f upper;

  constexpr float perimeter() const { return 2.0f * ((upper.x - lower.x) + (upper.y - lower.y)); }
  constexpr bool contains(const FxAABB& b) const {
    return lower.x <= b.lower.x && lower.y <= b.lower.y && b.upper.x <= upper.x && b.upper.y <= upper.y;
  }
};

constexpr FxAABB union_of(const FxAABB& a, const FxAABB& b) { return {min(a.lower, b.lower), max(a.upper, b.upper)}; }
constexpr bool overlaps(const FxAABB& a, const FxAABB& b) {
  return !(b.lower.x > a.upper.x || b.lower.y > a.upper.y || a.lower.x > b.upper.x || a.lower.y > b.upper.y);
}
constexpr FxAABB inflate(const FxAABB& a, float margin) {
  return {{a.lower.x - margin, a.lower.y - margin}, {a.upper.x + margin, a.upper.y + margin}};
}

// Compensated (Kahan) accumulation: value + carry together hold the running sum to about twice
// float precision. Poses are advanced this way so that a body 10 km from the origin, where one
// float ulp is a millimetre, still moves by the sub-millimetre steps a substep produces.
// The precise sum is value - carry (carry holds the rounding error value still has too much).
// Requires strict IEEE evaluation (no -ffast-math, no contraction).
inline void FxCarryAdd(float& value, float& carry, float delta) {
  const float corrected = delta - carry;
  const float sum = value + corrected;
  carry = (sum - value) - corrected;
  value = sum;
}

inline void FxCarryAdd(FxVec2f& value, FxVec2f& carry, FxVec2f delta) {
  FxCarryAdd(value.x, carry.x, delta.x);
  FxCarryAdd(value.y, carry.y, delta.y);
}

inline double precise_value(float value, float carry) { return double(value) - double(carry); }

}  // namespace fx2d

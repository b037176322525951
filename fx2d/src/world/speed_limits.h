// The scene's speed limits and the clamps that keep every body within them, so that no push,
// however large, can turn a finite state into an infinite one.
#pragma once

#include <algorithm>
#include <cmath>

#include "fx2d/Math.h"
#include "fx2d/Scene.h"

namespace fx2d::detail {

struct SpeedLimits {
  float max_speed = 0.0f;  // m/s
  float max_spin = 0.0f;   // rad/s
};

// A quarter turn per substep: faster spin cannot be represented by the rotation integration.
inline float max_angular_speed(const FxSceneSettings& settings) {
  return 0.25f * 3.14159265f * static_cast<float>(settings.substeps) / settings.dt;
}

// The rare case of limited_speed: `v` is faster than `max_speed`, or overflowed, or NaN.
FxVec2f slowed_to(FxVec2f v, float max_speed);

// `v` scaled down to `max_speed` when it is faster; finite whatever `v` is, even infinite or NaN.
// Inline, with the rare case out of line: the substep loops call it for every body twice.
inline FxVec2f limited_speed(FxVec2f v, float max_speed) {
  return length_squared(v) <= max_speed * max_speed ? v : slowed_to(v, max_speed);
}

// `w` clamped to +-max_spin; a NaN spin becomes 0.
inline float limited_spin(float w, float max_spin) { return std::isnan(w) ? 0.0f : std::clamp(w, -max_spin, max_spin); }

}  // namespace fx2d::detail

// A read-only view of one contact manifold, as FxScene::contacts() reports it.
#pragma once

#include <cstdint>

#include "fx2d/Math.h"

namespace fx2d {

struct FxContactPoint {
  FxVec2f point;               // world metres, midway between the surfaces as the last narrow phase found them
  float separation = 0.0f;     // metres, negative when overlapping (speculative points are positive)
  float normal_impulse = 0.0f;   // N s applied along the normal in the last substep
  float tangent_impulse = 0.0f;  // N s applied along the tangent in the last substep
  std::uint32_t feature_id = 0;  // stable while the same features touch
};

struct FxContact {
  std::uint32_t entity_a = 0;  // packed indices of the two entities
  std::uint32_t entity_b = 0;
  FxVec2f normal;              // unit, from a towards b
  int point_count = 0;         // 1 or 2
  FxContactPoint points[2];
};

}  // namespace fx2d

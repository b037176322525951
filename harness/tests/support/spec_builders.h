// Building blocks for hand-made SceneSpecs in the harness's tests.
#pragma once

#include "scene/scene_spec.h"

namespace fxbench::test {

inline BodySpec box_at(Vec2 position, double angle = 0.0, BodyType type = BodyType::dynamic) {
  BodySpec body;
  body.type = type;
  body.shape = ShapeKind::box;
  body.position = position;
  body.angle = angle;
  return body;
}

inline BodySpec circle_at(Vec2 position, double radius = 0.5) {
  BodySpec body;
  body.shape = ShapeKind::circle;
  body.radius = radius;
  body.position = position;
  return body;
}

}  // namespace fxbench::test

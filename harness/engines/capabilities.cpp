// Whether an engine can build a scene: the check every command makes before measuring (engine.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engines/engine.h"

namespace fxbench {
namespace {

const char* plural_name(ShapeKind shape) {
  switch (shape) {
    case ShapeKind::circle: return "circles";
    case ShapeKind::box: return "boxes";
    case ShapeKind::polygon: return "polygons";
  }
  return "unknown shapes";
}

const char* plural_name(JointKind joint) {
  switch (joint) {
    case JointKind::distance: return "distance joints";
    case JointKind::revolute: return "revolute joints";
  }
  return "unknown joints";
}

}  // namespace

std::optional<std::string> missing_capability(const EngineCapabilities& capabilities, const SceneSpec& scene) {
  if (scene.bodies.size() > capabilities.max_bodies)
    return "more than " + std::to_string(capabilities.max_bodies) + " bodies (the scene has " +
           std::to_string(scene.bodies.size()) + ")";
  for (const BodySpec& body : scene.bodies)
    if (std::ranges::find(capabilities.shapes, body.shape) == capabilities.shapes.end()) return plural_name(body.shape);
  for (const BodySpec& body : scene.bodies) {
    const double speed = std::hypot(body.linear_velocity.x, body.linear_velocity.y);
    if (speed > capabilities.max_linear_speed) {
      char text[96];
      std::snprintf(text, sizeof text, "bodies faster than %g m/s (one starts at %g m/s)", capabilities.max_linear_speed, speed);
      return text;
    }
  }
  for (const JointSpec& joint : scene.joints)
    if (std::ranges::find(capabilities.joints, joint.kind) == capabilities.joints.end()) return plural_name(joint.kind);
  if (!capabilities.bullets && std::ranges::any_of(scene.bodies, &BodySpec::bullet)) return "bullets";
  return std::nullopt;
}

}  // namespace fxbench

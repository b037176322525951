// Small scene-building helpers shared by the engine's tests.
#pragma once

#include <memory>

#include "fx2d/fx2d.h"

namespace fx2d::test {

// A static box whose top face lies at y = top.
inline std::shared_ptr<FxEntity> add_ground(FxScene& scene, float half_width = 50.0f, float top = 0.0f,
                                            FxMaterial material = {}) {
  FxEntityDef def;
  def.type = FxBodyType::static_body;
  def.shape = FxShape::box(half_width, 1.0f);
  def.position = {0.0f, top - 1.0f};
  def.material = material;
  return scene.create_entity(def);
}

inline std::shared_ptr<FxEntity> add_box(FxScene& scene, FxVec2f position, float half = 0.5f, FxMaterial material = {},
                                         float angle = 0.0f) {
  FxEntityDef def;
  def.shape = FxShape::box(half, half);
  def.position = position;
  def.angle = angle;
  def.material = material;
  return scene.create_entity(def);
}

inline std::shared_ptr<FxEntity> add_circle(FxScene& scene, FxVec2f position, float radius = 0.5f,
                                            FxMaterial material = {}) {
  FxEntityDef def;
  def.shape = FxShape::circle(radius);
  def.position = position;
  def.material = material;
  return scene.create_entity(def);
}

inline void run(FxScene& scene, float seconds) {
  const int steps = static_cast<int>(seconds / scene.settings().dt + 0.5f);
  for (int i = 0; i < steps; ++i) scene.step();
}

}  // namespace fx2d::test

// Drops a ball onto the ground through the installed public API and prints where it came to rest.
#include <cstdio>

#include <fx2d/fx2d.h>

int main() {
  fx2d::FxScene scene;
  fx2d::FxEntityDef ground;
  ground.type = fx2d::FxBodyType::static_body;
  ground.shape = fx2d::FxShape::box(10.0f, 1.0f);
  ground.position = {0.0f, -1.0f};
  scene.create_entity(ground);
  fx2d::FxEntityDef ball;
  ball.shape = fx2d::FxShape::circle(0.5f);
  ball.position = {0.0f, 3.0f};
  auto body = scene.create_entity(ball);
  for (int i = 0; i < 120; ++i) scene.step();
  std::printf("fx2d %s ball at y=%.3f\n", std::string(fx2d::fx_version()).c_str(), body->position().y);
  return body->position().y > 0.49f && body->position().y < 0.51f ? 0 : 1;
}

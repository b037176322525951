// libFuzzer target: arbitrary text through the scene loader, the way `fx2d-bench run` reads a
// scene file.
//
// Invariant checked: text either loads into a scene that keeps the limits scenes/README.md
// documents (at most 1,000,000 bodies, coordinates within +-1,000,000 m, positive shape sizes,
// joints between two distinct existing bodies), or is refused with one InputError whose message
// is a single line. Any other exception, a crash or a sanitizer report is a bug; a broken limit
// aborts with a message naming it.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/errors.h"
#include "scene/scene_loader.h"

namespace {

constexpr std::size_t kMaxBodies = 1'000'000;
constexpr double kMaxMagnitude = 1e6;

[[noreturn]] void broken(const char* limit) {
  std::fprintf(stderr, "scene_loader_fuzz: documented limit broken: %s\n", limit);
  std::abort();
}

bool within_limits(fxbench::Vec2 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::abs(v.x) <= kMaxMagnitude &&
         std::abs(v.y) <= kMaxMagnitude;
}

bool positive_size(const fxbench::BodySpec& body) {
  switch (body.shape) {
    case fxbench::ShapeKind::circle:
      return body.radius > 0.0;
    case fxbench::ShapeKind::box:
      return body.half_extents.x > 0.0 && body.half_extents.y > 0.0;
    case fxbench::ShapeKind::polygon:
      return body.vertices.size() >= 3;
  }
  return false;
}

void check_documented_limits(const fxbench::SceneSpec& scene) {
  if (scene.bodies.size() > kMaxBodies) broken("more than 1,000,000 bodies");
  if (!(std::isfinite(scene.dt) && scene.dt > 0.0)) broken("dt not a finite number > 0");
  if (!within_limits(scene.gravity)) broken("gravity beyond +-1e6");
  for (const fxbench::BodySpec& body : scene.bodies) {
    if (!within_limits(body.position) || !within_limits(body.linear_velocity))
      broken("body position or velocity beyond +-1e6");
    if (!positive_size(body)) broken("a shape without a positive size");
  }
  const auto body_count = static_cast<int>(scene.bodies.size());
  for (const fxbench::JointSpec& joint : scene.joints) {
    if (joint.body_a < 0 || joint.body_a >= body_count || joint.body_b < 0 || joint.body_b >= body_count) {
      broken("a joint naming a body that does not exist");
    }
    if (joint.body_a == joint.body_b) broken("a joint between a body and itself");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    check_documented_limits(fxbench::load_scene_text(text, "<fuzz>"));
  } catch (const fxbench::InputError& error) {
    if (std::string(error.what()).find('\n') != std::string::npos)
      broken("an error message longer than one line");
  }
  return 0;
}

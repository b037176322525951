// The engine-neutral description of a scene: what every engine adapter builds, body for body.
//
// A scene file (JSON, see scenes/README.md) is loaded into this form once; generators are
// expanded into explicit bodies here, so adapters never interpret generators and every engine
// builds exactly the same list. Doubles throughout: each adapter converts to its own precision.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace fxbench {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

enum class BodyType { static_body, kinematic, dynamic };
enum class ShapeKind { circle, box, polygon };

struct MaterialSpec {
  double density = 1.0;           // kg/m^2 (ODE uses kg/m^3 over a 1 m deep solid: same mass)
  double static_friction = 0.6;   // dimensionless, >= 0
  double dynamic_friction = 0.6;  // dimensionless, >= 0
  double restitution = 0.0;       // dimensionless, 0..1
};

struct BodySpec {
  BodyType type = BodyType::dynamic;
  ShapeKind shape = ShapeKind::box;
  double radius = 0.5;              // circle
  Vec2 half_extents{0.5, 0.5};      // box
  std::vector<Vec2> vertices;       // polygon, body-local, counter-clockwise
  Vec2 position;                    // body origin, metres
  double angle = 0.0;               // radians
  Vec2 linear_velocity;             // m/s
  double angular_velocity = 0.0;    // rad/s
  MaterialSpec material;
  bool bullet = false;              // swept against fast dynamic bodies too (Fx2D, Box2D)
};

enum class JointKind { distance, revolute };

struct JointSpec {
  JointKind kind = JointKind::revolute;
  int body_a = 0;                   // indices into SceneSpec::bodies
  int body_b = 0;
  Vec2 local_anchor_a;              // body-local metres
  Vec2 local_anchor_b;
  double length = -1.0;             // distance joint: rest length; < 0 means "as built"
};

// Which accuracy figure a scene is judged by in speed-versus-accuracy charts.
enum class PrimaryMetric { penetration, displacement };

// The /solver blocks the scene format defines: Fx2D's, Box2D's and ODE's, whose values are those
// engines' knobs, checked by the engine (engines/engine.h) as a plugin engine's block is; the
// resolved scene records each of the three as the format resolved it.
inline constexpr std::array<std::string_view, 3> format_solver_blocks{"fx2d", "box2d", "ode"};

struct SceneSpec {
  std::string name;                 // e.g. "pile"
  std::string source_path;          // the file it came from ("" for embedded scenes)
  std::string resolved_json;        // the scene after --bodies/--set, defaults filled, pretty-printed
  std::string hash;                 // 16 hex digits, FNV-1a 64 of resolved_json: the exact scene
  int size = 0;                     // the scene's size parameter N (what --bodies sets)
  Vec2 gravity{0.0, -10.0};
  double dt = 1.0 / 60.0;
  int steps = 200;
  Vec2 bounds_lower{-1000.0, -1000.0};  // a body outside these bounds has escaped
  Vec2 bounds_upper{1000.0, 1000.0};
  PrimaryMetric primary_metric = PrimaryMetric::penetration;
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;
  // Where each value of an engine's knob block came from, for the engine's refusal of it
  // (engines/knobs.cpp): "/solver/<engine>/<key>" -> "file:line:col" or the --set that wrote it.
  std::map<std::string, std::string> knob_places;
};

// The scene's size as results name it: its size parameter N, or for a scene that has none (a file
// listing its bodies) the number of dynamic bodies it holds.
inline int bodies_of(const SceneSpec& scene) {
  if (scene.size > 0) return scene.size;
  int dynamic = 0;
  for (const BodySpec& body : scene.bodies) dynamic += body.type == BodyType::dynamic ? 1 : 0;
  return dynamic;
}

}  // namespace fxbench

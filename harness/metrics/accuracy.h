// Engine-neutral accuracy figures: what the harness measures from poses and shapes alone, with
// its own double-precision geometry, so every engine is judged by the same code and no engine's
// contact report is trusted.
//
// Invariants: penetration is the minimum translation distance between two convex shapes (0 when
// they touch or are apart), found by the separating-axis test; pairs of static bodies and pairs
// joined by a joint are never measured (no engine collides them); a body with a non-finite pose
// or velocity is counted in `nan` and left out of every other figure, so one exploded body cannot
// turn the rest of the sample into NaN. Kinetic energy takes linear_velocity as the velocity of
// the centre of mass and the moment of inertia about the centroid (the body origin, for circles
// and boxes). After construction, measure() allocates nothing.
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common/results.h"
#include "engines/engine.h"
#include "scene/scene_spec.h"

namespace fxbench {

// A convex shape placed in the world. A circle is one vertex (its centre) with a radius and no
// normals; a polygon has radius 0, counter-clockwise vertices and one outward unit normal per
// edge, normal i belonging to the edge from vertex i to vertex i + 1.
struct ConvexView {
  std::span<const Vec2> vertices;
  std::span<const Vec2> normals;
  double radius = 0.0;
};

// The minimum translation distance that separates `a` from `b`, in metres; 0 when they touch or
// are apart.
double penetration_depth(const ConvexView& a, const ConvexView& b);

class AccuracyProbe {
 public:
  // `start` holds the poses the displacement and drift figures are measured from, in
  // scene.bodies order. Throws std::invalid_argument on a polygon of fewer than three vertices or
  // a start of the wrong size.
  AccuracyProbe(const SceneSpec& scene, std::vector<BodyState> start);

  // The figures for `states` (scene.bodies order), tagged with `step`. Throws
  // std::invalid_argument when states.size() differs from the scene's body count.
  AccuracySample measure(int step, const std::vector<BodyState>& states);

 private:
  struct Aabb {
    Vec2 lower;
    Vec2 upper;
  };
  // A body's shape in its own frame: vertices at [first, first + vertex_count) of the vertex
  // arrays, normals at [first, first + normal_count) of the normal arrays (none for a circle).
  struct BodyShape {
    BodyType type = BodyType::dynamic;
    double radius = 0.0;
    int first = 0;
    int vertex_count = 0;
    int normal_count = 0;
    double mass = 0.0;     // kg
    double inertia = 0.0;  // kg m^2, about the centroid
  };
  struct PairPenetration {
    double max = 0.0;
    double sum = 0.0;
    int count = 0;
  };

  void place_shapes(const std::vector<BodyState>& states);
  PairPenetration measure_penetration();
  bool joined(int a, int b) const;
  ConvexView placed(int body) const;

  Vec2 bounds_lower_;
  Vec2 bounds_upper_;
  std::vector<BodyShape> shapes_;
  std::vector<Vec2> local_vertices_;
  std::vector<Vec2> local_normals_;
  std::vector<BodyState> start_;
  std::vector<std::pair<int, int>> joined_pairs_;  // (lower index, higher index), sorted

  // Scratch, sized once in the constructor.
  std::vector<Vec2> world_vertices_;
  std::vector<Vec2> world_normals_;
  std::vector<Aabb> bounds_;
  std::vector<char> finite_;
  std::vector<int> sweep_order_;  // finite bodies, sorted by the lower bound on the sweep axis
};

// FNV-1a 64 of every body's position, angle and velocities, bit for bit, as 16 hex digits.
std::string state_hash(const std::vector<BodyState>& states);

}  // namespace fxbench

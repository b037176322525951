// Conservative advancement between two swept convex shapes (time_of_impact.h): the distance
// between circles and polygons, and the advance that cannot overshoot the first touch.
#include "collision/time_of_impact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fx2d::detail {
namespace {

// Below this the distance is reached: a quarter of the target, as Box2D's tolerance.
constexpr float tolerance_share = 0.25f;
// Each iteration costs one distance query; a sweep that needs more is stopped where it has got
// to, which is early (never late): the next step's contact carries on from there.
constexpr int max_iterations = 48;

// A polygon's vertices and outward normals placed by a transform.
struct PlacedPolygon {
  std::array<FxVec2f, FxShape::max_vertices> vertices;
  std::array<FxVec2f, FxShape::max_vertices> normals;
  int count = 0;
};

PlacedPolygon place(const FxShape& polygon, const FxTransform& xf) {
  PlacedPolygon placed;
  placed.count = polygon.vertex_count();
  for (int i = 0; i < placed.count; ++i) {
    placed.vertices[i] = transform_point(xf, polygon.vertices()[i]);
    placed.normals[i] = rotate(xf.q, polygon.normals()[i]);
  }
  return placed;
}

FxVec2f closest_on_segment(FxVec2f point, FxVec2f start, FxVec2f end) {
  const FxVec2f edge = end - start;
  const float u = dot(point - start, edge) / dot(edge, edge);
  return start + std::clamp(u, 0.0f, 1.0f) * edge;
}

// The closest pair of points between a polygon's boundary and `point`, first on the polygon.
struct ClosestPair {
  FxVec2f on_a;
  FxVec2f on_b;
  float distance_squared = std::numeric_limits<float>::max();

  void offer(FxVec2f a, FxVec2f b) {
    const float d = length_squared(b - a);
    if (d < distance_squared) *this = {a, b, d};
  }
  Separation separation(float radii) const {
    return {std::sqrt(distance_squared) - radii, normalize(on_b - on_a)};
  }
};

// How far `points` lie outside the polygon's face of greatest separation, and that face.
struct FaceSeparation {
  float separation = -std::numeric_limits<float>::max();
  FxVec2f normal;
};

FaceSeparation deepest_face(const PlacedPolygon& polygon, const FxVec2f* points, int point_count) {
  FaceSeparation best;
  for (int i = 0; i < polygon.count; ++i) {
    float nearest = std::numeric_limits<float>::max();
    for (int j = 0; j < point_count; ++j) {
      nearest = std::min(nearest, dot(polygon.normals[i], points[j] - polygon.vertices[i]));
    }
    if (nearest > best.separation) best = {nearest, polygon.normals[i]};
  }
  return best;
}

Separation circles(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b) {
  const FxVec2f center_a = transform_point(xf_a, a.centroid());
  const FxVec2f center_b = transform_point(xf_b, b.centroid());
  return {distance(center_a, center_b) - a.radius() - b.radius(), normalize(center_b - center_a)};
}

Separation polygon_circle(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b) {
  const PlacedPolygon polygon = place(a, xf_a);
  const FxVec2f center = transform_point(xf_b, b.centroid());
  const FaceSeparation face = deepest_face(polygon, &center, 1);
  if (face.separation <= 0.0f) return {face.separation - b.radius(), face.normal};
  ClosestPair closest;
  for (int i = 0; i < polygon.count; ++i) {
    const FxVec2f end = polygon.vertices[i + 1 < polygon.count ? i + 1 : 0];
    closest.offer(closest_on_segment(center, polygon.vertices[i], end), center);
  }
  return closest.separation(b.radius());
}

// Offers every vertex of `from` against every edge of `to`, each pair as (point on a, point on b).
void offer_vertices_against_edges(const PlacedPolygon& from, const PlacedPolygon& to, bool from_is_a,
                                  ClosestPair& closest) {
  for (int i = 0; i < to.count; ++i) {
    const FxVec2f end = to.vertices[i + 1 < to.count ? i + 1 : 0];
    for (int j = 0; j < from.count; ++j) {
      const FxVec2f on_edge = closest_on_segment(from.vertices[j], to.vertices[i], end);
      if (from_is_a) {
        closest.offer(from.vertices[j], on_edge);
      } else {
        closest.offer(on_edge, from.vertices[j]);
      }
    }
  }
}

// Separated convex polygons are closest at a vertex of one and an edge of the other; overlapping
// ones are told apart first by the separating-axis test.
Separation polygons(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b) {
  const PlacedPolygon polygon_a = place(a, xf_a);
  const PlacedPolygon polygon_b = place(b, xf_b);
  const FaceSeparation face_a = deepest_face(polygon_a, polygon_b.vertices.data(), polygon_b.count);
  const FaceSeparation face_b = deepest_face(polygon_b, polygon_a.vertices.data(), polygon_a.count);
  if (face_a.separation <= 0.0f && face_b.separation <= 0.0f) {
    return face_a.separation >= face_b.separation ? Separation{face_a.separation, face_a.normal}
                                                  : Separation{face_b.separation, -face_b.normal};
  }
  ClosestPair closest;
  offer_vertices_against_edges(polygon_b, polygon_a, false, closest);
  offer_vertices_against_edges(polygon_a, polygon_b, true, closest);
  return closest.separation(0.0f);
}

// How close the advance may bring two shapes that are `start` apart when the step begins: the
// target; shapes that start within two targets, one target closer than they start (a body that
// turns about the point it touches keeps its distance until the rest of it comes round, and is
// stopped there); but never deeper into overlap than one target, or than they start less the
// tolerance: else a body its contact cannot push out (one that spins too fast for the contact's
// points to hold) would sink one target deeper every step until it passed.
float closest_allowed(float start, float target, float tolerance) {
  const float closer_than_start = std::min(target, start - target);
  const float deepest = std::min(start, -target) - tolerance;
  return std::max(closer_than_start, deepest);
}

}  // namespace

float reach(const FxShape& shape, FxVec2f local_center) {
  const float turning_extent = shape.type() == FxShapeType::circle ? 0.0f : shape.extent();
  return turning_extent + distance(shape.centroid(), local_center);
}

FxTransform Sweep::at(float t) const {
  const FxVec2f center = lerp(center0, center1, t);
  const float c = rotation0.c + t * (rotation1.c - rotation0.c);
  const float s = rotation0.s + t * (rotation1.s - rotation0.s);
  const float norm_squared = c * c + s * s;
  // Exactly opposite rotations have no direction halfway between them; the end's will do there.
  if (!(norm_squared > 0.0f)) return {center - rotate(rotation1, local_center), rotation1};
  const float inv = 1.0f / std::sqrt(norm_squared);
  const FxRot rotation{c * inv, s * inv};
  return {center - rotate(rotation, local_center), rotation};
}

// The interpolated rotation turns fastest halfway, where the chord between the two rotations is
// nearest the origin: at 2 tan(phi / 2) = 2 sin(phi) / (1 + cos(phi)) per unit of t for a turn
// phi. Near a half turn that grows without bound; the floor keeps it finite (and large, so the
// advance is cautious there).
float Sweep::max_turn_rate() const {
  const FxRot turn = inv_mul(rotation0, rotation1);
  return 2.0f * std::abs(turn.s) / std::max(1.0f + turn.c, 1.0e-6f);
}

Separation shape_separation(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b) {
  const bool a_is_circle = a.type() == FxShapeType::circle;
  const bool b_is_circle = b.type() == FxShapeType::circle;
  if (a_is_circle && b_is_circle) return circles(a, xf_a, b, xf_b);
  if (b_is_circle) return polygon_circle(a, xf_a, b, xf_b);
  if (a_is_circle) {
    const Separation flipped = polygon_circle(b, xf_b, a, xf_a);
    return {flipped.distance, -flipped.normal};
  }
  return polygons(a, xf_a, b, xf_b);
}

TimeOfImpact time_of_impact(const FxShape& a, const Sweep& sweep_a, const FxShape& b, const Sweep& sweep_b,
                            float target) {
  // The distance between the shapes shrinks no faster than the relative motion of the centres
  // along the normal (exact for translation: the signed distance, negative in overlap, is then
  // convex in t) plus the fastest any point can swing about its centre.
  const FxVec2f closing_motion = (sweep_a.center1 - sweep_a.center0) - (sweep_b.center1 - sweep_b.center0);
  const float turning = sweep_a.max_turn_rate() * reach(a, sweep_a.local_center) +
                        sweep_b.max_turn_rate() * reach(b, sweep_b.local_center);
  const float tolerance = tolerance_share * target;
  Separation separation = shape_separation(a, sweep_a.at(0.0f), b, sweep_b.at(0.0f));
  const float stop_at = closest_allowed(separation.distance, target, tolerance);
  TimeOfImpact impact{1.0f, separation.distance < target + tolerance};
  float t = 0.0f;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    if (separation.distance < stop_at + tolerance) break;
    const float closing_speed = dot(closing_motion, separation.normal) + turning;
    if (closing_speed <= 0.0f) return impact;
    t += (separation.distance - stop_at) / closing_speed;
    if (t >= 1.0f) return impact;
    separation = shape_separation(a, sweep_a.at(t), b, sweep_b.at(t));
  }
  impact.fraction = t;
  return impact;
}

}  // namespace fx2d::detail

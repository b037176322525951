// Accuracy figures from poses and shapes: the separating-axis penetration test, a sweep-and-prune
// pair search, and per-body motion and energy.
//
// Invariant: every scratch array is sized in the constructor, so measure() allocates nothing.
// The pair search sorts the bodies' bounding boxes along the axis where the movable bodies are
// most spread out and sweeps them (O(n log n + k), k the pairs whose intervals overlap on that
// axis), so a 3000-body scene is measured without testing all n^2 pairs.
#include "metrics/accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "common/hash.h"

namespace fxbench {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
Vec2 operator*(double k, Vec2 v) { return {k * v.x, k * v.y}; }
double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
double length(Vec2 v) { return std::hypot(v.x, v.y); }
Vec2 rotate(Vec2 v, double cosine, double sine) {
  return {cosine * v.x - sine * v.y, sine * v.x + cosine * v.y};
}

struct Interval {
  double lower;
  double upper;
};

Interval project(const ConvexView& shape, Vec2 axis) {
  Interval extent{infinity, -infinity};
  for (Vec2 vertex : shape.vertices) {
    const double along = dot(vertex, axis);
    extent.lower = std::min(extent.lower, along);
    extent.upper = std::max(extent.upper, along);
  }
  return {extent.lower - shape.radius, extent.upper + shape.radius};
}

double overlap_along(const ConvexView& a, const ConvexView& b, Vec2 axis) {
  const Interval on_a = project(a, axis);
  const Interval on_b = project(b, axis);
  return std::min(on_a.upper - on_b.lower, on_b.upper - on_a.lower);
}

// Where a circle's deepest point meets a corner of the other shape (or the other circle's
// centre), no edge normal points along the separating direction; the axis from the centre to the
// nearest vertex does. Concentric shapes overlap equally along every axis, so any axis serves.
Vec2 axis_to_nearest_vertex(Vec2 centre, const ConvexView& other) {
  Vec2 nearest = other.vertices.front();
  for (Vec2 vertex : other.vertices) {
    if (length(vertex - centre) < length(nearest - centre)) nearest = vertex;
  }
  const double distance = length(nearest - centre);
  if (distance == 0.0) return {1.0, 0.0};
  return (1.0 / distance) * (nearest - centre);
}

bool is_finite(const BodyState& state) {
  return std::isfinite(state.position.x) && std::isfinite(state.position.y) && std::isfinite(state.angle) &&
         std::isfinite(state.linear_velocity.x) && std::isfinite(state.linear_velocity.y) &&
         std::isfinite(state.angular_velocity);
}

// A box is the polygon of its four corners, so one mass computation serves both.
std::vector<Vec2> outline(const BodySpec& body) {
  switch (body.shape) {
    case ShapeKind::circle:
      return {Vec2{}};
    case ShapeKind::box: {
      const Vec2 h = body.half_extents;
      return {{-h.x, -h.y}, {h.x, -h.y}, {h.x, h.y}, {-h.x, h.y}};
    }
    case ShapeKind::polygon:
      return body.vertices;
  }
  return {};
}

struct MassProperties {
  double mass = 0.0;
  double inertia = 0.0;  // about the centroid
};

// Sums the triangles fanned out from the first vertex (not the body origin, which may lie far
// away and cost precision), then moves the second moment to the centroid.
MassProperties polygon_mass(const std::vector<Vec2>& vertices, double density) {
  const Vec2 reference = vertices.front();
  double area = 0.0;
  Vec2 first_moment{};
  double second_moment = 0.0;
  for (std::size_t i = 1; i + 1 < vertices.size(); ++i) {
    const Vec2 a = vertices[i] - reference;
    const Vec2 b = vertices[i + 1] - reference;
    const double twice_area = cross(a, b);
    area += 0.5 * twice_area;
    first_moment = first_moment + (twice_area / 6.0) * (a + b);
    second_moment += twice_area / 12.0 * (dot(a, a) + dot(a, b) + dot(b, b));
  }
  const Vec2 centroid = (1.0 / area) * first_moment;
  const double mass = density * area;
  return {mass, density * second_moment - mass * dot(centroid, centroid)};
}

MassProperties mass_properties(const BodySpec& body, const std::vector<Vec2>& vertices) {
  const double density = body.material.density;
  if (body.shape == ShapeKind::circle) {
    const double mass = density * std::numbers::pi * body.radius * body.radius;
    return {mass, 0.5 * mass * body.radius * body.radius};
  }
  return polygon_mass(vertices, density);
}

}  // namespace

double penetration_depth(const ConvexView& a, const ConvexView& b) {
  // The depth is the least overlap over the candidate axes; a single axis with no overlap
  // separates the shapes.
  double depth = infinity;
  const auto overlaps_along = [&](Vec2 axis) {
    depth = std::min(depth, overlap_along(a, b, axis));
    return depth > 0.0;
  };
  for (Vec2 normal : a.normals) {
    if (!overlaps_along(normal)) return 0.0;
  }
  for (Vec2 normal : b.normals) {
    if (!overlaps_along(normal)) return 0.0;
  }
  if (a.normals.empty() && !overlaps_along(axis_to_nearest_vertex(a.vertices.front(), b))) return 0.0;
  if (b.normals.empty() && !overlaps_along(axis_to_nearest_vertex(b.vertices.front(), a))) return 0.0;
  return depth;
}

AccuracyProbe::AccuracyProbe(const SceneSpec& scene, std::vector<BodyState> start)
    : bounds_lower_(scene.bounds_lower), bounds_upper_(scene.bounds_upper), start_(std::move(start)) {
  if (start_.size() != scene.bodies.size()) {
    throw std::invalid_argument("AccuracyProbe: " + std::to_string(start_.size()) + " start states for " +
                                std::to_string(scene.bodies.size()) + " bodies");
  }
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodySpec& body = scene.bodies[i];
    const std::vector<Vec2> vertices = outline(body);
    const bool is_circle = body.shape == ShapeKind::circle;
    if (!is_circle && vertices.size() < 3) {
      throw std::invalid_argument("AccuracyProbe: body " + std::to_string(i) +
                                  ": a polygon needs at least 3 vertices");
    }
    const MassProperties mass = mass_properties(body, vertices);
    const int count = static_cast<int>(vertices.size());
    shapes_.push_back({body.type, is_circle ? body.radius : 0.0, static_cast<int>(local_vertices_.size()),
                       count, is_circle ? 0 : count, mass.mass, mass.inertia});
    for (int k = 0; k < count; ++k) {
      const Vec2 edge = vertices[(k + 1) % count] - vertices[k];
      local_vertices_.push_back(vertices[k]);
      // Counter-clockwise winding puts the outside on the right of each edge.
      local_normals_.push_back(is_circle ? Vec2{} : (1.0 / length(edge)) * Vec2{edge.y, -edge.x});
    }
  }
  for (const JointSpec& joint : scene.joints) {
    joined_pairs_.emplace_back(std::min(joint.body_a, joint.body_b), std::max(joint.body_a, joint.body_b));
  }
  std::sort(joined_pairs_.begin(), joined_pairs_.end());

  world_vertices_.resize(local_vertices_.size());
  world_normals_.resize(local_normals_.size());
  bounds_.resize(shapes_.size());
  finite_.resize(shapes_.size());
  sweep_order_.reserve(shapes_.size());
}

ConvexView AccuracyProbe::placed(int body) const {
  const BodyShape& shape = shapes_[body];
  return {std::span<const Vec2>(world_vertices_).subspan(shape.first, shape.vertex_count),
          std::span<const Vec2>(world_normals_).subspan(shape.first, shape.normal_count), shape.radius};
}

bool AccuracyProbe::joined(int a, int b) const {
  return std::binary_search(joined_pairs_.begin(), joined_pairs_.end(),
                            std::pair{std::min(a, b), std::max(a, b)});
}

void AccuracyProbe::place_shapes(const std::vector<BodyState>& states) {
  for (std::size_t i = 0; i < shapes_.size(); ++i) {
    finite_[i] = is_finite(states[i]);
    if (!finite_[i]) continue;
    const BodyShape& shape = shapes_[i];
    const double cosine = std::cos(states[i].angle);
    const double sine = std::sin(states[i].angle);
    Aabb box{{infinity, infinity}, {-infinity, -infinity}};
    for (int k = shape.first; k < shape.first + shape.vertex_count; ++k) {
      const Vec2 vertex = states[i].position + rotate(local_vertices_[k], cosine, sine);
      world_vertices_[k] = vertex;
      world_normals_[k] = rotate(local_normals_[k], cosine, sine);
      box.lower = {std::min(box.lower.x, vertex.x), std::min(box.lower.y, vertex.y)};
      box.upper = {std::max(box.upper.x, vertex.x), std::max(box.upper.y, vertex.y)};
    }
    bounds_[i] = {box.lower - Vec2{shape.radius, shape.radius}, box.upper + Vec2{shape.radius, shape.radius}};
  }
}

AccuracyProbe::PairPenetration AccuracyProbe::measure_penetration() {
  // Sweep along the axis where the movable bodies' centres vary most: fewest intervals overlap.
  double sum_x = 0.0, sum_y = 0.0, sum_xx = 0.0, sum_yy = 0.0;
  int movable = 0;
  sweep_order_.clear();
  for (std::size_t i = 0; i < shapes_.size(); ++i) {
    if (!finite_[i]) continue;
    sweep_order_.push_back(static_cast<int>(i));
    if (shapes_[i].type == BodyType::static_body) continue;
    const Vec2 centre = 0.5 * (bounds_[i].lower + bounds_[i].upper);
    sum_x += centre.x;
    sum_y += centre.y;
    sum_xx += centre.x * centre.x;
    sum_yy += centre.y * centre.y;
    ++movable;
  }
  const bool sweep_y = movable > 0 && sum_yy - sum_y * sum_y / movable > sum_xx - sum_x * sum_x / movable;
  const auto lower = [&](int body) { return sweep_y ? bounds_[body].lower.y : bounds_[body].lower.x; };
  const auto upper = [&](int body) { return sweep_y ? bounds_[body].upper.y : bounds_[body].upper.x; };
  const auto cross_overlap = [&](int a, int b) {
    return sweep_y ? bounds_[a].lower.x <= bounds_[b].upper.x && bounds_[b].lower.x <= bounds_[a].upper.x
                   : bounds_[a].lower.y <= bounds_[b].upper.y && bounds_[b].lower.y <= bounds_[a].upper.y;
  };
  std::sort(sweep_order_.begin(), sweep_order_.end(), [&](int a, int b) { return lower(a) < lower(b); });

  PairPenetration result;
  for (std::size_t first = 0; first < sweep_order_.size(); ++first) {
    const int a = sweep_order_[first];
    for (std::size_t second = first + 1; second < sweep_order_.size(); ++second) {
      const int b = sweep_order_[second];
      if (lower(b) > upper(a)) break;
      const bool both_static =
          shapes_[a].type == BodyType::static_body && shapes_[b].type == BodyType::static_body;
      if (both_static || !cross_overlap(a, b) || joined(a, b)) continue;
      const double depth = penetration_depth(placed(a), placed(b));
      if (depth <= 0.0) continue;
      result.max = std::max(result.max, depth);
      result.sum += depth;
      ++result.count;
    }
  }
  return result;
}

AccuracySample AccuracyProbe::measure(int step, const std::vector<BodyState>& states) {
  if (states.size() != shapes_.size()) {
    throw std::invalid_argument("AccuracyProbe::measure: " + std::to_string(states.size()) + " states for " +
                                std::to_string(shapes_.size()) + " bodies");
  }
  place_shapes(states);
  const PairPenetration penetration = measure_penetration();

  AccuracySample sample;
  sample.step = step;
  sample.max_penetration = penetration.max;
  sample.mean_penetration = penetration.count > 0 ? penetration.sum / penetration.count : 0.0;
  for (std::size_t i = 0; i < shapes_.size(); ++i) {
    if (!finite_[i]) {
      ++sample.nan;
      continue;
    }
    const BodyShape& shape = shapes_[i];
    if (shape.type != BodyType::dynamic) continue;
    const BodyState& state = states[i];
    const Vec2 moved = state.position - start_[i].position;
    sample.max_displacement = std::max(sample.max_displacement, length(moved));
    sample.max_lateral_drift = std::max(sample.max_lateral_drift, std::abs(moved.x));
    sample.kinetic_energy += 0.5 * shape.mass * dot(state.linear_velocity, state.linear_velocity) +
                             0.5 * shape.inertia * state.angular_velocity * state.angular_velocity;
    const Vec2 p = state.position;
    const bool inside =
        p.x >= bounds_lower_.x && p.x <= bounds_upper_.x && p.y >= bounds_lower_.y && p.y <= bounds_upper_.y;
    if (!inside) ++sample.escaped;
  }
  return sample;
}

std::string state_hash(const std::vector<BodyState>& states) {
  Fnv1a64 hash;
  for (const BodyState& state : states) {
    for (double value : {state.position.x, state.position.y, state.angle, state.linear_velocity.x,
                         state.linear_velocity.y, state.angular_velocity}) {
      hash.add(value);
    }
  }
  return hash.hex();
}

}  // namespace fxbench

// Shape factories and per-shape geometry: validation, polygon normalisation, mass properties
// and bounds.
//
// Invariant: every FxShape a factory returns is either a circle of finite positive radius, or a
// strictly convex counter-clockwise polygon of 3..max_vertices finite, distinct vertices with an
// area of at least min_polygon_area and a unit outward normal per edge. Anything else is rejected
// with an FxInvalidArgument naming the factory and the field.
#include "fx2d/Shape.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace fx2d {
namespace {

// Vertices closer than this are one vertex, and a vertex closer than this to the line through
// its neighbours is not a corner (metres). Far below the 5 mm linear slop the solver works to,
// far above float rounding for shapes of the sizes a scene holds.
constexpr float feature_tolerance = 1.0e-5f;
constexpr float min_polygon_area = 1.0e-8f;  // m^2

std::string format_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string format_point(FxVec2f v) {
  char text[64];
  std::snprintf(text, sizeof text, "(%g, %g)", double(v.x), double(v.y));
  return text;
}

[[noreturn]] void reject(const char* factory, const std::string& field, const std::string& problem) {
  throw FxInvalidArgument(std::string(factory) + ": " + field + ": " + problem);
}

// Shapes are bounded so that every product the narrow phase and the mass integrals form stays
// finite in float (a size of 1e19 already overflows an edge cross product).
void require_size(const char* factory, const char* field, float value) {
  if (!(std::isfinite(value) && value > 0.0f && value <= FxShape::max_extent))
    reject(factory, field, format_number(value) + " given, finite, > 0 and <= " + format_number(FxShape::max_extent) + " expected");
}

void require_bounded(const char* factory, const char* field, FxVec2f value) {
  if (!(is_finite(value) && std::fabs(value.x) <= FxShape::max_extent && std::fabs(value.y) <= FxShape::max_extent))
    reject(factory, field, format_point(value) + " given, finite coordinates within +-" + format_number(FxShape::max_extent) + " expected");
}

std::string vertex_field(int index) { return "vertices[" + std::to_string(index) + "]"; }

// Dividing by the length (rather than multiplying by its inverse) keeps axis-aligned normals
// exactly unit, so boxes meet face to face with exactly zero separation.
FxVec2f outward_normal(FxVec2f edge) {
  const float len = length(edge);
  return {edge.y / len, -edge.x / len};
}

// Signed turn at `corner`: positive for a left (counter-clockwise) turn.
float turn(FxVec2f previous, FxVec2f corner, FxVec2f next) { return cross(corner - previous, next - corner); }

// Integrals over a fan of triangles from `origin`: area, first moment and second moment.
struct FanIntegrals {
  float area = 0.0f;
  FxVec2f first_moment;        // integral of (x - origin) dA
  float second_moment = 0.0f;  // integral of |x - origin|^2 dA
};

FanIntegrals integrate_fan(std::span<const FxVec2f> vertices, FxVec2f origin) {
  FanIntegrals sums;
  const int count = int(vertices.size());
  for (int i = 0; i < count; ++i) {
    const FxVec2f e1 = vertices[i] - origin;
    const FxVec2f e2 = vertices[(i + 1) % count] - origin;
    const float doubled_area = cross(e1, e2);
    sums.area += 0.5f * doubled_area;
    sums.first_moment += (doubled_area / 6.0f) * (e1 + e2);
    const float xx = e1.x * e1.x + e1.x * e2.x + e2.x * e2.x;
    const float yy = e1.y * e1.y + e1.y * e2.y + e2.y * e2.y;
    sums.second_moment += (doubled_area / 12.0f) * (xx + yy);
  }
  return sums;
}

// The mean of the vertices lies inside a convex polygon and close to every vertex, which keeps
// the fan integrals well conditioned wherever the polygon sits.
FxVec2f vertex_mean(std::span<const FxVec2f> vertices) {
  FxVec2f sum;
  for (FxVec2f v : vertices) sum += v;
  return (1.0f / float(vertices.size())) * sum;
}

// A polygon outline that passed validation, counter-clockwise.
struct Outline {
  std::array<FxVec2f, FxShape::max_vertices> vertices{};
  int count = 0;
  std::span<const FxVec2f> points() const { return {vertices.data(), std::size_t(count)}; }
};

void require_distinct(const char* factory, std::span<const FxVec2f> input) {
  const int count = int(input.size());
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      if (distance(input[i], input[j]) < feature_tolerance) {
        reject(factory, vertex_field(j), "duplicates " + vertex_field(i) + ", distinct points expected");
      }
    }
  }
}

void require_corners(const char* factory, std::span<const FxVec2f> input) {
  const int count = int(input.size());
  for (int i = 0; i < count; ++i) {
    const FxVec2f previous = input[(i + count - 1) % count];
    const FxVec2f next = input[(i + 1) % count];
    // |turn| / chord is the corner's distance from the chord joining its neighbours.
    if (std::abs(turn(previous, input[i], next)) < feature_tolerance * distance(previous, next)) {
      reject(factory, vertex_field(i),
             format_point(input[i]) + " is collinear with its neighbours, a corner expected");
    }
  }
}

// Convex and not self-intersecting (which a same-sign test on the corners alone would miss):
// every vertex lies strictly left of every edge it does not belong to.
void require_convex(const char* factory, std::span<const FxVec2f> ccw) {
  const int count = int(ccw.size());
  for (int i = 0; i < count; ++i) {
    const int next = (i + 1) % count;
    for (int j = 0; j < count; ++j) {
      if (j != i && j != next && turn(ccw[i], ccw[next], ccw[j]) <= 0.0f) {
        reject(factory, "vertices",
               "outline is not convex at vertex " + std::to_string(j) + ", a convex outline expected");
      }
    }
  }
}

Outline validated_outline(const char* factory, std::span<const FxVec2f> input) {
  const int count = int(input.size());
  if (count < 3) reject(factory, "vertices", std::to_string(count) + " given, at least 3 expected");
  if (count > FxShape::max_vertices) {
    reject(factory, "vertices",
           std::to_string(count) + " given, at most " + std::to_string(FxShape::max_vertices) + " expected");
  }
  for (int i = 0; i < count; ++i) require_bounded(factory, vertex_field(i).c_str(), input[i]);
  require_distinct(factory, input);
  require_corners(factory, input);

  Outline outline;
  outline.count = count;
  // Every corner of a convex outline turns the same way as the first.
  const bool clockwise = turn(input[count - 1], input[0], input[1]) < 0.0f;
  for (int i = 0; i < count; ++i) outline.vertices[i] = clockwise ? input[count - 1 - i] : input[i];
  require_convex(factory, outline.points());

  const float area = integrate_fan(outline.points(), vertex_mean(outline.points())).area;
  if (area < min_polygon_area) {
    reject(factory, "vertices",
           "area " + format_number(area) + " m^2, at least " + format_number(min_polygon_area) +
               " m^2 expected");
  }
  return outline;
}

// Four vertices (+-a, +-b): distinct, they are the four corners of a box centred on the origin.
bool is_centred_box(const Outline& outline) {
  if (outline.count != 4) return false;
  const FxVec2f corner = outline.vertices[0];
  for (FxVec2f v : outline.points()) {
    if (std::fabs(v.x) != std::fabs(corner.x) || std::fabs(v.y) != std::fabs(corner.y)) return false;
  }
  return true;
}

}  // namespace

FxShape FxShape::circle(float radius, FxVec2f center) {
  require_size("FxShape::circle", "radius", radius);
  require_bounded("FxShape::circle", "center", center);
  FxShape shape;
  shape.type_ = FxShapeType::circle;
  shape.radius_ = radius;
  shape.centroid_ = center;
  shape.extent_ = radius;
  return shape;
}

FxShape FxShape::box(float half_width, float half_height, FxVec2f center, float angle) {
  constexpr const char* factory = "FxShape::box";
  require_size(factory, "half_width", half_width);
  require_size(factory, "half_height", half_height);
  require_bounded(factory, "center", center);
  if (!std::isfinite(angle)) reject(factory, "angle", format_number(angle) + " given, finite expected");
  const FxTransform placement{center, FxRot::from_angle(angle)};
  const std::array<FxVec2f, 4> corners{transform_point(placement, {-half_width, -half_height}),
                                       transform_point(placement, {half_width, -half_height}),
                                       transform_point(placement, {half_width, half_height}),
                                       transform_point(placement, {-half_width, half_height})};
  // Validated here so that a box too small to be a polygon is reported as a box.
  const Outline outline = validated_outline(factory, corners);
  return polygon(outline.points());
}

FxShape FxShape::polygon(std::span<const FxVec2f> input) {
  const Outline outline = validated_outline("FxShape::polygon", input);
  FxShape shape;
  shape.type_ = FxShapeType::polygon;
  shape.vertex_count_ = outline.count;
  shape.centred_box_ = is_centred_box(outline);
  for (int i = 0; i < outline.count; ++i) {
    shape.vertices_[i] = outline.vertices[i];
    shape.normals_[i] = outward_normal(outline.vertices[(i + 1) % outline.count] - outline.vertices[i]);
  }
  const FxVec2f origin = vertex_mean(shape.vertices());
  const FanIntegrals fan = integrate_fan(shape.vertices(), origin);
  shape.centroid_ = origin + (1.0f / fan.area) * fan.first_moment;
  for (FxVec2f v : shape.vertices()) {
    const float reach = distance(v, shape.centroid_);
    if (reach > shape.extent_) shape.extent_ = reach;
  }
  return shape;
}

FxMassData FxShape::mass_data(float density) const {
  if (!(std::isfinite(density) && density > 0.0f)) {
    reject("FxShape::mass_data", "density", format_number(density) + " given, finite and > 0 expected");
  }
  FxMassData data;
  if (type_ == FxShapeType::circle) {
    data.mass = density * std::numbers::pi_v<float> * radius_ * radius_;
    data.center = centroid_;
    data.rotational_inertia = 0.5f * data.mass * radius_ * radius_;
    return data;
  }
  const FxVec2f origin = vertex_mean(vertices());
  const FanIntegrals fan = integrate_fan(vertices(), origin);
  const FxVec2f offset = (1.0f / fan.area) * fan.first_moment;
  data.mass = density * fan.area;
  data.center = origin + offset;
  // Parallel-axis theorem: move the second moment from the fan origin to the centre of mass.
  data.rotational_inertia = density * fan.second_moment - data.mass * length_squared(offset);
  return data;
}

void FxShape::compute_aabb(const FxTransform& xf, FxAABB& out) const {
  if (type_ == FxShapeType::circle) {
    const FxVec2f center = transform_point(xf, centroid_);
    out.lower = {center.x - radius_, center.y - radius_};
    out.upper = {center.x + radius_, center.y + radius_};
    return;
  }
  // Rounding is monotonic, so the translation added to the extreme rotated vertex gives the bits
  // the extreme transformed vertex would (and a -0 sum needs a -0 vertex, the least one alone).
  if (centred_box_) {
    // The corners rotate to (+-C +-S, +-S' +-C'), each product rounded alike up to its sign; the
    // farthest along an axis is |C| + |S|, rounded once as that corner's own sum.
    const float a = std::fabs(vertices_[0].x);
    const float b = std::fabs(vertices_[0].y);
    const FxVec2f reach{std::fabs(xf.q.c * a) + std::fabs(xf.q.s * b), std::fabs(xf.q.s * a) + std::fabs(xf.q.c * b)};
    out.lower = xf.p - reach;
    out.upper = xf.p + reach;
    return;
  }
  FxVec2f lower = rotate(xf.q, vertices_[0]);
  FxVec2f upper = lower;
  for (int i = 1; i < vertex_count_; ++i) {
    const FxVec2f v = rotate(xf.q, vertices_[i]);
    lower = min(lower, v);
    upper = max(upper, v);
  }
  out.lower = lower + xf.p;
  out.upper = upper + xf.p;
}

}  // namespace fx2d

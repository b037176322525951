// Collision shapes: a circle, or a convex polygon of at most FxShape::max_vertices vertices.
//
// A shape is defined in its body's local frame. Polygons are stored counter-clockwise with an
// outward unit normal per edge (normal i belongs to the edge from vertex i to vertex i+1), which
// is what the separating-axis test and clipping read. Shapes are validated when made: a factory
// that returns has produced a shape the narrow phase can trust.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

#include "fx2d/Math.h"

namespace fx2d {

// Thrown when a shape, entity, joint or scene is created from invalid input. what() names the
// field and what was expected, e.g. "FxShape::polygon: vertices: 2 given, at least 3 expected".
class FxInvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

enum class FxShapeType : std::uint8_t { circle, polygon };

// Mass properties of a shape at a given density.
struct FxMassData {
  float mass = 0.0f;           // kg
  FxVec2f center;              // centre of mass, body-local metres
  float rotational_inertia = 0.0f;  // kg m^2 about the centre of mass
};

class FxShape {
 public:
  static constexpr int max_vertices = 8;
  // Largest size and coordinate a shape may have (metres), so that every product formed from
  // shapes stays finite in float.
  static constexpr float max_extent = 1.0e6f;

  // A circle of radius in (0, max_extent] metres centred at `center` (body-local metres).
  static FxShape circle(float radius, FxVec2f center = {});
  // A box with half-extents in (0, max_extent] metres, centred at `center` and rotated by `angle` (radians)
  // in the body frame.
  static FxShape box(float half_width, float half_height, FxVec2f center = {}, float angle = 0.0f);
  // A convex polygon from 3 to max_vertices points in either winding. Rejected: fewer than 3 or
  // more than max_vertices points, coordinates beyond +-max_extent, duplicate or collinear points,
  // non-convex outlines, and an area below 1e-8 m^2.
  static FxShape polygon(std::span<const FxVec2f> vertices);

  FxShapeType type() const { return type_; }
  // Circle radius (metres); 0 for a polygon.
  float radius() const { return radius_; }
  // Circle centre, or polygon centroid (body-local metres).
  FxVec2f centroid() const { return centroid_; }
  int vertex_count() const { return vertex_count_; }
  // Polygon vertices, counter-clockwise (body-local metres).
  std::span<const FxVec2f> vertices() const { return {vertices_.data(), std::size_t(vertex_count_)}; }
  // Outward unit edge normals (body-local); normals()[i] belongs to edge (i, i+1).
  std::span<const FxVec2f> normals() const { return {normals_.data(), std::size_t(vertex_count_)}; }

  // Mass, centre of mass and rotational inertia for a density > 0 (kg/m^2).
  FxMassData mass_data(float density) const;
  // Tight world-space bounds of the shape placed by `xf`, written into `out` (no temporaries).
  void compute_aabb(const FxTransform& xf, FxAABB& out) const;
  // A length that bounds how far any point of the shape lies from its centroid (metres);
  // the solver uses it to bound how far rotation can move a surface in one step.
  float extent() const { return extent_; }
  // True for a polygon whose vertices are (+-a, +-b) exactly, as FxShape::box makes with no centre
  // or angle: the narrow phase and compute_aabb() treat such a box in closed form.
  bool centred_box() const { return centred_box_; }

 private:
  FxShapeType type_ = FxShapeType::circle;
  // A polygon whose vertices are (+-a, +-b) exactly, as FxShape::box makes with no centre or
  // angle: compute_aabb() bounds it in closed form, to the bit what its corners give.
  bool centred_box_ = false;
  int vertex_count_ = 0;
  float radius_ = 0.0f;
  float extent_ = 0.0f;
  FxVec2f centroid_;
  std::array<FxVec2f, max_vertices> vertices_{};
  std::array<FxVec2f, max_vertices> normals_{};
};

}  // namespace fx2d

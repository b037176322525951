// Tests for FxShape: every validation error, polygon normalisation, mass properties and bounds.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

#include "fx2d/Shape.h"

namespace fx2d {
namespace {

constexpr float nan = std::numeric_limits<float>::quiet_NaN();
constexpr float infinity = std::numeric_limits<float>::infinity();

// The message `make` throws, or a note that it threw nothing.
std::string error_of(const std::function<void()>& make) {
  try {
    make();
  } catch (const FxInvalidArgument& error) {
    return error.what();
  }
  return "<no FxInvalidArgument thrown>";
}

void expect_error(const std::function<void()>& make, const std::string& prefix, const std::string& detail) {
  const std::string message = error_of(make);
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
  EXPECT_NE(message.find(detail), std::string::npos) << message;
}

FxShape polygon_of(std::initializer_list<FxVec2f> points) {
  return FxShape::polygon({points.begin(), points.size()});
}

TEST(ShapeValidation, CircleRejectsNonPositiveRadius) {
  expect_error([] { FxShape::circle(0.0f); }, "FxShape::circle: radius: 0 given", "> 0 and <= 1e+06 expected");
  expect_error([] { FxShape::circle(-1.0f); }, "FxShape::circle: radius: -1 given", "> 0 and <= 1e+06 expected");
}

TEST(ShapeValidation, CircleRejectsNonFiniteRadius) {
  expect_error([] { FxShape::circle(nan); }, "FxShape::circle: radius:", "finite");
  expect_error([] { FxShape::circle(infinity); }, "FxShape::circle: radius:", "finite");
}

TEST(ShapeValidation, CircleRejectsNonFiniteCenter) {
  expect_error(
      [] {
        FxShape::circle(1.0f, {nan, 0.0f});
      },
      "FxShape::circle: center:", "finite coordinates within +-1e+06 expected");
}

TEST(ShapeValidation, BoxRejectsNonPositiveHalfWidth) {
  expect_error([] { FxShape::box(0.0f, 1.0f); }, "FxShape::box: half_width: 0 given", "> 0 and <= 1e+06 expected");
}

TEST(ShapeValidation, ShapesBeyondMaxExtentAreRejected) {
  // A box of 1e30 m would overflow its own edge cross products (found by the engine fuzzer).
  expect_error([] { FxShape::box(1.0e30f, 1.0f); }, "FxShape::box: half_width: 1e+30 given", "<= 1e+06 expected");
  expect_error([] { FxShape::circle(1.0f, {2.0e6f, 0.0f}); }, "FxShape::circle: center:", "within +-1e+06");
}

TEST(ShapeValidation, BoxRejectsNonPositiveHalfHeight) {
  expect_error([] { FxShape::box(1.0f, -2.0f); }, "FxShape::box: half_height: -2 given", "> 0 and <= 1e+06 expected");
}

TEST(ShapeValidation, BoxRejectsNonFiniteCenter) {
  expect_error(
      [] {
        FxShape::box(1.0f, 1.0f, {0.0f, infinity});
      },
      "FxShape::box: center:", "finite coordinates");
}

TEST(ShapeValidation, BoxRejectsNonFiniteAngle) {
  expect_error([] { FxShape::box(1.0f, 1.0f, {}, nan); }, "FxShape::box: angle:", "finite expected");
}

TEST(ShapeValidation, BoxTooSmallToBeAPolygonIsReportedAsABox) {
  expect_error([] { FxShape::box(4.0e-5f, 4.0e-5f); }, "FxShape::box: vertices:", "m^2 expected");
}

TEST(ShapeValidation, PolygonRejectsFewerThanThreeVertices) {
  expect_error(
      [] {
        polygon_of({{0.0f, 0.0f}, {1.0f, 0.0f}});
      },
      "FxShape::polygon: vertices: 2 given", "at least 3 expected");
}

TEST(ShapeValidation, PolygonRejectsMoreThanMaxVertices) {
  std::array<FxVec2f, FxShape::max_vertices + 1> ring;
  for (int i = 0; i < int(ring.size()); ++i) {
    const float angle = 2.0f * std::numbers::pi_v<float> * float(i) / float(ring.size());
    ring[i] = {std::cos(angle), std::sin(angle)};
  }
  expect_error([&] { FxShape::polygon(ring); }, "FxShape::polygon: vertices: 9 given", "at most 8 expected");
}

TEST(ShapeValidation, PolygonRejectsNonFiniteVertex) {
  expect_error(
      [] {
        polygon_of({{0.0f, 0.0f}, {1.0f, nan}, {0.0f, 1.0f}});
      },
      "FxShape::polygon: vertices[1]:", "finite coordinates within +-1e+06 expected");
}

TEST(ShapeValidation, PolygonRejectsDuplicateVertex) {
  expect_error(
      [] {
        polygon_of({{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}});
      },
      "FxShape::polygon: vertices[3]:", "duplicates vertices[1]");
}

TEST(ShapeValidation, PolygonRejectsCollinearVertex) {
  expect_error(
      [] {
        polygon_of({{0.0f, 0.0f}, {1.0f, 0.0f}, {2.0f, 0.0f}, {1.0f, 1.0f}});
      },
      "FxShape::polygon: vertices[1]:", "collinear");
}

TEST(ShapeValidation, PolygonRejectsReflexCorner) {
  // An arrowhead: vertex 3 points inwards.
  expect_error(
      [] {
        polygon_of({{0.0f, 0.0f}, {2.0f, 0.0f}, {2.0f, 2.0f}, {1.0f, 0.5f}, {0.0f, 2.0f}});
      },
      "FxShape::polygon: vertices:", "not convex");
}

TEST(ShapeValidation, PolygonRejectsSelfIntersectingStar) {
  // A pentagram turns the same way at every corner but winds twice.
  std::array<FxVec2f, 5> star;
  for (int i = 0; i < 5; ++i) {
    const float angle = 2.0f * std::numbers::pi_v<float> * float(2 * i) / 5.0f;
    star[i] = {std::cos(angle), std::sin(angle)};
  }
  expect_error([&] { FxShape::polygon(star); }, "FxShape::polygon: vertices:", "not convex");
}

TEST(ShapeValidation, PolygonRejectsTinyArea) {
  // Sides of 1e-4 m pass the duplicate and corner tests but enclose only 5e-9 m^2.
  expect_error(
      [] {
        polygon_of({{0.0f, 0.0f}, {1.0e-4f, 0.0f}, {0.0f, 1.0e-4f}});
      },
      "FxShape::polygon: vertices: area", "at least 1e-08 m^2 expected");
}

TEST(ShapeValidation, MassDataRejectsNonPositiveDensity) {
  expect_error([] { (void)FxShape::circle(1.0f).mass_data(0.0f); }, "FxShape::mass_data: density: 0 given",
               "> 0 expected");
}

TEST(Polygon, ClockwiseInputIsStoredCounterClockwiseWithOutwardNormals) {
  const std::array<FxVec2f, 4> clockwise{{{0.0f, 0.0f}, {0.0f, 1.0f}, {2.0f, 1.0f}, {2.0f, 0.0f}}};
  const FxShape shape = FxShape::polygon(clockwise);
  ASSERT_EQ(shape.vertex_count(), 4);
  const auto v = shape.vertices();
  const auto n = shape.normals();
  for (int i = 0; i < 4; ++i) {
    const FxVec2f edge = v[(i + 1) % 4] - v[i];
    EXPECT_GT(cross(edge, v[(i + 2) % 4] - v[(i + 1) % 4]), 0.0f) << "corner " << i + 1 << " turns clockwise";
    EXPECT_FLOAT_EQ(length(n[i]), 1.0f);
    EXPECT_FLOAT_EQ(dot(n[i], edge), 0.0f);
    for (int j = 0; j < 4; ++j)
      EXPECT_LE(dot(n[i], v[j] - v[i]), 0.0f) << "normal " << i << " points inwards";
  }
  // The same points, in reverse order.
  for (int i = 0; i < 4; ++i) EXPECT_EQ(v[i], clockwise[3 - i]);
}

TEST(Polygon, TriangleCentroidIsTheVertexMeanAndInertiaMatchesSideLengths) {
  const FxShape triangle = polygon_of({{0.0f, 0.0f}, {3.0f, 0.0f}, {0.0f, 3.0f}});
  // Area 4.5; sides 3, 3 and 3 sqrt 2; the polar moment about the centroid of a uniform triangle
  // is m (a^2 + b^2 + c^2) / 36 = m. Float rounding on values of order 10 stays below 1e-5.
  const FxMassData data = triangle.mass_data(2.0f);
  EXPECT_NEAR(triangle.centroid().x, 1.0f, 1.0e-6f);
  EXPECT_NEAR(triangle.centroid().y, 1.0f, 1.0e-6f);
  EXPECT_NEAR(data.mass, 9.0f, 1.0e-5f);
  EXPECT_NEAR(data.center.x, 1.0f, 1.0e-6f);
  EXPECT_NEAR(data.center.y, 1.0f, 1.0e-6f);
  EXPECT_NEAR(data.rotational_inertia, 9.0f, 1.0e-5f);
  // The farthest vertex, (3, 0) or (0, 3), lies sqrt(5) from (1, 1).
  EXPECT_NEAR(triangle.extent(), std::sqrt(5.0f), 1.0e-6f);
}

TEST(Polygon, BoxMassDataMatchesAnalyticWhereverTheBoxIsPlaced) {
  constexpr float half_width = 1.5f;
  constexpr float half_height = 0.5f;
  constexpr float density = 2.0f;
  // m = 4 hw hh rho; I = m (w^2 + h^2) / 12; neither depends on where the box sits in its body.
  constexpr float mass = 4.0f * half_width * half_height * density;
  constexpr float inertia =
      mass * (4.0f * half_width * half_width + 4.0f * half_height * half_height) / 12.0f;
  const FxVec2f offset{3.0f, -2.0f};
  for (const FxShape& box :
       {FxShape::box(half_width, half_height), FxShape::box(half_width, half_height, offset, 0.6f)}) {
    const FxMassData data = box.mass_data(density);
    // Relative 1e-6 covers the rounding of sums of a few terms of order 10.
    EXPECT_NEAR(data.mass, mass, 1.0e-6f * mass);
    EXPECT_NEAR(data.rotational_inertia, inertia, 1.0e-5f * inertia);
    EXPECT_NEAR(data.center.x, box.centroid().x, 1.0e-6f);
    EXPECT_NEAR(data.center.y, box.centroid().y, 1.0e-6f);
    EXPECT_NEAR(box.extent(), std::sqrt(half_width * half_width + half_height * half_height), 1.0e-5f);
  }
  const FxShape placed = FxShape::box(half_width, half_height, offset, 0.6f);
  EXPECT_NEAR(placed.centroid().x, offset.x, 1.0e-6f);
  EXPECT_NEAR(placed.centroid().y, offset.y, 1.0e-6f);
}

TEST(Polygon, AxisAlignedBoxHasExactUnitNormals) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  const std::array<FxVec2f, 4> expected{{{0.0f, -1.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}, {-1.0f, 0.0f}}};
  for (int i = 0; i < 4; ++i) EXPECT_EQ(box.normals()[i], expected[i]);
}

TEST(Circle, MassDataIsUniformDisc) {
  const FxShape circle = FxShape::circle(0.5f, {1.0f, 2.0f});
  const FxMassData data = circle.mass_data(3.0f);
  const float mass = 3.0f * std::numbers::pi_v<float> * 0.25f;
  EXPECT_FLOAT_EQ(data.mass, mass);
  EXPECT_FLOAT_EQ(data.rotational_inertia, 0.5f * mass * 0.25f);
  EXPECT_EQ(data.center, (FxVec2f{1.0f, 2.0f}));
  EXPECT_EQ(circle.extent(), 0.5f);
}

TEST(Bounds, RotatedBoxAabbHasProjectedHalfExtents) {
  const FxShape box = FxShape::box(1.0f, 0.5f);
  const float angle = 0.5f;
  const FxTransform xf{{2.0f, 3.0f}, FxRot::from_angle(angle)};
  FxAABB aabb;
  box.compute_aabb(xf, aabb);
  const float c = std::abs(std::cos(angle));
  const float s = std::abs(std::sin(angle));
  const float extent_x = 1.0f * c + 0.5f * s;
  const float extent_y = 1.0f * s + 0.5f * c;
  EXPECT_NEAR(aabb.lower.x, 2.0f - extent_x, 1.0e-6f);
  EXPECT_NEAR(aabb.upper.x, 2.0f + extent_x, 1.0e-6f);
  EXPECT_NEAR(aabb.lower.y, 3.0f - extent_y, 1.0e-6f);
  EXPECT_NEAR(aabb.upper.y, 3.0f + extent_y, 1.0e-6f);
}

// The bounds of each vertex placed by transform_point(), the engine's own arithmetic for a point.
FxAABB bounds_of_placed_vertices(const FxShape& shape, const FxTransform& xf) {
  FxAABB box{transform_point(xf, shape.vertices()[0]), transform_point(xf, shape.vertices()[0])};
  for (FxVec2f v : shape.vertices()) box = union_of(box, {transform_point(xf, v), transform_point(xf, v)});
  return box;
}

std::array<std::uint32_t, 4> bits_of(const FxAABB& box) {
  return {std::bit_cast<std::uint32_t>(box.lower.x), std::bit_cast<std::uint32_t>(box.lower.y),
          std::bit_cast<std::uint32_t>(box.upper.x), std::bit_cast<std::uint32_t>(box.upper.y)};
}

// compute_aabb() bounds a centred box in closed form and adds a polygon's translation once: both
// must give, to the bit, the bounds of the vertices placed one by one (the state hashes rest on it).
TEST(Bounds, AabbBitsEqualThoseOfTheVerticesPlacedOneByOne) {
  const std::array<FxVec2f, 5> pentagon{{{0.3f, -0.7f}, {1.1f, 0.1f}, {0.4f, 0.9f}, {-0.6f, 0.5f}, {-0.7f, -0.4f}}};
  const std::array<FxVec2f, 4> clockwise_box{{{-0.3f, 0.7f}, {0.3f, 0.7f}, {0.3f, -0.7f}, {-0.3f, -0.7f}}};
  const std::array<FxShape, 5> shapes{FxShape::box(0.5f, 0.25f), FxShape::box(1.0e-2f, 3.0f), FxShape::polygon(clockwise_box),
                                      FxShape::box(0.5f, 0.25f, {0.1f, 0.0f}), FxShape::polygon(pentagon)};
  const std::array<FxVec2f, 5> origins{{{0.0f, 0.0f}, {-0.0f, -0.0f}, {0.5f, -0.25f}, {3.7f, -12.1f}, {-1.0e6f, 7.0e5f}}};
  const std::array<FxRot, 4> exact_turns{{{1.0f, 0.0f}, {-0.0f, 1.0f}, {-1.0f, -0.0f}, {0.0f, -1.0f}}};
  for (const FxShape& shape : shapes) {
    for (FxVec2f origin : origins) {
      for (int step = 0; step < 720; ++step) {
        const FxRot turn = step < 4 ? exact_turns[step] : FxRot::from_angle(0.00873f * float(step) - 3.1f);
        const FxTransform xf{origin, turn};
        FxAABB aabb;
        shape.compute_aabb(xf, aabb);
        ASSERT_EQ(bits_of(aabb), bits_of(bounds_of_placed_vertices(shape, xf))) << "step " << step;
      }
    }
  }
}

TEST(Bounds, CircleAabbIsCentreOffsetByRadius) {
  const FxShape circle = FxShape::circle(0.25f, {1.0f, 0.0f});
  FxAABB aabb;
  circle.compute_aabb({{0.0f, 5.0f}, FxRot::from_angle(0.5f * std::numbers::pi_v<float>)}, aabb);
  // The quarter turn carries the local centre (1, 0) to (0, 1), then up by 5.
  EXPECT_NEAR(aabb.lower.x, -0.25f, 1.0e-6f);
  EXPECT_NEAR(aabb.upper.x, 0.25f, 1.0e-6f);
  EXPECT_NEAR(aabb.lower.y, 5.75f, 1.0e-6f);
  EXPECT_NEAR(aabb.upper.y, 6.25f, 1.0e-6f);
}

}  // namespace
}  // namespace fx2d

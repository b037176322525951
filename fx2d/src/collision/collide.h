// Narrow phase: contact manifolds between pairs of shapes.
//
// A manifold holds up to two points with a shared normal pointing from shape A to shape B. Each
// point carries a feature id naming the pair of features (vertex/edge indices of A and B, and
// which shape held the reference face) that produced it, so the contact cache can match points
// across steps and carry their impulses (warm starting). Points are reported speculatively: any
// point whose separation is below `speculative_distance` is kept, so the solver can stop bodies
// before they touch rather than after they overlap.
//
// Callers pass transforms relative to a nearby origin (typically shape A's body origin) so that
// every coordinate handled here is small, whatever the bodies' distance from the world origin.
#pragma once

#include <cstdint>

#include "fx2d/Math.h"
#include "fx2d/Shape.h"

namespace fx2d::detail {

struct ManifoldPoint {
  FxVec2f point;          // midway between the two surfaces, in the frame of the transforms given
  float separation = 0;   // signed distance along the normal, negative when overlapping (metres)
  std::uint32_t id = 0;   // feature id, stable while the same features touch
};

// Whose face the normal is, and so which body it turns with while the step moves the pair: a
// polygon's face normal turns with that polygon, two circles' normal with neither.
enum class NormalFrame : std::uint8_t { world, body_a, body_b };

// A face that held two polygons at least the speculative distance apart. Most pairs the broad
// phase keeps are apart, and stay apart along the same face step after step, so the pair's next
// collision tries that face first and, while it still separates them, skips the full search.
// Skipping the collision too while a bound on the pair's motion since showed that face could not
// have closed to the speculative distance (the same bits) cut settling_boxes' instructions by 1.7%
// (200) and 2.6% (800), but not its time: collide took 1.02-1.05 times as long. Nor did skipping
// it when the shapes' bounding circles lay further apart than the margin (the same bits; 51% of
// settling_boxes 200's full collisions passed that test, and 77% were apart): instructions 0.992
// and 0.982, collide 1.042 and 1.003. A pair held apart by its face costs little more than the test.
struct SeparatingFace {
  enum class Owner : std::uint8_t { none, a, b };
  Owner owner = Owner::none;
  std::uint8_t edge = 0;
};

struct Manifold {
  FxVec2f normal;         // unit, from A towards B
  NormalFrame normal_frame = NormalFrame::world;
  SeparatingFace separating_face;  // with no points: the face that found two polygons apart, if one did
  ManifoldPoint points[2];
  int point_count = 0;    // 0 when the shapes are farther apart than the speculative distance
};

void collide_circles(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
                     float speculative_distance, Manifold& out);
void collide_polygon_circle(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
                            float speculative_distance, Manifold& out);
// `first_try` is the face that separated the pair last time (the previous manifold's
// separating_face, or none; an edge of that polygon): tried before the others, it changes only how
// soon a separated pair is found apart, never the manifold.
// A centred box as A (FxShape::centred_box) finds its faces' and B's faces' separations in
// closed form, the same bits as the vertex loops every other pair runs; `search` lets a test run
// the loops on a box to check that.
enum class FaceSearch : std::uint8_t { closed_form_for_boxes, vertex_loops };
void collide_polygons(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
                      float speculative_distance, SeparatingFace first_try, Manifold& out,
                      FaceSearch search = FaceSearch::closed_form_for_boxes);

// Dispatches on the two shape types. A circle-polygon pair is solved as polygon-circle and its
// normal flipped, so the result always points from `a` to `b`.
void collide(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
             float speculative_distance, SeparatingFace first_try, Manifold& out);

}  // namespace fx2d::detail

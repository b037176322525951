// Tests for the narrow phase: manifolds with known geometry, speculative filtering, feature ids
// and the direction of the normal.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

#include "collision/collide.h"

namespace fx2d::detail {
namespace {

// Coordinates here are below 10 m, where a float ulp is under 1e-6 m and each result is a few
// roundings away from exact; 1e-5 m is far below any geometric mistake the tests look for.
constexpr float tolerance = 1.0e-5f;
constexpr float speculative = 0.02f;  // four linear slops, as the solver uses

FxTransform at(float x, float y, float angle = 0.0f) { return {{x, y}, FxRot::from_angle(angle)}; }

Manifold collide_pair(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
                      float speculative_distance = speculative) {
  Manifold m;
  collide(a, xf_a, b, xf_b, speculative_distance, {}, m);
  return m;
}

void expect_near(FxVec2f actual, FxVec2f expected) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
}

// The manifold's points ordered by x, to compare with expectations independent of clip order.
void sort_by_x(Manifold& m) {
  if (m.point_count == 2 && m.points[1].point.x < m.points[0].point.x) std::swap(m.points[0], m.points[1]);
}

TEST(CollideCircles, SeparatedCirclesReportDistanceMinusRadiiAlongCentreLine) {
  const FxShape a = FxShape::circle(1.0f);
  const FxShape b = FxShape::circle(0.5f);
  // Centres 5 apart along (0.6, 0.8): surfaces at (0.6, 0.8) and (2.7, 3.6), 3.5 apart.
  const Manifold m = collide_pair(a, at(0.0f, 0.0f), b, at(3.0f, 4.0f), 4.0f);
  ASSERT_EQ(m.point_count, 1);
  EXPECT_NEAR(m.points[0].separation, 3.5f, tolerance);
  expect_near(m.normal, {0.6f, 0.8f});
  expect_near(m.points[0].point, {1.65f, 2.2f});
  EXPECT_EQ(collide_pair(a, at(0.0f, 0.0f), b, at(3.0f, 4.0f), 3.5f).point_count, 0);
}

TEST(CollideCircles, TouchingCirclesReportZeroSeparation) {
  const FxShape circle = FxShape::circle(0.5f);
  const Manifold m = collide_pair(circle, at(0.0f, 0.0f), circle, at(1.0f, 0.0f));
  ASSERT_EQ(m.point_count, 1);
  EXPECT_EQ(m.points[0].separation, 0.0f);
  expect_near(m.points[0].point, {0.5f, 0.0f});
}

TEST(CollidePolygons, BoxRestingOnBoxTouchesAtTheCornersOfTheOverlap) {
  const FxShape ground = FxShape::box(2.0f, 0.5f);
  const FxShape box = FxShape::box(0.5f, 0.5f);
  // Ground top at y = 0; the box spans x in [-0.2, 0.8] and sits on it exactly.
  Manifold m = collide_pair(ground, at(0.0f, -0.5f), box, at(0.3f, 0.5f));
  ASSERT_EQ(m.point_count, 2);
  sort_by_x(m);
  EXPECT_EQ(m.normal, (FxVec2f{0.0f, 1.0f}));
  for (const ManifoldPoint& p : m.points) EXPECT_EQ(p.separation, 0.0f);
  expect_near(m.points[0].point, {-0.2f, 0.0f});
  expect_near(m.points[1].point, {0.8f, 0.0f});
}

TEST(CollidePolygons, BoxOverhangingTheEdgeIsClippedToTheSupport) {
  const FxShape ground = FxShape::box(2.0f, 0.5f);
  const FxShape box = FxShape::box(0.5f, 0.5f);
  // The box spans x in [1.7, 2.7]; the ground ends at x = 2, so the overlap is [1.7, 2].
  Manifold m = collide_pair(ground, at(0.0f, -0.5f), box, at(2.2f, 0.5f));
  ASSERT_EQ(m.point_count, 2);
  sort_by_x(m);
  expect_near(m.points[0].point, {1.7f, 0.0f});
  expect_near(m.points[1].point, {2.0f, 0.0f});
}

TEST(CollidePolygons, OverlappingBoxesReportPenetrationDepth) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  // Centres 0.9 apart vertically: 0.1 of overlap, points midway at y = 0.45.
  Manifold m = collide_pair(box, at(0.0f, 0.0f), box, at(0.0f, 0.9f));
  ASSERT_EQ(m.point_count, 2);
  sort_by_x(m);
  expect_near(m.normal, {0.0f, 1.0f});
  for (const ManifoldPoint& p : m.points) EXPECT_NEAR(p.separation, -0.1f, tolerance);
  expect_near(m.points[0].point, {-0.5f, 0.45f});
  expect_near(m.points[1].point, {0.5f, 0.45f});
}

TEST(CollidePolygons, RotatedBoxCornerOnAFaceTouchesThereAndKeepsItsEdgesFarEnd) {
  const FxShape ground = FxShape::box(2.0f, 0.5f);
  const FxShape box = FxShape::box(0.5f, 0.5f);
  const float angle = 0.6f;
  const float c = std::cos(angle);
  const float s = std::sin(angle);
  // The lowest corner, local (-0.5, -0.5) rotated, lies 0.5 (c + s) below the centre; sink it 0.01.
  const FxVec2f corner_offset{0.5f * (s - c), -0.5f * (c + s)};
  const FxVec2f center{0.1f, -corner_offset.y - 0.01f};
  const Manifold m = collide_pair(ground, at(0.0f, -0.5f), box, {center, {c, s}});
  ASSERT_EQ(m.point_count, 2);
  expect_near(m.normal, {0.0f, 1.0f});
  EXPECT_NEAR(m.points[0].separation, -0.01f, tolerance);
  expect_near(m.points[0].point, {center.x + corner_offset.x, -0.005f});
  // The other end of the bottom edge, speculative: it rises sin(0.6) over the edge's 1 m.
  EXPECT_NEAR(m.points[1].separation, -0.01f + s, tolerance);
}

TEST(CollidePolygons, CardsLeaningTogetherMeetCornerToCornerAlongTheirBisector) {
  // Two cards leaning 20 degrees from vertical, mirror images across x = 0, whose top corners meet
  // there (an A-frame's apex), each pushed 1 mm towards the other. By symmetry the contact normal
  // is horizontal; either card's face normal would lean 20 degrees and cost friction tan 20.
  const FxShape card = FxShape::box(0.02f, 0.5f);
  const float angle = 0.34906585f;
  const float c = std::cos(angle);
  const float s = std::sin(angle);
  // The left card's top right corner, local (0.02, 0.5) turned by -angle.
  const FxVec2f corner_offset{0.02f * c + 0.5f * s, 0.5f * c - 0.02f * s};
  const float push = 0.001f;
  const FxTransform left{{push - corner_offset.x, -corner_offset.y}, FxRot::from_angle(-angle)};
  const FxTransform right{{corner_offset.x - push, -corner_offset.y}, FxRot::from_angle(angle)};
  for (const bool left_first : {true, false}) {
    const Manifold m = left_first ? collide_pair(card, left, card, right) : collide_pair(card, right, card, left);
    ASSERT_EQ(m.point_count, 1);
    expect_near(m.normal, {left_first ? 1.0f : -1.0f, 0.0f});
    // The corners overlap by 2 mm across the apex; measured along a card's face it is 2 cos 20 mm.
    EXPECT_NEAR(m.points[0].separation, -2.0f * push * c, tolerance);
  }
}

TEST(CollidePolygons, EdgesBeyondTheSpeculativeDistanceAreDropped) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  // A gap of 0.03 m between the faces.
  EXPECT_EQ(collide_pair(box, at(0.0f, 0.0f), box, at(0.0f, 1.03f), 0.02f).point_count, 0);
  const Manifold m = collide_pair(box, at(0.0f, 0.0f), box, at(0.0f, 1.03f), 0.04f);
  ASSERT_EQ(m.point_count, 2);
  for (const ManifoldPoint& p : m.points) EXPECT_NEAR(p.separation, 0.03f, tolerance);
  // A tilted box whose near corner is inside the speculative band and whose far corner is not: the
  // far corner stays, speculative, as the other end of the edge (the box may be struck down about
  // the near one within the step).
  const Manifold tilted = collide_pair(box, at(0.0f, 0.0f), box, at(0.2f, 1.0f, 0.02f), 0.005f);
  ASSERT_EQ(tilted.point_count, 2);
  const float near = std::min(tilted.points[0].separation, tilted.points[1].separation);
  const float far = std::max(tilted.points[0].separation, tilted.points[1].separation);
  EXPECT_LT(near, 0.005f);
  // The edge runs from the low corner to where A's side x = 0.5 clips it, rising tan 0.02 a metre.
  const float low_corner_x = 0.2f - 0.5f * std::cos(0.02f) + 0.5f * std::sin(0.02f);
  EXPECT_NEAR(far - near, (0.5f - low_corner_x) * std::tan(0.02f), tolerance);
  // Lifted clear of the band, neither end is kept.
  EXPECT_EQ(collide_pair(box, at(0.0f, 0.0f), box, at(0.2f, 1.03f, 0.02f), 0.005f).point_count, 0);
}

TEST(CollidePolygons, FeatureIdsAreStableUnderSmallMotionAndDistinctWithinAManifold) {
  const FxShape ground = FxShape::box(2.0f, 0.5f);
  const FxShape box = FxShape::box(0.5f, 0.5f);
  Manifold before = collide_pair(ground, at(0.0f, -0.5f), box, at(0.3f, 0.5f, 0.01f));
  Manifold after = collide_pair(ground, at(0.0f, -0.5f), box, at(0.31f, 0.499f, 0.012f));
  ASSERT_EQ(before.point_count, 2);
  ASSERT_EQ(after.point_count, 2);
  sort_by_x(before);
  sort_by_x(after);
  EXPECT_NE(before.points[0].id, before.points[1].id);
  EXPECT_EQ(before.points[0].id, after.points[0].id);
  EXPECT_EQ(before.points[1].id, after.points[1].id);
}

TEST(CollidePolygons, SwappingTheShapesKeepsThePointButNotTheId) {
  const FxShape ground = FxShape::box(2.0f, 0.5f);
  const FxShape box = FxShape::box(0.5f, 0.5f);
  // A tilted box's corner on the ground: the ground's top face is the reference whichever shape
  // is A, so the point and depth agree, while the id records that the reference moved to B.
  const Manifold ab = collide_pair(box, at(0.3f, 0.5f, 0.2f), ground, at(0.0f, -0.5f));
  const Manifold ba = collide_pair(ground, at(0.0f, -0.5f), box, at(0.3f, 0.5f, 0.2f));
  ASSERT_EQ(ab.point_count, 2);  // the corner, and the far end of its edge
  ASSERT_EQ(ba.point_count, 2);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NE(ab.points[i].id, ba.points[i].id);
    EXPECT_NEAR(ab.points[i].separation, ba.points[i].separation, tolerance);
    expect_near(ab.points[i].point, ba.points[i].point);
  }
}

TEST(CollidePolygons, EqualBoxesRockingSlightlyKeepTheirReferenceFace) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  // A tilt of 1e-4 rad changes the two faces' separations by about 5e-5 m, well inside the
  // 5e-4 m hysteresis, so A's face stays the reference and the ids do not change.
  Manifold left = collide_pair(box, at(0.0f, 0.0f), box, at(0.2f, 0.999f, -1.0e-4f));
  Manifold right = collide_pair(box, at(0.0f, 0.0f), box, at(0.2f, 0.999f, 1.0e-4f));
  ASSERT_EQ(left.point_count, 2);
  ASSERT_EQ(right.point_count, 2);
  sort_by_x(left);
  sort_by_x(right);
  EXPECT_EQ(left.points[0].id, right.points[0].id);
  EXPECT_EQ(left.points[1].id, right.points[1].id);
}

// Every field of the contact, compared to the bit; the separating face only as far as whether
// one was found, since of several faces that part a pair the one tried first may be named.
void expect_same_contact(const Manifold& actual, const Manifold& expected) {
  EXPECT_EQ(actual.point_count, expected.point_count);
  EXPECT_EQ(actual.normal, expected.normal);
  EXPECT_EQ(actual.normal_frame, expected.normal_frame);
  EXPECT_EQ(actual.separating_face.owner == SeparatingFace::Owner::none,
            expected.separating_face.owner == SeparatingFace::Owner::none);
  for (int i = 0; i < expected.point_count; ++i) {
    EXPECT_EQ(actual.points[i].point, expected.points[i].point);
    EXPECT_EQ(actual.points[i].separation, expected.points[i].separation);
    EXPECT_EQ(actual.points[i].id, expected.points[i].id);
  }
}

Manifold collide_trying_first(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
                              SeparatingFace first_try) {
  Manifold m;
  collide(a, xf_a, b, xf_b, speculative, first_try, m);
  return m;
}

TEST(CollidePolygons, ApartPolygonsNameAFaceThatSeparatesThemBsWhenBothDo) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  using Owner = SeparatingFace::Owner;
  // A level box 5 cm above another: A's top face and B's bottom face both part them; B's is named,
  // the cheaper to try again.
  const Manifold level = collide_pair(box, at(0.0f, 0.0f), box, at(0.0f, 1.05f));
  EXPECT_EQ(level.point_count, 0);
  ASSERT_EQ(level.separating_face.owner, Owner::b);
  EXPECT_EQ(box.normals()[level.separating_face.edge], (FxVec2f{0.0f, -1.0f}));
  // A box on its corner 5 cm above a level one: none of its slanted faces parts them, the level
  // box's top face does.
  const float tip = 0.5f * std::sqrt(2.0f);
  const Manifold corner = collide_pair(box, at(0.0f, 0.0f), box, at(0.0f, tip + 0.55f, 0.785398f));
  EXPECT_EQ(corner.point_count, 0);
  ASSERT_EQ(corner.separating_face.owner, Owner::a);
  EXPECT_EQ(box.normals()[corner.separating_face.edge], (FxVec2f{0.0f, 1.0f}));
}

TEST(CollidePolygons, TheFaceTriedFirstNeverChangesTheManifold) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  const FxShape wide = FxShape::box(1.5f, 0.25f);
  using Owner = SeparatingFace::Owner;
  // Pairs apart along A's face or B's, touching face to face, corner to face, and overlapping.
  const FxTransform placements[][2] = {{at(0.0f, 0.0f), at(0.1f, 1.05f)},
                                       {at(0.0f, 0.0f, 0.785398f), at(0.0f, 1.3f)},
                                       {at(0.0f, 0.0f), at(0.3f, 0.75f)},
                                       {at(0.0f, 0.0f), at(0.2f, 1.2f, 0.6f)},
                                       {at(0.0f, 0.0f, 0.1f), at(0.4f, 0.6f, -0.2f)}};
  for (const auto& [xf_a, xf_b] : placements) {
    const Manifold fresh = collide_pair(box, xf_a, wide, xf_b);
    for (const Owner owner : {Owner::a, Owner::b}) {
      for (std::uint8_t edge = 0; edge < 4; ++edge) {
        expect_same_contact(collide_trying_first(box, xf_a, wide, xf_b, {owner, edge}), fresh);
      }
    }
  }
}

// Every bit of two manifolds, the separating face included.
void expect_identical(const Manifold& actual, const Manifold& expected) {
  const auto bits = [](FxVec2f v) {
    return std::array{std::bit_cast<std::uint32_t>(v.x), std::bit_cast<std::uint32_t>(v.y)};
  };
  ASSERT_EQ(actual.point_count, expected.point_count);
  EXPECT_EQ(bits(actual.normal), bits(expected.normal));
  EXPECT_EQ(actual.normal_frame, expected.normal_frame);
  EXPECT_EQ(actual.separating_face.owner, expected.separating_face.owner);
  EXPECT_EQ(actual.separating_face.edge, expected.separating_face.edge);
  for (int i = 0; i < expected.point_count; ++i) {
    EXPECT_EQ(bits(actual.points[i].point), bits(expected.points[i].point));
    EXPECT_EQ(std::bit_cast<std::uint32_t>(actual.points[i].separation),
              std::bit_cast<std::uint32_t>(expected.points[i].separation));
    EXPECT_EQ(actual.points[i].id, expected.points[i].id);
  }
}

// A fixed sequence of floats in [lo, hi), the same on every platform.
class Sequence {
 public:
  float next(float lo, float hi) {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * float(state_ >> 40) * 0x1.0p-24f;
  }

 private:
  std::uint64_t state_ = 19;
};

TEST(CollidePolygons, ACentredBoxFindsTheFacesTheVertexLoopsFind) {
  const FxShape boxes[] = {FxShape::box(0.5f, 0.5f), FxShape::box(1.5f, 0.25f), FxShape::box(0.1f, 0.7f)};
  const FxVec2f pentagon[] = {{0.0f, -0.6f}, {0.5f, -0.2f}, {0.3f, 0.5f}, {-0.3f, 0.5f}, {-0.5f, -0.2f}};
  const FxShape others[] = {boxes[0], boxes[1], boxes[2], FxShape::box(0.5f, 0.5f, {0.1f, 0.0f}, 0.3f),
                            FxShape::polygon(pentagon)};
  ASSERT_TRUE(boxes[0].centred_box());
  ASSERT_FALSE(others[3].centred_box());
  Sequence random;
  int touching = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const FxShape& a = boxes[trial % 3];
    const FxShape& b = others[(trial / 3) % 5];
    // Half the trials turn B by a quarter turn plus at most a few ulps, and place it flush
    // against one of A's faces give or take a few micrometres: the near ties between faces.
    const bool aligned = trial % 2 == 0;
    const float quarter_turns = std::floor(random.next(0.0f, 4.0f));
    const float angle_b =
        aligned ? quarter_turns * 1.5707964f + random.next(-2.0e-7f, 2.0e-7f) : random.next(-3.2f, 3.2f);
    const float reach = a.extent() + b.extent();
    FxVec2f offset{random.next(-reach, reach), random.next(-reach, reach)};
    if (aligned) {
      float lowest = 0.0f, highest = 0.0f;
      for (FxVec2f v : b.vertices()) {
        const float y = rotate(FxRot::from_angle(angle_b), v).y;
        lowest = std::min(lowest, y);
        highest = std::max(highest, y);
      }
      const float top = std::abs(a.vertices()[0].y);
      const float gap = random.next(-1.0e-5f, 1.0e-5f);
      offset.y = offset.y < 0.0f ? -top - highest - gap : top - lowest + gap;
    }
    const FxTransform xf_a = at(random.next(-50.0f, 50.0f), random.next(-5.0f, 5.0f), random.next(-3.2f, 3.2f));
    const FxTransform xf_b{transform_point(xf_a, offset), mul(xf_a.q, FxRot::from_angle(angle_b))};
    // No face tried first, then one of A's or B's faces, as a pair apart last step tries it.
    const auto owner = trial % 3 == 0 ? SeparatingFace::Owner::a : SeparatingFace::Owner::b;
    const int tried_count = owner == SeparatingFace::Owner::a ? a.vertex_count() : b.vertex_count();
    const auto tried_edge = std::uint8_t(std::floor(random.next(0.0f, float(tried_count))));
    for (const SeparatingFace first_try : {SeparatingFace{}, SeparatingFace{owner, tried_edge}}) {
      Manifold fast, loops;
      collide_polygons(a, xf_a, b, xf_b, speculative, first_try, fast, FaceSearch::closed_form_for_boxes);
      collide_polygons(a, xf_a, b, xf_b, speculative, first_try, loops, FaceSearch::vertex_loops);
      SCOPED_TRACE("trial " + std::to_string(trial));
      expect_identical(fast, loops);
      if (HasFailure()) return;  // the first pose that differs says enough
      if (loops.point_count > 0) ++touching;
    }
  }
  // Enough of the pairs touch for the clip to see the faces chosen.
  EXPECT_GT(touching, 10000);
}

TEST(Collide, NormalPointsFromAToBForBothArgumentOrders) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  const FxShape wide = FxShape::box(1.5f, 0.25f);
  const FxShape circle = FxShape::circle(0.4f);
  const FxTransform xf_a = at(0.2f, -0.1f, 0.3f);
  const FxTransform xf_b = at(1.0f, 0.6f, -0.2f);
  for (const FxShape* a : {&box, &wide, &circle}) {
    for (const FxShape* b : {&box, &wide, &circle}) {
      const Manifold forward = collide_pair(*a, xf_a, *b, xf_b, 1.0f);
      const Manifold backward = collide_pair(*b, xf_b, *a, xf_a, 1.0f);
      ASSERT_GT(forward.point_count, 0);
      ASSERT_GT(backward.point_count, 0);
      // B lies up and to the right of A, so the normal must lean that way.
      EXPECT_GT(dot(forward.normal, xf_b.p - xf_a.p), 0.0f);
      expect_near(backward.normal, -forward.normal);
      EXPECT_NEAR(length(forward.normal), 1.0f, 1.0e-6f);
    }
  }
}

TEST(Collide, NormalTurnsWithTheBodyWhoseFaceItIs) {
  const FxShape box = FxShape::box(0.5f, 0.5f);
  const FxShape circle = FxShape::circle(0.25f);
  // A turned box's corner 1 cm above the top face of a level one: the level box's face is the
  // reference whichever argument it is.
  const FxTransform level = at(0.0f, 0.0f),
                    corner_down = at(0.0f, 0.5f + 0.01f + 0.5f * std::sqrt(2.0f), 0.785398f);
  EXPECT_EQ(collide_pair(box, level, box, corner_down).normal_frame, NormalFrame::body_a);
  EXPECT_EQ(collide_pair(box, corner_down, box, level).normal_frame, NormalFrame::body_b);
  // A circle above a face: the face's; beyond a corner: the normal follows the circle's centre.
  EXPECT_EQ(collide_pair(box, level, circle, at(0.2f, 0.76f)).normal_frame, NormalFrame::body_a);
  EXPECT_EQ(collide_pair(circle, at(0.2f, 0.76f), box, level).normal_frame, NormalFrame::body_b);
  EXPECT_EQ(collide_pair(box, level, circle, at(0.8f, 0.8f), 0.3f).normal_frame, NormalFrame::world);
  EXPECT_EQ(collide_pair(circle, at(0.0f, 0.0f), circle, at(0.0f, 0.51f)).normal_frame, NormalFrame::world);
}

TEST(CollidePolygonCircle, CircleInsidePolygonUsesFaceOfLeastPenetration) {
  const FxShape box = FxShape::box(1.0f, 0.5f);
  const FxShape circle = FxShape::circle(0.2f);
  // The centre (0.3, 0.1) is 0.4 below the top face, nearer than to any other: separation
  // -(0.4 + 0.2); surfaces at (0.3, 0.5) and (0.3, -0.1), midway (0.3, 0.2).
  const Manifold m = collide_pair(box, at(0.0f, 0.0f), circle, at(0.3f, 0.1f));
  ASSERT_EQ(m.point_count, 1);
  expect_near(m.normal, {0.0f, 1.0f});
  EXPECT_NEAR(m.points[0].separation, -0.6f, tolerance);
  expect_near(m.points[0].point, {0.3f, 0.2f});
}

TEST(CollidePolygonCircle, CircleNearACornerSeparatesFromTheVertex) {
  const FxShape box = FxShape::box(1.0f, 0.5f);
  const FxShape circle = FxShape::circle(0.25f);
  // The centre is (0.3, 0.4) beyond the corner (1, 0.5): 0.5 away, separation 0.25.
  const Manifold m = collide_pair(box, at(0.0f, 0.0f), circle, at(1.3f, 0.9f), 0.3f);
  ASSERT_EQ(m.point_count, 1);
  expect_near(m.normal, {0.6f, 0.8f});
  EXPECT_NEAR(m.points[0].separation, 0.25f, tolerance);
  // Midway between the corner and the circle's surface at (1.15, 0.7).
  expect_near(m.points[0].point, {1.075f, 0.6f});
  EXPECT_EQ(collide_pair(box, at(0.0f, 0.0f), circle, at(1.3f, 0.9f), 0.24f).point_count, 0);
}

TEST(CollidePolygonCircle, CircleAboveAFaceSeparatesAlongTheFaceNormal) {
  const FxShape box = FxShape::box(1.0f, 0.5f);
  const FxShape circle = FxShape::circle(0.25f);
  const Manifold m = collide_pair(box, at(0.0f, 0.0f, 0.5f * 3.14159265f), circle, at(-0.7f, 0.2f));
  // A quarter turn makes the box's top face point to -x at x = -0.5; the centre is 0.2 beyond it.
  ASSERT_EQ(m.point_count, 1);
  expect_near(m.normal, {-1.0f, 0.0f});
  EXPECT_NEAR(m.points[0].separation, -0.05f, tolerance);
}

}  // namespace
}  // namespace fx2d::detail

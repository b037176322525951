// Narrow phase: contact manifolds for circle-circle, polygon-circle and polygon-polygon pairs.
//
// Polygon pairs use the separating-axis test with reference-face clipping (Catto, "Contact
// Manifolds", GDC 2007): the face of greatest separation is the
// reference, the most anti-parallel face of the other polygon is the incident edge, and the
// incident edge clipped to the reference face's side planes gives at most two points.
// Invariants: the normal points from A to B; points lie midway between the surfaces; every choice
// breaks ties by the lowest index, so the same input gives the same manifold bit for bit; the two
// points of a manifold carry distinct feature ids, and the same touching features give the same
// ids from one step to the next. Nothing here allocates.
#include "collision/collide.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace fx2d::detail {
namespace {

constexpr float linear_slop = 0.005f;  // metres: the overlap the solver tolerates at rest
// B becomes the reference only when its face separates clearly more than A's, so that two faces
// with nearly equal separation (a box at rest on a box) do not swap roles from step to step and
// change every feature id.
constexpr float reference_face_hysteresis = 0.1f * linear_slop;
// Two corners meeting (the apex of an A-frame of cards) give each polygon a face that separates
// the pair about equally, and neither is the face of the contact. Either face's normal leans by
// half the angle between the faces, so holding the corners would cost friction of the tangent of
// that lean. Within the hysteresis, where which face is the reference depends only on which shape
// is A, the manifold's single point takes the bisector of the two faces, which treats both bodies
// alike. (A tie as wide as a linear slop took settling_boxes 800 to 12.5 mm of penetration in
// 200 steps, against 3.3 mm with the face normal; this one leaves it at 3.3 mm.)
constexpr float corner_tie_tolerance = reference_face_hysteresis;

// Feature id of a polygon-polygon point: which polygon holds the reference face, the reference
// edge, and the incident vertex whose clipped or unclipped image the point is. A point clipped
// off at a side plane keeps its vertex's id: it moves continuously into that vertex as the
// vertex slides back inside, so carrying its impulse across is right.
constexpr std::uint32_t polygon_feature_id(bool reference_is_b, int reference_edge, int incident_vertex) {
  return (reference_is_b ? 1u << 16 : 0u) | std::uint32_t(reference_edge) << 8 |
         std::uint32_t(incident_vertex);
}

// A circle contact has a single point that moves continuously over the polygon's boundary, so one
// id serves every feature and the impulse carries over as the circle rolls past a vertex.
constexpr std::uint32_t circle_feature_id = 0;

// A polygon's vertices and normals in one frame: A's as the shape stores them, or B's placed in A's
// frame on the caller's stack.
struct PolygonView {
  const FxVec2f* vertices;
  const FxVec2f* normals;
  int count;
};

// A polygon's vertices and normals placed in another's frame, on the caller's stack. The arrays
// are left uninitialised (an empty union constructor): every entry below `count` is written before
// it is read, and zeroing them was a 128-byte `rep stos` on every collision of two polygons.
struct PlacedPolygon {
  union Points {
    Points() {}
    FxVec2f at[FxShape::max_vertices];
  };
  Points vertices, normals;
  int count = 0;
  PolygonView view() const { return {vertices.at, normals.at, count}; }
};

struct FaceSeparation {
  int edge = 0;
  float separation = 0.0f;
};

// How far `other` lies beyond the face with `normal` through `origin`: its deepest vertex's distance.
// Measured, not kept: every vertex at once, from the polygons' coordinates copied into two lanes of
// eight (the last vertex repeated; the same bits, as the least value does not depend on the order
// of comparison). `ab` against this loop, sleeping off, 8 rounds: a pile of 600 octagons ran 0.915
// of the instructions in 1.011 of the time, and a rain of 600 triangles, pentagons and hexagons
// took 1.25 times as long to collide (step 1.087): the copies cost what the lanes save.
float separation_along(FxVec2f normal, FxVec2f origin, const PolygonView& other) {
  float deepest = std::numeric_limits<float>::max();
  for (int j = 0; j < other.count; ++j) {
    const float s = dot(normal, other.vertices[j] - origin);
    if (s < deepest) deepest = s;
  }
  return deepest;
}

// The face of greatest separation among `count` faces, each measured by `separation_of`; or the
// first face that separates the pair by `apart` or more, since the pair is then apart whichever
// separates most. Ties go to the lowest index.
template <typename SeparationOf>
FaceSeparation max_face_separation(int count, float apart, SeparationOf separation_of) {
  FaceSeparation best{0, -std::numeric_limits<float>::max()};
  for (int i = 0; i < count; ++i) {
    const float deepest = separation_of(i);
    if (deepest >= apart) return {i, deepest};
    if (deepest > best.separation) best = {i, deepest};
  }
  return best;
}

// A centred box (FxShape::centred_box) in its own frame has corners (+-hx, +-hy) and unit axes
// for normals, and the closed forms below give, bit for bit, the least value the vertex loops of
// separation_along find: rounding is monotonic, so each rounded term of a dot product grows or
// shrinks with its own coordinate, and so does their rounded sum.
struct Bounds {
  FxVec2f lower, upper;
};

// GCC cannot see that a placed polygon (PlacedPolygon, whose storage starts uninitialised) has
// its first vertex written: every polygon has three or more, all placed before this reads them.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
Bounds bounds_of(const PolygonView& polygon) {
  Bounds bounds{polygon.vertices[0], polygon.vertices[0]};
  for (int i = 1; i < polygon.count; ++i) {
    const FxVec2f v = polygon.vertices[i];
    bounds.lower = {std::min(bounds.lower.x, v.x), std::min(bounds.lower.y, v.y)};
    bounds.upper = {std::max(bounds.upper.x, v.x), std::max(bounds.upper.y, v.y)};
  }
  return bounds;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// How far a polygon within `other` lies beyond the box's face with `normal` through `origin`. The
// normal's zero component adds a zero, so the deepest vertex is the one least far along the axis,
// and its coordinate less the face's is the loop's least difference.
float separation_beyond_box_face(FxVec2f normal, FxVec2f origin, const Bounds& other) {
  if (normal.x > 0.0f) return other.lower.x - origin.x;
  if (normal.x < 0.0f) return origin.x - other.upper.x;
  if (normal.y > 0.0f) return other.lower.y - origin.y;
  return origin.y - other.upper.y;
}

// How far a box with half extents `half` lies beyond the face with `normal` through `origin`. Its
// corners pair either x with either y, so its deepest corner takes from each pair the end the
// normal points away from (either, where the normal's component is zero).
float separation_of_box(FxVec2f normal, FxVec2f origin, FxVec2f half) {
  const FxVec2f deepest{normal.x > 0.0f ? -half.x : half.x, normal.y > 0.0f ? -half.y : half.y};
  return dot(normal, deepest - origin);
}

// How far B (placed in A's frame) lies beyond A's face `face`: from B's bounds when A is a centred
// box, else by the vertex loop.
template <bool a_is_box>
class SeparationOfB {
 public:
  SeparationOfB(const PolygonView& a, const PolygonView& b) : a_(a), b_(b) {
    if constexpr (a_is_box) b_bounds_ = bounds_of(b);
  }
  float operator()(int face) const {
    if constexpr (a_is_box) return separation_beyond_box_face(a_.normals[face], a_.vertices[face], b_bounds_);
    return separation_along(a_.normals[face], a_.vertices[face], b_);
  }

 private:
  const PolygonView& a_;
  const PolygonView& b_;
  Bounds b_bounds_;
};

// How far A lies beyond a face of B with `normal` through `origin` (in A's frame): from one corner
// when A is a centred box, else by the vertex loop.
template <bool a_is_box>
class SeparationOfA {
 public:
  explicit SeparationOfA(const PolygonView& a)
      : a_(a), half_{std::abs(a.vertices[0].x), std::abs(a.vertices[0].y)} {}
  float operator()(FxVec2f normal, FxVec2f origin) const {
    if constexpr (a_is_box) return separation_of_box(normal, origin, half_);
    return separation_along(normal, origin, a_);
  }

 private:
  const PolygonView& a_;
  FxVec2f half_;
};

// Where the face searches leave a polygon pair: apart along a face (its owner not none), or each
// polygon's face of greatest separation.
struct FaceSearchResult {
  SeparatingFace apart;
  FaceSeparation a, b;
};

// True when `face` of polygon b (placed in a's frame by `b_in_a`) still holds a apart by `apart`:
// the very arithmetic the face search does for that face, on that face's vertex and normal alone.
template <bool a_is_box>
bool b_face_separates(const PolygonView& poly_a, const FxShape& b, const FxTransform& b_in_a, int face, float apart) {
  const SeparationOfA<a_is_box> separation_of_a(poly_a);
  return separation_of_a(rotate(b_in_a.q, b.normals()[face]), transform_point(b_in_a, b.vertices()[face])) >= apart;
}

// The face searches of collide_polygons, in A's frame, after B's face tried first (if any) has not
// parted the pair. Any face that separates the pair by `apart` ends them, and A's face tried first
// is tried before the others. B's vertices and normals, placed in A's frame, are written to
// `placed_b`: B's normals only once A's faces have not separated the two, as they do for most pairs
// the broad phase finds. Instantiated for a centred box A, whose loops are closed forms, and for any A.
template <bool a_is_box>
FaceSearchResult search_faces(const PolygonView& poly_a, const FxShape& b, const FxTransform& b_in_a,
                              SeparatingFace first_try, float apart, PlacedPolygon& placed_b) {
  const PolygonView poly_b = placed_b.view();
  using Owner = SeparatingFace::Owner;
  const SeparationOfA<a_is_box> separation_of_a(poly_a);
  for (int i = 0; i < poly_b.count; ++i) placed_b.vertices.at[i] = transform_point(b_in_a, b.vertices()[i]);
  const SeparationOfB<a_is_box> separation_of_b(poly_a, poly_b);
  if (first_try.owner == Owner::a && separation_of_b(first_try.edge) >= apart) return {first_try, {}, {}};
  const int count_a = a_is_box ? 4 : poly_a.count;  // a box's four, known here: the loop unrolls
  const FaceSeparation face_a = max_face_separation(count_a, apart, separation_of_b);
  for (int i = 0; i < poly_b.count; ++i) placed_b.normals.at[i] = rotate(b_in_a.q, b.normals()[i]);
  const FaceSeparation face_b = max_face_separation(poly_b.count, apart, [&](int i) {
    return separation_of_a(poly_b.normals[i], poly_b.vertices[i]);
  });
  // Of two faces that part the pair, B's is named: trying it first places one of B's vertices, not all.
  if (!(face_b.separation < apart)) return {{Owner::b, std::uint8_t(face_b.edge)}, face_a, face_b};
  if (!(face_a.separation < apart)) return {{Owner::a, std::uint8_t(face_a.edge)}, face_a, face_b};
  return {{}, face_a, face_b};
}

// The edge of `polygon` whose normal is most anti-parallel to `normal`.
int incident_edge(const PolygonView& polygon, FxVec2f normal) {
  int best = 0;
  float lowest = dot(normal, polygon.normals[0]);
  for (int i = 1; i < polygon.count; ++i) {
    const float d = dot(normal, polygon.normals[i]);
    if (d < lowest) {
      lowest = d;
      best = i;
    }
  }
  return best;
}

struct ClipVertex {
  FxVec2f point;
  int vertex = 0;
};

// Keeps the part of segment [a, b] where dot(direction, p - origin) >= 0. Returns false when
// nothing is left. A clipped end keeps the vertex index of the end it replaces.
bool clip_to_side_plane(ClipVertex& a, ClipVertex& b, FxVec2f direction, FxVec2f origin) {
  const float da = dot(direction, a.point - origin);
  const float db = dot(direction, b.point - origin);
  if (da < 0.0f && db < 0.0f) return false;
  if (da < 0.0f) a.point = lerp(a.point, b.point, da / (da - db));
  if (db < 0.0f) b.point = lerp(b.point, a.point, db / (db - da));
  return true;
}

// True when two corners meet: the reference face and the incident polygon's best separating face
// separate the pair equally and face each other. A single point there takes the bisector of the two
// faces as its normal, else the reference face's. An edge on a face gives two points and a corner
// well inside a face gives no tie, so both keep the face normal bit for bit.
bool corners_meet(FxVec2f reference_normal, FxVec2f incident_face_normal, float separation_difference) {
  return std::abs(separation_difference) <= corner_tie_tolerance && dot(reference_normal, incident_face_normal) < 0.0f;
}

void add_point(Manifold& out, FxVec2f point, float separation, std::uint32_t id) {
  ManifoldPoint& p = out.points[out.point_count++];
  p.point = point;
  p.separation = separation;
  p.id = id;
}

}  // namespace

void collide_circles(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
                     float speculative_distance, Manifold& out) {
  out = Manifold{};
  const FxVec2f center_a = transform_point(xf_a, a.centroid());
  const FxVec2f center_b = transform_point(xf_b, b.centroid());
  const float center_distance = distance(center_a, center_b);
  const float separation = center_distance - a.radius() - b.radius();
  if (!(separation < speculative_distance)) return;
  // Concentric circles have no preferred direction; a fixed one keeps the result deterministic.
  out.normal =
      center_distance > 0.0f ? (1.0f / center_distance) * (center_b - center_a) : FxVec2f{0.0f, 1.0f};
  const FxVec2f surface_a = center_a + a.radius() * out.normal;
  const FxVec2f surface_b = center_b - b.radius() * out.normal;
  add_point(out, lerp(surface_a, surface_b, 0.5f), separation, circle_feature_id);
}

void collide_polygon_circle(const FxShape& a, const FxTransform& xf_a, const FxShape& b,
                            const FxTransform& xf_b, float speculative_distance, Manifold& out) {
  out = Manifold{};
  // Work in A's frame, where A's vertices and normals need no transforming.
  const FxVec2f center = inv_transform_point(xf_a, transform_point(xf_b, b.centroid()));
  const float radius = b.radius();
  const auto vertices = a.vertices();
  const auto normals = a.normals();
  const int count = a.vertex_count();

  // For a centre outside the polygon the face of greatest separation holds the closest point; for
  // a centre inside it is the face of least penetration.
  int face = 0;
  float face_separation = -std::numeric_limits<float>::max();
  for (int i = 0; i < count; ++i) {
    const float s = dot(normals[i], center - vertices[i]);
    if (s > face_separation) {
      face_separation = s;
      face = i;
    }
  }
  if (!(face_separation - radius < speculative_distance)) return;

  const FxVec2f v1 = vertices[face];
  const FxVec2f v2 = vertices[(face + 1) % count];
  FxVec2f normal = normals[face];
  FxVec2f surface_a = center - face_separation * normal;
  float center_distance = face_separation;
  // A face's normal turns with the polygon; a vertex's points at the circle's centre, wherever that goes.
  NormalFrame frame = NormalFrame::body_a;
  if (face_separation > 0.0f) {
    // Outside: the closest point is a vertex when the centre lies beyond either end of the face.
    const bool beyond_v1 = dot(center - v1, v2 - v1) < 0.0f;
    const bool beyond_v2 = dot(center - v2, v1 - v2) < 0.0f;
    if (beyond_v1 || beyond_v2) {
      surface_a = beyond_v1 ? v1 : v2;
      center_distance = distance(surface_a, center);
      normal = (1.0f / center_distance) * (center - surface_a);
      frame = NormalFrame::world;
    }
  }
  const float separation = center_distance - radius;
  if (!(separation < speculative_distance)) return;
  out.normal = rotate(xf_a.q, normal);
  out.normal_frame = frame;
  const FxVec2f surface_b = center - radius * normal;
  add_point(out, transform_point(xf_a, lerp(surface_a, surface_b, 0.5f)), separation, circle_feature_id);
}

void collide_polygons(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
                      float speculative_distance, SeparatingFace first_try, Manifold& out, FaceSearch search) {
  out = Manifold{};
  // Work in A's frame: A's vertices and normals as stored, B's placed relative to it.
  const FxTransform b_in_a = inv_mul(xf_a, xf_b);
  const PolygonView poly_a{a.vertices().data(), a.normals().data(), a.vertex_count()};
  const bool a_is_box = search == FaceSearch::closed_form_for_boxes && a.centred_box();
  // Any face that separates the pair by the speculative distance ends the search with no points,
  // so the face that did so last time is tried first: B's before B is placed in A's frame.
  if (first_try.owner == SeparatingFace::Owner::b &&
      (a_is_box ? b_face_separates<true>(poly_a, b, b_in_a, first_try.edge, speculative_distance)
                : b_face_separates<false>(poly_a, b, b_in_a, first_try.edge, speculative_distance))) {
    out.separating_face = first_try;
    return;
  }
  PlacedPolygon placed_b;
  placed_b.count = b.vertex_count();
  const PolygonView poly_b = placed_b.view();
  const FaceSearchResult faces =
      a_is_box ? search_faces<true>(poly_a, b, b_in_a, first_try, speculative_distance, placed_b)
               : search_faces<false>(poly_a, b, b_in_a, first_try, speculative_distance, placed_b);
  if (faces.apart.owner != SeparatingFace::Owner::none) {
    out.separating_face = faces.apart;
    return;
  }
  const FaceSeparation face_a = faces.a;
  const FaceSeparation face_b = faces.b;

  const bool reference_is_b = face_b.separation > face_a.separation + reference_face_hysteresis;
  const PolygonView& reference = reference_is_b ? poly_b : poly_a;
  const PolygonView& incident = reference_is_b ? poly_a : poly_b;
  const int reference_edge = reference_is_b ? face_b.edge : face_a.edge;

  const FxVec2f ref_start = reference.vertices[reference_edge];
  const FxVec2f ref_end = reference.vertices[(reference_edge + 1) % reference.count];
  const FxVec2f normal = reference.normals[reference_edge];
  // Counter-clockwise winding makes the edge direction the normal turned left.
  const FxVec2f tangent = left_perp(normal);

  const int edge = incident_edge(incident, normal);
  const int next = (edge + 1) % incident.count;
  ClipVertex clip[2] = {{incident.vertices[edge], edge}, {incident.vertices[next], next}};
  if (!clip_to_side_plane(clip[0], clip[1], tangent, ref_start)) return;
  if (!clip_to_side_plane(clip[0], clip[1], -tangent, ref_end)) return;

  // An end beyond the speculative distance is kept, speculative, while the other end is within it:
  // a body struck or set turning within the step swings that end about the near one faster than its
  // motion at the step's start foretells (narrow_phase.cpp). Not where two corners meet: the far end
  // of that edge is no feature of the contact.
  const FxVec2f incident_face_normal = incident.normals[reference_is_b ? face_a.edge : face_b.edge];
  const bool corner_tie = corners_meet(normal, incident_face_normal, face_a.separation - face_b.separation);
  const float separations[2] = {dot(normal, clip[0].point - ref_start), dot(normal, clip[1].point - ref_start)};
  const bool whole_edge =
      !corner_tie && (separations[0] < speculative_distance || separations[1] < speculative_distance);
  for (int i = 0; i < 2; ++i) {
    if (!(separations[i] < speculative_distance) && !whole_edge) continue;
    const FxVec2f midway = clip[i].point - (0.5f * separations[i]) * normal;
    add_point(out, transform_point(xf_a, midway), separations[i],
              polygon_feature_id(reference_is_b, reference_edge, clip[i].vertex));
  }
  const FxVec2f contact_normal =
      out.point_count == 1 && corner_tie ? normalize(normal - incident_face_normal) : normal;
  out.normal = rotate(xf_a.q, reference_is_b ? -contact_normal : contact_normal);
  out.normal_frame = reference_is_b ? NormalFrame::body_b : NormalFrame::body_a;
}

void collide(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b,
             float speculative_distance, SeparatingFace first_try, Manifold& out) {
  const bool a_is_circle = a.type() == FxShapeType::circle;
  const bool b_is_circle = b.type() == FxShapeType::circle;
  if (a_is_circle && b_is_circle) {
    collide_circles(a, xf_a, b, xf_b, speculative_distance, out);
  } else if (b_is_circle) {
    collide_polygon_circle(a, xf_a, b, xf_b, speculative_distance, out);
  } else if (a_is_circle) {
    // Points lie midway and separations are symmetric, so only the normal changes sides.
    collide_polygon_circle(b, xf_b, a, xf_a, speculative_distance, out);
    out.normal = -out.normal;
    if (out.normal_frame == NormalFrame::body_a) out.normal_frame = NormalFrame::body_b;
  } else {
    collide_polygons(a, xf_a, b, xf_b, speculative_distance, first_try, out);
  }
}

}  // namespace fx2d::detail

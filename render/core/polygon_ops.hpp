// Plane classification and splitting of convex polygons, shared by the BSP build and the painter's
// Newell mode. Fragments live in their own PolygonSoup that shares the source's materials and
// objects, so a fragment keeps its source's id, material, object, flags and plane exactly (the plane
// is copied, never recomputed from the cut vertices). Positions and shading normals of new vertices
// are interpolated along the cut edge.
#pragma once

#include "render/core/cancel.hpp"
#include "render/core/tessellate.hpp"

#include <span>
#include <vector>

namespace rr {

struct Plane {
  Vec3 normal{0.0, 1.0, 0.0};  // unit
  double offset = 0.0;         // points p on the plane have dot(normal, p) == offset
  double distance(Vec3 p) const { return glm::dot(normal, p) - offset; }
};

inline Plane plane_of(const Polygon& p) { return {p.normal, p.offset}; }

// Where a polygon lies relative to a plane, with every vertex within `epsilon` of the plane taken
// as on it: `on` (all vertices), `front`/`back` (the rest on one side), or `spanning`.
enum class PlaneSide { front, back, on, spanning };
PlaneSide classify_polygon(std::span<const Vec3> points, const Plane& plane, double epsilon);

// An empty soup sharing `source`'s materials and objects, to hold fragments of its polygons.
PolygonSoup make_fragment_soup(const PolygonSoup& source);

// Appends a copy of `polygon` (whose vertices are in `from`) to `to`; returns its index in `to`.
// `from` and `to` may be the same soup.
uint32_t append_polygon(PolygonSoup& to, const PolygonSoup& from, const Polygon& polygon);

struct SplitResult {
  int64_t front = -1;  // index in the output soup of the part in front of the plane, or -1
  int64_t back = -1;
};

// Splits a convex polygon that spans `plane` into its front and back parts, appended to `out` (which
// may be `from`). Vertices within `epsilon` of the plane belong to both parts; a part left with
// fewer than 3 vertices (or zero area) is dropped. Both parts are convex and keep the source's
// attributes. Used only for polygons classify_polygon called `spanning`.
SplitResult split_polygon(const PolygonSoup& from, const Polygon& polygon, const Plane& plane, double epsilon,
                          PolygonSoup& out);

// Closes the T-junctions between fragments of one source polygon (same id): a fragment split again
// gets a vertex on the seam that its sibling across the seam lacks, and the rasterizer would snap
// the two sides of the seam differently, leaving pixel-wide cracks. Every vertex of a sibling that
// lies on an edge's interior (within `epsilon` of it) is inserted into that edge, copied bit for
// bit, so both sides of every seam have the same vertices. Polygons stay in order and convex (the
// inserted vertices are on their edges); a polygon with no sibling is untouched.
void close_t_junctions(PolygonSoup& fragments, double epsilon, const CancelToken* cancel = nullptr);

}  // namespace rr

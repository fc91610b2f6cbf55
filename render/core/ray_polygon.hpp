// A ray against one convex polygon of a soup, in doubles (world space): the exact test of the
// reference's rays and of the pipelines' shadow rays, so that both decide a ray the same way.
#pragma once

#include "render/core/math.hpp"
#include "render/core/tessellate.hpp"

#include <optional>

namespace rr {

// Where origin + t * direction (t_min < t < t_max) meets the convex polygon, boundary included;
// nullopt when it misses or runs parallel to its plane. World space, doubles; used by the shadow
// rays (the reference's and shadow_rays.hpp's) and by tests comparing the BVH with a brute-force search.
std::optional<double> intersect_polygon(const PolygonSoup& soup, const Polygon& polygon, Vec3 origin, Vec3 direction,
                                        double t_min, double t_max);

// The two steps of intersect_polygon, for callers that keep a polygon in another layout (the shadow
// rays' packed casters): the same arithmetic in the same order, so the same answers bit for bit.

// Where the ray meets the plane n . x = offset within (t_min, t_max); nullopt when it misses or runs
// parallel to it.
inline std::optional<double> ray_plane_t(Vec3 normal, double offset, Vec3 origin, Vec3 direction, double t_min,
                                         double t_max) {
  const double denom = glm::dot(normal, direction);
  if (denom == 0.0) return std::nullopt;
  const double t = (offset - glm::dot(normal, origin)) / denom;
  if (!(t > t_min && t < t_max)) return std::nullopt;
  return t;
}

// The plane a polygon's inside is tested in: the normal's largest component dropped, the other two
// axes (u, v) kept, and the sign of the dropped one (the polygon winds counter-clockwise about its
// normal, so every edge cross product has that sign).
struct InsideAxes {
  int u = 0, v = 0;
  double sign = 1.0;
};
inline InsideAxes inside_axes(Vec3 normal) {
  const Vec3 a = glm::abs(normal);
  const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return {drop == 2 ? 0 : drop + 1, drop == 0 ? 2 : drop - 1, normal[drop] >= 0.0 ? 1.0 : -1.0};
}

// Whether (pu, pv) lies inside or on the polygon whose `count` vertices, on the kept axes, vertex(k)
// gives: edges (s, e) in order, the last one closing back to the first vertex. No vertices: inside.
template <class Vertex>
bool inside_projected(double pu, double pv, double sign, size_t count, Vertex&& vertex) {
  if (count == 0) return true;
  glm::dvec2 s = vertex(count - 1);
  for (size_t k = 0; k < count; ++k) {
    const glm::dvec2 e = vertex(k);
    const double cross = (e.x - s.x) * (pv - s.y) - (e.y - s.y) * (pu - s.x);
    if (sign * cross < 0.0) return false;
    s = e;
  }
  return true;
}

}  // namespace rr

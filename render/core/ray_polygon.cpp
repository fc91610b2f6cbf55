// intersect_polygon (see ray_polygon.hpp).
#include "render/core/ray_polygon.hpp"

namespace rr {

std::optional<double> intersect_polygon(const PolygonSoup& soup, const Polygon& polygon, Vec3 origin, Vec3 direction,
                                        double t_min, double t_max) {
  const double denom = glm::dot(polygon.normal, direction);
  if (denom == 0.0) return std::nullopt;
  const double t = (polygon.offset - glm::dot(polygon.normal, origin)) / denom;
  if (!(t > t_min && t < t_max)) return std::nullopt;
  const Vec3 p = origin + t * direction;
  // Inside test in the plane with the largest normal component dropped; the polygon winds
  // counter-clockwise about its normal, so every edge cross product has the sign of that component.
  const Vec3 a = glm::abs(polygon.normal);
  const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int u = drop == 2 ? 0 : drop + 1, v = drop == 0 ? 2 : drop - 1;
  const double sign = polygon.normal[drop] >= 0.0 ? 1.0 : -1.0;
  const auto points = soup.points(polygon);
  if (points.empty()) return t;
  // Edges (s, e) in order, the last one closing back to the first vertex (no index wraps).
  const Vec3* s = &points.back();
  for (const Vec3& e : points) {
    const double cross = (e[u] - (*s)[u]) * (p[v] - (*s)[v]) - (e[v] - (*s)[v]) * (p[u] - (*s)[u]);
    if (sign * cross < 0.0) return std::nullopt;
    s = &e;
  }
  return t;
}

}  // namespace rr

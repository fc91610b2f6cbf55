// intersect_polygon (see ray_polygon.hpp).
#include "render/core/ray_polygon.hpp"

namespace rr {

std::optional<double> intersect_polygon(const PolygonSoup& soup, const Polygon& polygon, Vec3 origin, Vec3 direction,
                                        double t_min, double t_max) {
  const std::optional<double> t = ray_plane_t(polygon.normal, polygon.offset, origin, direction, t_min, t_max);
  if (!t) return std::nullopt;
  const Vec3 p = origin + *t * direction;
  const InsideAxes axes = inside_axes(polygon.normal);
  const auto points = soup.points(polygon);
  const bool inside = inside_projected(p[axes.u], p[axes.v], axes.sign, points.size(),
                                       [&](size_t k) { return glm::dvec2(points[k][axes.u], points[k][axes.v]); });
  if (!inside) return std::nullopt;
  return t;
}

}  // namespace rr

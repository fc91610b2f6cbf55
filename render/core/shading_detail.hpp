// Internal to the shading (shading.cpp, shading_pixel.cpp); nothing else includes it.
#pragma once

#include "render/core/shading.hpp"

#include <algorithm>
#include <limits>
#include <span>

namespace rr::shading_detail {

inline glm::dvec3 ambient_irradiance(const Scene& scene) {
  return glm::dvec3(scene.ambient.color) * double(scene.ambient.intensity);
}

// Weights of p (in the plane of the convex polygon `points`) over the fan triangle (0, j, j + 1)
// that holds it, the triangulation the rasterizer draws; a point just outside by rounding takes
// the triangle it is least outside of.
struct FanPoint {
  size_t j = 1;
  double w[3] = {1.0, 0.0, 0.0};
};

inline FanPoint locate_in_fan(std::span<const Vec3> points, Vec3 normal, Vec3 p) {
  const Vec3 a = glm::abs(normal);
  const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  auto flat = [&](Vec3 q) { return Vec2(q[u] - points[0][u], q[v] - points[0][v]); };
  auto cross = [](Vec2 x, Vec2 y) { return x.x * y.y - x.y * y.x; };
  const Vec2 x = flat(p);
  FanPoint best;
  double best_min = -std::numeric_limits<double>::infinity();
  for (size_t j = 1; j + 1 < points.size(); ++j) {
    const Vec2 b = flat(points[j]), c = flat(points[j + 1]);
    const double area = cross(b, c);
    if (area == 0.0) continue;
    const double w1 = cross(x, c) / area, w2 = cross(b, x) / area, w0 = 1.0 - w1 - w2;
    const double worst = std::min({w0, w1, w2});
    if (worst > best_min) best_min = worst, best = {j, {w0, w1, w2}};
    if (worst >= 0.0) break;
  }
  return best;
}

}  // namespace rr::shading_detail

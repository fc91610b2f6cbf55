// Header-only: hand-built polygon soups (no tessellator involved) and seeded random ones, for the
// BVH, reference and stress tests. Each polygon is its own open object with material 0 unless
// flags say otherwise; the normal follows the winding (counter-clockwise seen from the front).
#pragma once

#include "render/core/tessellate.hpp"

#include <cstdlib>
#include <random>
#include <vector>

namespace rr::testing {

inline void add_polygon(PolygonSoup& soup, const std::vector<Vec3>& points, uint32_t flags = 0, uint32_t material = 0) {
  if (soup.materials.empty()) soup.materials.push_back({});
  Polygon p;
  p.first_vertex = uint32_t(soup.positions.size());
  p.vertex_count = uint32_t(points.size());
  p.id = uint32_t(soup.polygons.size());
  p.object = uint32_t(soup.objects.size());
  p.material = material;
  p.flags = flags;
  p.normal = glm::normalize(glm::cross(points[1] - points[0], points[2] - points[0]));
  p.offset = glm::dot(p.normal, points[0]);
  for (const Vec3& x : points) {
    soup.positions.push_back(x);
    soup.normals.push_back(glm::vec3(p.normal));
  }
  soup.polygons.push_back(p);
  soup.objects.push_back({ElementRef::solid(soup.objects.size()), (flags & polygon_closed) != 0, false});
}

// `count` random triangles with corners in [-size, size]^3 (skipping near-degenerate ones).
inline PolygonSoup random_triangle_soup(std::mt19937& rng, size_t count, double size) {
  std::uniform_real_distribution<double> coord(-size, size), edge(-0.3 * size, 0.3 * size);
  PolygonSoup soup;
  while (soup.polygons.size() < count) {
    const Vec3 a(coord(rng), coord(rng), coord(rng));
    const Vec3 b = a + Vec3(edge(rng), edge(rng), edge(rng)), c = a + Vec3(edge(rng), edge(rng), edge(rng));
    if (glm::length(glm::cross(b - a, c - a)) < 1e-3 * size * size) continue;
    add_polygon(soup, {a, b, c});
  }
  return soup;
}

// The first seed of a seeded test and how many to run: ROOMRENDER_TEST_SEED replays one seed.
struct SeedRange {
  unsigned first;
  unsigned count;
};
inline SeedRange test_seeds(unsigned first, unsigned count) {
  if (const char* s = std::getenv("ROOMRENDER_TEST_SEED")) return {unsigned(std::strtoul(s, nullptr, 10)), 1};
  return {first, count};
}

}  // namespace rr::testing

// Plan geometry and face emission shared by the solids (solid_*.cpp): rotations in the plan, and
// one face of a solid as one convex polygon or, when it is not convex and planar, ear-clipped
// triangles. World space, metres, doubles; plan points are (x, z).
#include "render/core/tessellate_detail.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace rr::detail {

namespace {

// Convex test for a polygon of positive orientation: no right turn (collinear vertices allowed,
// within 1e-12 of the edge lengths) and one revolution in total (rejects star polygons).
bool is_convex_ccw(std::span<const Vec2> p) {
  const size_t n = p.size();
  double turning = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 e1 = p[i] - p[(i + n - 1) % n], e2 = p[(i + 1) % n] - p[i];
    const double c = cross2(e1, e2);
    if (c < -1e-12 * glm::length(e1) * glm::length(e2)) return false;
    turning += std::atan2(c, glm::dot(e1, e2));
  }
  return std::abs(turning - 2.0 * pi) < pi;
}

bool blocks_ear(Vec2 a, Vec2 b, Vec2 c, Vec2 p) {
  if (p == a || p == b || p == c) return false;  // a polygon touching itself at a vertex
  return cross2(b - a, p - a) >= 0.0 && cross2(c - b, p - b) >= 0.0 && cross2(a - c, p - c) >= 0.0;
}

// Ear clipping of a simple polygon of positive orientation; triangles index `p`. O(n^2) typical.
// A vertex between collinear neighbours is removed without a triangle (it would have no area).
// If rounding leaves no clean ear, the most convex vertex is clipped so the loop always ends.
std::vector<std::array<uint32_t, 3>> ear_clip(std::span<const Vec2> p) {
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<uint32_t> ring(p.size());
  for (uint32_t i = 0; i < ring.size(); ++i) ring[i] = i;
  while (ring.size() > 3) {
    const size_t m = ring.size();
    size_t chosen = m, best = 0;
    double best_turn = -1e300;
    for (size_t i = 0; i < m && chosen == m; ++i) {
      const Vec2 a = p[ring[(i + m - 1) % m]], b = p[ring[i]], c = p[ring[(i + 1) % m]];
      const double turn = cross2(b - a, c - b);
      if (turn > best_turn) best_turn = turn, best = i;
      if (turn <= 1e-12 * glm::length(b - a) * glm::length(c - b)) {
        if (glm::dot(b - a, c - b) > 0.0) chosen = i;  // collinear pass-through vertex
        continue;
      }
      bool ear = true;
      for (size_t j = 0; j < m && ear; ++j) ear = !blocks_ear(a, b, c, p[ring[j]]);
      if (ear) chosen = i;
    }
    if (chosen == m) chosen = best;
    const Vec2 a = p[ring[(chosen + m - 1) % m]], b = p[ring[chosen]], c = p[ring[(chosen + 1) % m]];
    if (std::abs(cross2(b - a, c - b)) > 0.0) {
      triangles.push_back({ring[(chosen + m - 1) % m], ring[chosen], ring[(chosen + 1) % m]});
    }
    ring.erase(ring.begin() + std::ptrdiff_t(chosen));
  }
  if (ring.size() == 3) triangles.push_back({ring[0], ring[1], ring[2]});
  return triangles;
}

// Coordinates of `points` in their plane (normal n), oriented so the polygon has positive area:
// drop the dominant axis of n and keep the other two in right-handed order.
std::vector<Vec2> project_to_plane(std::span<const Vec3> points, Vec3 n) {
  const Vec3 a = glm::abs(n);
  const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  const bool flip = n[drop] < 0.0;
  std::vector<Vec2> out;
  out.reserve(points.size());
  for (const Vec3& p : points) {
    const Vec3 q = p - points[0];
    out.push_back(flip ? Vec2(q[v], q[u]) : Vec2(q[u], q[v]));
  }
  return out;
}

}  // namespace

double cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

Vec2 rotate_plan(Vec2 xz, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * xz.x + s * xz.y, -s * xz.x + c * xz.y};
}

// Twice the signed area of a plan polygon in (x, z) coordinates.
double twice_signed_area(std::span<const Vec2> p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) a += cross2(p[i] - p[0], p[(i + 1) % p.size()] - p[0]);
  return a;
}

// Planar means within 1e-9 of the face's extent (the invariant of tessellate.hpp); a mesh face
// validated only to 1e-6 is split rather than silently flattened.
bool split_face(std::span<const Vec3> points, std::vector<std::array<uint32_t, 3>>& triangles) {
  triangles.clear();
  const Vec3 n = newell_vector(points);
  const double len = glm::length(n);
  if (points.size() < 3 || !(len > 0.0)) return false;
  const Vec3 unit = n / len;
  double extent = 0.0, off_plane = 0.0;
  for (const Vec3& p : points) {
    extent = std::max(extent, glm::length(p - points[0]));
    off_plane = std::max(off_plane, std::abs(glm::dot(unit, p - points[0])));
  }
  const std::vector<Vec2> flat = project_to_plane(points, unit);
  if (off_plane <= 1e-9 * extent && is_convex_ccw(flat)) return true;
  triangles = ear_clip(flat);
  return true;
}

void add_face_pieces(SoupBuilder& out, std::span<const Vec3> points, std::span<const glm::vec3> shading,
                     std::span<const std::array<uint32_t, 3>> triangles, Vec3 outward, uint32_t material,
                     uint32_t object, std::span<const glm::dvec2> uvs) {
  if (triangles.empty()) {
    out.add_polygon(points, outward, material, object, shading, uvs);
    return;
  }
  for (const auto& t : triangles) {
    const Vec3 tri[3] = {points[t[0]], points[t[1]], points[t[2]]};
    glm::vec3 tri_shading[3];
    glm::dvec2 tri_uvs[3];
    for (int c = 0; c < 3; ++c) {
      if (!shading.empty()) tri_shading[c] = shading[t[size_t(c)]];
      if (!uvs.empty()) tri_uvs[c] = uvs[t[size_t(c)]];
    }
    out.add_polygon(tri, outward, material, object, shading.empty() ? std::span<const glm::vec3>{} : tri_shading,
                    uvs.empty() ? std::span<const glm::dvec2>{} : tri_uvs);
  }
}

void add_face(SoupBuilder& out, std::span<const Vec3> points, std::span<const glm::vec3> shading, Vec3 outward,
              uint32_t material, uint32_t object) {
  std::vector<std::array<uint32_t, 3>> triangles;
  if (split_face(points, triangles)) add_face_pieces(out, points, shading, triangles, outward, material, object);
}

}  // namespace rr::detail

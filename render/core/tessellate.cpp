// Static geometry -> PolygonSoup: the polygon builder, the floor and the solids (walls live in
// tessellate_walls.cpp). World space, metres, doubles. Ids are indices, in the order of
// docs/scene-format.md "Polygon ids"; every polygon is convex, planar, CCW seen from its front.
#include "render/core/tessellate_detail.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace rr {
namespace detail {

Vec3 newell_vector(std::span<const Vec3> points) {
  Vec3 sum{0.0};
  if (points.size() < 3) return sum;
  const Vec3 origin = points[0];
  for (size_t i = 1; i + 1 < points.size(); ++i) {
    sum += glm::cross(points[i] - origin, points[i + 1] - origin);
  }
  return sum;
}

uint32_t SoupBuilder::add_object(ElementRef element, bool closed, bool smooth) {
  soup_.objects.push_back({element, closed, smooth});
  return uint32_t(soup_.objects.size() - 1);
}

uint32_t SoupBuilder::add_material(const Material& m) {
  const std::array<float, 9> key{m.color.r, m.color.g, m.color.b, m.opacity, m.params.specular,
                                 m.params.shininess, m.params.specular_color.r, m.params.specular_color.g,
                                 m.params.specular_color.b};
  auto [it, inserted] = material_index_.try_emplace(key, uint32_t(soup_.materials.size()));
  if (inserted) soup_.materials.push_back(m);
  return it->second;
}

bool SoupBuilder::add_polygon(std::span<const Vec3> points, Vec3 outward, uint32_t material,
                              uint32_t object, std::span<const glm::vec3> shading) {
  assert(shading.empty() || shading.size() == points.size());
  if (points.size() < 3) return false;
  // Merge tolerance: 1e-12 of the polygon's own extent (pieces computed as exactly zero-sized in
  // local coordinates), plus ~64 ulp of the coordinates' magnitude (the same pieces after the
  // mapping to a world position far from the origin).
  double extent = 0.0, magnitude = 0.0;
  for (const Vec3& p : points) {
    extent = std::max(extent, glm::length(p - points[0]));
    magnitude = std::max({magnitude, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  const double tol = 1e-12 * extent + 1e-14 * magnitude;
  points_.clear();
  shading_.clear();
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points_.empty() && glm::length(points[i] - points_.back()) <= tol) continue;
    points_.push_back(points[i]);
    if (!shading.empty()) shading_.push_back(shading[i]);
  }
  while (points_.size() >= 3 && glm::length(points_.front() - points_.back()) <= tol) {
    points_.pop_back();
    if (!shading_.empty()) shading_.pop_back();
  }
  if (points_.size() < 3) return false;
  Vec3 n = newell_vector(points_);
  const double twice_area = glm::length(n);
  // A polygon thinner than the merge tolerance is a sliver of rounding error, not geometry.
  if (!(twice_area > 2.0 * tol * extent)) return false;
  if (glm::dot(n, outward) < 0.0) {
    std::reverse(points_.begin(), points_.end());
    std::reverse(shading_.begin(), shading_.end());
    n = -n;
  }
  Polygon poly;
  poly.first_vertex = uint32_t(soup_.positions.size());
  poly.vertex_count = uint32_t(points_.size());
  poly.id = uint32_t(soup_.polygons.size());
  poly.material = material;
  poly.object = object;
  poly.normal = n / twice_area;
  poly.offset = 0.0;
  for (const Vec3& p : points_) poly.offset += glm::dot(poly.normal, p);
  poly.offset /= double(points_.size());
  if (soup_.objects[object].closed) poly.flags |= polygon_closed;
  if (soup_.materials[material].opacity < 1.0f) poly.flags |= polygon_translucent;
  soup_.positions.insert(soup_.positions.end(), points_.begin(), points_.end());
  if (shading_.empty()) {
    soup_.normals.insert(soup_.normals.end(), points_.size(), glm::vec3(poly.normal));
  } else {
    soup_.normals.insert(soup_.normals.end(), shading_.begin(), shading_.end());
  }
  soup_.polygons.push_back(poly);
  return true;
}

void add_cuboid(SoupBuilder& out, Vec3 c, Vec3 hx, Vec3 hy, Vec3 hz, uint32_t material,
                uint32_t object) {
  const Vec3 axes[3] = {hx, hy, hz};
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 a = axes[axis], b = axes[(axis + 1) % 3], d = axes[(axis + 2) % 3];
    for (double sign : {1.0, -1.0}) {
      const Vec3 f = c + sign * a;
      const Vec3 quad[4] = {f - b - d, f + b - d, f + b + d, f - b + d};
      out.add_polygon(quad, sign * a, material, object);
    }
  }
}

}  // namespace detail

namespace {

using detail::SoupBuilder;

double cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// rotation_y is counter-clockwise seen from above, i.e. right-handed about +Y: +X turns to -Z.
Vec2 rotate_plan(Vec2 xz, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * xz.x + s * xz.y, -s * xz.x + c * xz.y};
}

Vec3 plan_to_world(Vec2 xz, double y) { return {xz.x, y, xz.y}; }

Material solid_material(const Solid& s) { return {s.color, 1.0f, s.material}; }

// Twice the signed area of a plan polygon in (x, z) coordinates.
double twice_signed_area(std::span<const Vec2> p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) a += cross2(p[i] - p[0], p[(i + 1) % p.size()] - p[0]);
  return a;
}

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

// One face of a solid: a convex planar face stays one polygon; otherwise it is ear-clipped into
// triangles with consecutive ids. Planar means within 1e-9 of the face's extent (the invariant of
// tessellate.hpp); a mesh face validated only to 1e-6 is split rather than silently flattened.
void add_face(SoupBuilder& out, std::span<const Vec3> points, std::span<const glm::vec3> shading,
              Vec3 outward, uint32_t material, uint32_t object) {
  const Vec3 n = detail::newell_vector(points);
  const double len = glm::length(n);
  if (points.size() < 3 || !(len > 0.0)) return;
  const Vec3 unit = n / len;
  double extent = 0.0, off_plane = 0.0;
  for (const Vec3& p : points) {
    extent = std::max(extent, glm::length(p - points[0]));
    off_plane = std::max(off_plane, std::abs(glm::dot(unit, p - points[0])));
  }
  const std::vector<Vec2> flat = project_to_plane(points, unit);
  if (off_plane <= 1e-9 * extent && is_convex_ccw(flat)) {
    out.add_polygon(points, outward, material, object, shading);
    return;
  }
  for (const auto& t : ear_clip(flat)) {
    const Vec3 tri[3] = {points[t[0]], points[t[1]], points[t[2]]};
    if (shading.empty()) {
      out.add_polygon(tri, outward, material, object);
    } else {
      const glm::vec3 tri_shading[3] = {shading[t[0]], shading[t[1]], shading[t[2]]};
      out.add_polygon(tri, outward, material, object, tri_shading);
    }
  }
}

void add_floor(SoupBuilder& out, const Floor& f) {
  static const Color fallback[2] = {{0.851f, 0.831f, 0.780f}, {0.549f, 0.522f, 0.475f}};
  std::span<const Color> colors = f.colors;
  if (colors.empty()) colors = fallback;  // the documented default; the parser normally fills it
  std::vector<uint32_t> materials;
  for (const Color& c : colors) materials.push_back(out.add_material({c, 1.0f, f.material}));
  const uint32_t object = out.add_object(ElementRef::floor(), false, false);
  for (int j = 0; j < f.cells_z; ++j) {
    for (int i = 0; i < f.cells_x; ++i) {
      // Corners from the cell index, not accumulated, so neighbouring cells share exact edges.
      const double x0 = f.origin.x + i * f.cell_size, x1 = f.origin.x + (i + 1) * f.cell_size;
      const double z0 = f.origin.y + j * f.cell_size, z1 = f.origin.y + (j + 1) * f.cell_size;
      const Vec3 quad[4] = {{x0, f.elevation, z0}, {x0, f.elevation, z1}, {x1, f.elevation, z1},
                            {x1, f.elevation, z0}};
      out.add_polygon(quad, {0.0, 1.0, 0.0}, materials[size_t(i + j) % materials.size()], object);
    }
  }
}

// Faces +X, -X, +Y (top), -Y (bottom), +Z, -Z of the box's own (unrotated) frame.
void add_box(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const double a = radians(s.rotation_y_deg);
  const Vec2 x = rotate_plan({1.0, 0.0}, a), z = rotate_plan({0.0, 1.0}, a);
  detail::add_cuboid(out, {s.center.x, s.base + 0.5 * s.size.y, s.center.y},
                     plan_to_world(x, 0.0) * (0.5 * s.size.x), {0.0, 0.5 * s.size.y, 0.0},
                     plan_to_world(z, 0.0) * (0.5 * s.size.z), material, object);
}

// Triangles on the +X, -X, +Z, -Z sides of the pyramid's own frame, then the base quad.
void add_pyramid(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const double a = radians(s.rotation_y_deg);
  const auto corner = [&](double sx, double sz) {
    return plan_to_world(s.center + rotate_plan({sx * 0.5 * s.size.x, sz * 0.5 * s.size.z}, a), s.base);
  };
  const Vec3 apex{s.center.x, s.base + s.size.y, s.center.y};
  const Vec3 side_x = plan_to_world(rotate_plan({1.0, 0.0}, a), 0.0);
  const Vec3 side_z = plan_to_world(rotate_plan({0.0, 1.0}, a), 0.0);
  const Vec3 faces[4][3] = {{corner(1, -1), corner(1, 1), apex}, {corner(-1, 1), corner(-1, -1), apex},
                            {corner(1, 1), corner(-1, 1), apex}, {corner(-1, -1), corner(1, -1), apex}};
  const Vec3 outward[4] = {side_x, -side_x, side_z, -side_z};
  for (int i = 0; i < 4; ++i) out.add_polygon(faces[i], outward[i], material, object);
  const Vec3 base[4] = {corner(1, -1), corner(1, 1), corner(-1, 1), corner(-1, -1)};
  out.add_polygon(base, {0.0, -1.0, 0.0}, material, object);
}

// Side quads (segment k spans angles k and k+1, counter-clockwise from the rotated +X seen from
// above), then the top cap, then the bottom cap.
void add_cylinder(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const int n = std::max(3, s.segments);
  const double top = s.base + s.height, a0 = radians(s.rotation_y_deg);
  const auto radial = [&](double k) {
    const double phi = a0 + 2.0 * pi * k / n;
    return Vec3(std::cos(phi), 0.0, -std::sin(phi));
  };
  std::vector<Vec3> bottom_ring, top_ring;
  for (int k = 0; k < n; ++k) {
    const Vec3 p = Vec3(s.center.x, 0.0, s.center.y) + s.radius * radial(k);
    bottom_ring.push_back({p.x, s.base, p.z});
    top_ring.push_back({p.x, top, p.z});
  }
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    const Vec3 quad[4] = {bottom_ring[k], bottom_ring[k1], top_ring[k1], top_ring[k]};
    const glm::vec3 smooth[4] = {glm::vec3(radial(k)), glm::vec3(radial(k + 1)), glm::vec3(radial(k + 1)),
                                 glm::vec3(radial(k))};
    out.add_polygon(quad, radial(k + 0.5), material, object,
                    s.smooth ? std::span<const glm::vec3>(smooth) : std::span<const glm::vec3>());
  }
  if (!s.caps) return;
  out.add_polygon(top_ring, {0.0, 1.0, 0.0}, material, object);
  out.add_polygon(bottom_ring, {0.0, -1.0, 0.0}, material, object);
}

// Side quads (edge i runs from points[i] to points[i+1]), then the top cap, then the bottom cap.
// rotation_y turns the prism about the area centroid of its footprint (the prism has no centre).
void add_prism(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  std::vector<Vec2> plan;
  for (const Vec2& p : s.points) {
    if (plan.empty() || p != plan.back()) plan.push_back(p);
  }
  while (plan.size() > 1 && plan.front() == plan.back()) plan.pop_back();
  if (plan.size() < 3) return;
  const double area2 = twice_signed_area(plan);
  if (s.rotation_y_deg != 0.0 && area2 != 0.0) {
    Vec2 centroid{0.0};
    for (size_t i = 0; i < plan.size(); ++i) {
      const Vec2 p = plan[i] - plan[0], q = plan[(i + 1) % plan.size()] - plan[0];
      centroid += (p + q) * cross2(p, q);
    }
    centroid = plan[0] + centroid / (3.0 * area2);
    for (Vec2& p : plan) p = centroid + rotate_plan(p - centroid, radians(s.rotation_y_deg));
  }
  // In (x, z) a negative signed area is counter-clockwise seen from above; outward is then to the
  // right of each edge. Either input orientation is accepted.
  const double right = area2 < 0.0 ? 1.0 : -1.0;
  const double top = s.base + s.height;
  const size_t n = plan.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = plan[i], b = plan[(i + 1) % n], e = b - a;
    const Vec3 quad[4] = {plan_to_world(a, s.base), plan_to_world(b, s.base), plan_to_world(b, top),
                          plan_to_world(a, top)};
    out.add_polygon(quad, right * Vec3(-e.y, 0.0, e.x), material, object);
  }
  std::vector<Vec3> cap(n);
  for (double y : {top, s.base}) {
    for (size_t i = 0; i < n; ++i) cap[i] = plan_to_world(plan[i], y);
    add_face(out, cap, {}, {0.0, y == top ? 1.0 : -1.0, 0.0}, material, object);
  }
}

// A mesh's given normal in world space: the inverse transpose of scale, then rotation_y.
glm::vec3 mesh_normal_to_world(const Solid& s, Vec3 n, double angle_rad) {
  const Vec3 scaled = n / s.scale;
  const Vec2 xz = rotate_plan({scaled.x, scaled.z}, angle_rad);
  return glm::vec3(glm::normalize(Vec3(xz.x, scaled.y, xz.y)));
}

// One polygon per face (triangles for non-convex faces). Object space -> world: scale, then
// rotate_y, then translate. A mirroring scale would turn faces inside out, so it reverses them.
void add_mesh(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const double a = radians(s.rotation_y_deg);
  std::vector<Vec3> world(s.vertices.size());
  for (size_t i = 0; i < world.size(); ++i) {
    const Vec3 scaled = s.vertices[i] * s.scale;
    const Vec2 xz = rotate_plan({scaled.x, scaled.z}, a);
    world[i] = s.position + Vec3(xz.x, scaled.y, xz.y);
  }
  const bool mirrored = s.scale.x * s.scale.y * s.scale.z < 0.0;
  std::vector<std::vector<Vec3>> faces(s.faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    for (uint32_t v : s.faces[f]) faces[f].push_back(world[v]);
    if (mirrored) std::reverse(faces[f].begin(), faces[f].end());
  }
  // Smooth: each vertex averages the Newell vectors (2 * area * normal) of the faces using it.
  std::vector<Vec3> vertex_sum(s.smooth ? world.size() : 0, Vec3(0.0));
  if (s.smooth) {
    for (size_t f = 0; f < faces.size(); ++f) {
      const Vec3 n = detail::newell_vector(faces[f]);
      for (uint32_t v : s.faces[f]) vertex_sum[v] += n;
    }
  }
  std::vector<glm::vec3> shading;
  for (size_t f = 0; f < faces.size(); ++f) {
    const Vec3 n = detail::newell_vector(faces[f]);
    shading.clear();
    if (!s.normals.empty()) {
      std::vector<uint32_t> ids = s.faces[f];
      if (mirrored) std::reverse(ids.begin(), ids.end());
      for (uint32_t v : ids) shading.push_back(mesh_normal_to_world(s, s.normals[v], a));
    } else if (s.smooth) {
      std::vector<uint32_t> ids = s.faces[f];
      if (mirrored) std::reverse(ids.begin(), ids.end());
      for (uint32_t v : ids) {
        const double len = glm::length(vertex_sum[v]);
        shading.push_back(glm::vec3(len > 0.0 ? vertex_sum[v] / len : glm::normalize(n)));
      }
    }
    if (glm::length(n) > 0.0) add_face(out, faces[f], shading, n, material, object);
  }
}

void add_solid(SoupBuilder& out, const Solid& s, size_t index) {
  const bool closed = s.type == SolidType::cylinder ? s.caps
                      : s.type == SolidType::mesh   ? s.closed
                                                    : true;
  const bool smooth = (s.type == SolidType::cylinder || s.type == SolidType::mesh) &&
                      (s.smooth || !s.normals.empty());
  const uint32_t object = out.add_object(ElementRef::solid(index), closed, smooth);
  const uint32_t material = out.add_material(solid_material(s));
  switch (s.type) {
    case SolidType::box: add_box(out, s, material, object); break;
    case SolidType::cylinder: add_cylinder(out, s, material, object); break;
    case SolidType::pyramid: add_pyramid(out, s, material, object); break;
    case SolidType::prism: add_prism(out, s, material, object); break;
    case SolidType::mesh: add_mesh(out, s, material, object); break;
  }
}

size_t estimate_solid_polygons(const Solid& s) {
  switch (s.type) {
    case SolidType::box: return 6;
    case SolidType::pyramid: return 5;
    case SolidType::cylinder: return size_t(std::max(3, s.segments)) + 2;
    case SolidType::prism: {
      const size_t n = s.points.size();  // n sides, each cap at most n - 2 triangles
      return n + 2 * (n > 2 ? n - 2 : 1);
    }
    case SolidType::mesh: {
      size_t count = 0;  // a face of k vertices becomes at most k - 2 triangles
      for (const auto& f : s.faces) count += f.size() > 2 ? f.size() - 2 : 1;
      return count;
    }
  }
  return 0;
}

}  // namespace

PolygonSoup tessellate(const StaticGeometry& geometry) {
  SoupBuilder out;
  if (geometry.has_floor) add_floor(out, geometry.floor);
  detail::add_walls(out, geometry.walls);
  for (size_t i = 0; i < geometry.solids.size(); ++i) add_solid(out, geometry.solids[i], i);
  return out.take();
}

size_t estimate_polygon_count(const StaticGeometry& geometry) {
  size_t count = 0;
  if (geometry.has_floor) {
    count += size_t(std::max(0, geometry.floor.cells_x)) * size_t(std::max(0, geometry.floor.cells_z));
  }
  for (const Wall& w : geometry.walls) count += detail::estimate_wall_polygons(w);
  for (const Solid& s : geometry.solids) count += estimate_solid_polygons(s);
  return count;
}

double polygon_area(std::span<const Vec3> points) {
  return 0.5 * glm::length(detail::newell_vector(points));
}

}  // namespace rr

// Static geometry -> PolygonSoup: the polygon builder, the floor and the solids (walls live in
// tessellate_walls.cpp, each solid type's faces in its solid_<name>.cpp). World space, metres, doubles. Ids are
// indices, in the order of docs/scene-format.md "Polygon ids"; every polygon is convex, planar, CCW seen from its
// front.
#include "render/core/coplanar.hpp"
#include "render/core/hash.hpp"
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

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

namespace {

// A hash of the members that usually differ; equality (Material's operator==) decides.
uint64_t material_hash(const Material& m) {
  Fnv1a h;
  for (float v : {m.color.r, m.color.g, m.color.b, m.opacity, m.params.specular}) h.add_u64(std::bit_cast<uint32_t>(v));
  h.add_u64(uint64_t(reinterpret_cast<uintptr_t>(m.texture.get())));
  return h.value();
}

// The affine map that gives the three points their coordinates, within their plane.
UvMap uv_map_through(const Vec3 p[3], const glm::dvec2 uv[3]) {
  const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  const double a = glm::dot(e1, e1), b = glm::dot(e1, e2), c = glm::dot(e2, e2);
  const double det = a * c - b * b;
  UvMap m;
  if (!(det > 0.0)) return m;
  auto axis = [&](double d1, double d2) {
    const double x = (c * d1 - b * d2) / det, y = (a * d2 - b * d1) / det;
    return x * e1 + y * e2;
  };
  m.u_axis = axis(uv[1].x - uv[0].x, uv[2].x - uv[0].x);
  m.v_axis = axis(uv[1].y - uv[0].y, uv[2].y - uv[0].y);
  m.u0 = uv[0].x - glm::dot(m.u_axis, p[0]);
  m.v0 = uv[0].y - glm::dot(m.v_axis, p[0]);
  return m;
}

// Per-vertex coordinates of a planar polygon: the map through its fan triangle of largest area
// (exact for a triangle; a polygon whose coordinates are not affine over it takes that triangle's).
UvMap uv_map_of(std::span<const Vec3> points, std::span<const glm::dvec2> uvs) {
  size_t best = 1;
  double best_area = -1.0;
  for (size_t j = 1; j + 1 < points.size(); ++j) {
    const double area = glm::length(glm::cross(points[j] - points[0], points[j + 1] - points[0]));
    if (area > best_area) best_area = area, best = j;
  }
  const Vec3 p[3] = {points[0], points[best], points[best + 1]};
  const glm::dvec2 uv[3] = {uvs[0], uvs[best], uvs[best + 1]};
  return uv_map_through(p, uv);
}

}  // namespace

UvMap planar_uv_map(const SurfaceTexture& texture, Vec3 n, const UvFrame& frame) {
  const Vec2 n_plan = rotate_plan({n.x, n.z}, -frame.rotation_y_rad);
  const Vec3 local(n_plan.x, n.y, n_plan.y);
  Vec3 s_axis{1.0, 0.0, 0.0}, t_axis{0.0, 0.0, -1.0};
  const double across = std::hypot(local.x, local.z);
  if (across > 1e-6) {  // not horizontal: right of the viewer facing it, and up the face
    s_axis = Vec3(local.z, 0.0, -local.x) / across;
    t_axis = glm::cross(local, s_axis);
  }
  auto to_world = [&](Vec3 v) {
    const Vec2 xz = rotate_plan({v.x, v.z}, frame.rotation_y_rad);
    return Vec3(xz.x, v.y, xz.y);
  };
  const double c = std::cos(texture.angle), s = std::sin(texture.angle);
  UvMap m;
  m.u_axis = to_world(c * s_axis + s * t_axis) / texture.width;
  m.v_axis = to_world(c * t_axis - s * s_axis) / texture.height;
  m.u0 = -texture.x_offset - glm::dot(m.u_axis, frame.origin);
  m.v0 = -texture.y_offset - glm::dot(m.v_axis, frame.origin);
  return m;
}

uint32_t SoupBuilder::add_material(const Material& m) {
  const uint64_t key = material_hash(m);
  for (auto [it, end] = material_index_.equal_range(key); it != end; ++it) {
    if (soup_.materials[it->second] == m) return it->second;
  }
  const uint32_t index = uint32_t(soup_.materials.size());
  soup_.materials.push_back(m);
  material_index_.emplace(key, index);
  return index;
}

bool SoupBuilder::add_polygon(std::span<const Vec3> points, Vec3 outward, uint32_t material, uint32_t object,
                              std::span<const glm::vec3> shading, std::span<const glm::dvec2> uvs) {
  assert(shading.empty() || shading.size() == points.size());
  assert(uvs.empty() || uvs.size() == points.size());
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
  uvs_.clear();
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points_.empty() && glm::length(points[i] - points_.back()) <= tol) continue;
    points_.push_back(points[i]);
    if (!shading.empty()) shading_.push_back(shading[i]);
    if (!uvs.empty()) uvs_.push_back(uvs[i]);
  }
  while (points_.size() >= 3 && glm::length(points_.front() - points_.back()) <= tol) {
    points_.pop_back();
    if (!shading_.empty()) shading_.pop_back();
    if (!uvs_.empty()) uvs_.pop_back();
  }
  if (points_.size() < 3) return false;
  Vec3 n = newell_vector(points_);
  const double twice_area = glm::length(n);
  // A polygon thinner than the merge tolerance is a sliver of rounding error, not geometry.
  if (!(twice_area > 2.0 * tol * extent)) return false;
  if (glm::dot(n, outward) < 0.0) {
    std::reverse(points_.begin(), points_.end());
    std::reverse(shading_.begin(), shading_.end());
    std::reverse(uvs_.begin(), uvs_.end());
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
  if (const SurfaceTexture* texture = soup_.materials[material].texture.get()) {
    soup_.uv_maps.push_back(uvs_.empty() ? planar_uv_map(*texture, poly.normal, uv_frame_) : uv_map_of(points_, uvs_));
    poly.uv_map = uint32_t(soup_.uv_maps.size());
  }
  soup_.positions.insert(soup_.positions.end(), points_.begin(), points_.end());
  if (shading_.empty()) {
    soup_.normals.insert(soup_.normals.end(), points_.size(), glm::vec3(poly.normal));
  } else {
    soup_.normals.insert(soup_.normals.end(), shading_.begin(), shading_.end());
  }
  soup_.polygons.push_back(poly);
  return true;
}

void add_cuboid(SoupBuilder& out, Vec3 c, Vec3 hx, Vec3 hy, Vec3 hz, uint32_t material, uint32_t object) {
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

Material solid_material(const Solid& s) { return {s.color, 1.0f, s.material, s.texture}; }

void add_floor(SoupBuilder& out, const Floor& f) {
  static const Color fallback[2] = {{0.851f, 0.831f, 0.780f}, {0.549f, 0.522f, 0.475f}};
  std::span<const Color> colors = f.colors;
  if (colors.empty()) colors = fallback;  // the documented default; the parser normally fills it
  std::vector<uint32_t> materials;
  for (const Color& c : colors) materials.push_back(out.add_material({c, 1.0f, f.material, f.texture}));
  const uint32_t object = out.add_object(ElementRef::floor(), false, false);
  for (int j = 0; j < f.cells_z; ++j) {
    for (int i = 0; i < f.cells_x; ++i) {
      // Corners from the cell index, not accumulated, so neighbouring cells share exact edges.
      const double x0 = f.origin.x + i * f.cell_size, x1 = f.origin.x + (i + 1) * f.cell_size;
      const double z0 = f.origin.y + j * f.cell_size, z1 = f.origin.y + (j + 1) * f.cell_size;
      const Vec3 quad[4] = {{x0, f.elevation, z0}, {x0, f.elevation, z1}, {x1, f.elevation, z1}, {x1, f.elevation, z0}};
      out.add_polygon(quad, {0.0, 1.0, 0.0}, materials[size_t(i + j) % materials.size()], object);
    }
  }
}

void add_solid(SoupBuilder& out, const Solid& s, size_t index) {
  const SolidInfo& type = solid_table().row(s.type);
  const bool closed = type.closed(s);
  const bool smooth = type.smooth(s);
  const uint32_t object = out.add_object(ElementRef::solid(index), closed, smooth);
  const uint32_t material = out.add_material(solid_material(s));
  // A solid's textures are mapped in its own space: meshes from their position, the others from
  // the centre of their footprint at their base.
  out.set_uv_frame(
      {s.type == SolidType::mesh ? s.position : Vec3(s.center.x, s.base, s.center.y), radians(s.rotation_y_deg)});
  type.add(out, s, material, object);
  out.set_uv_frame({});
}

// Each object takes its element's level, so a view can select polygons by level.
void tag_levels(PolygonSoup& soup, const StaticGeometry& g) {
  for (SceneObject& o : soup.objects) {
    const ElementRef& e = o.element;
    switch (e.kind) {
      case ElementKind::scene:
        break;
      case ElementKind::floor:
        o.level = g.floor.level;
        break;
      case ElementKind::wall:
      case ElementKind::opening:
        o.level = g.walls[e.index].level;
        break;
      case ElementKind::solid:
        o.level = g.solids[e.index].level;
        break;
      case ElementKind::room:
        o.level = g.rooms[e.index].level;
        break;
    }
  }
}

}  // namespace

PolygonSoup tessellate(const StaticGeometry& geometry) {
  SoupBuilder out;
  if (geometry.has_floor) add_floor(out, geometry.floor);
  detail::add_walls(out, geometry.walls);
  for (size_t i = 0; i < geometry.solids.size(); ++i) add_solid(out, geometry.solids[i], i);
  detail::add_rooms(out, geometry.rooms, geometry.walls);
  PolygonSoup soup = out.take();
  assign_plane_groups(soup);
  if (!geometry.levels.empty()) tag_levels(soup, geometry);
  return soup;
}

size_t soup_bytes(const PolygonSoup& soup) {
  return soup.positions.capacity() * sizeof(Vec3) + soup.normals.capacity() * sizeof(glm::vec3) +
         soup.polygons.capacity() * sizeof(Polygon) + soup.materials.capacity() * sizeof(Material) +
         soup.objects.capacity() * sizeof(SceneObject) + soup.uv_maps.capacity() * sizeof(UvMap);
}

void bound_objects(PolygonSoup& soup) {
  const Vec3 inf(std::numeric_limits<double>::infinity());
  for (SceneObject& o : soup.objects) o.bounded = true, o.lo = inf, o.hi = -inf;
  for (const Polygon& p : soup.polygons) {
    SceneObject& o = soup.objects[p.object];
    for (const Vec3& q : soup.points(p)) o.lo = glm::min(o.lo, q), o.hi = glm::max(o.hi, q);
  }
}

size_t estimate_polygon_count(const StaticGeometry& geometry) {
  size_t count = 0;
  if (geometry.has_floor) {
    count += size_t(std::max(0, geometry.floor.cells_x)) * size_t(std::max(0, geometry.floor.cells_z));
  }
  for (const Wall& w : geometry.walls) count += detail::estimate_wall_polygons(w);
  for (const Solid& s : geometry.solids) count += solid_table().row(s.type).estimate(s);
  for (const Room& r : geometry.rooms) count += detail::estimate_room_polygons(r);
  return count;
}

int polygon_part(const PolygonSoup& soup, uint32_t id) {
  const std::vector<uint32_t>& first = soup.objects[soup.polygons[id].object].part_first_polygon;
  auto it = std::upper_bound(first.begin(), first.end(), id);
  return it == first.begin() ? -1 : int(it - first.begin()) - 1;
}

double polygon_area(std::span<const Vec3> points) { return 0.5 * glm::length(detail::newell_vector(points)); }

}  // namespace rr

// Static geometry (world space) -> planar convex polygons with outward normals, counter-clockwise
// winding seen from the front, a stable id (= index, order in docs/scene-format.md) and a material.
// Storage is flat (one vertex array, polygons index into it) so a million triangles cost no
// per-polygon allocation. Invariants: every polygon has >= 3 vertices, is convex and planar within
// 1e-9 of the scene size, and its `normal` is unit length with dot(normal, p) == offset on its plane.
#pragma once

#include "render/core/element.hpp"
#include "render/core/scene.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace rr {

// A surface's appearance: one owner for everything that decides its colour. Equal materials (by
// every member; a texture by identity) are one entry of PolygonSoup::materials.
struct Material {
  Color color{0.7f, 0.7f, 0.7f};  // multiplies the texel when textured
  float opacity = 1.0f;           // < 1: drawn translucent, after the opaque polygons
  MaterialParams params;
  // The image and its planar mapping; the texture coordinates of each polygon are its UvMap
  // (PolygonSoup::uv_maps), made from this mapping or from a mesh's per-vertex coordinates.
  std::shared_ptr<const SurfaceTexture> texture = nullptr;
  friend bool operator==(const Material&, const Material&) = default;
};

// Texture coordinates as an affine function of the world position on a polygon's plane:
// (u, v) = (dot(u_axis, p) + u0, dot(v_axis, p) + v0), in tiles (texture.hpp). Exact under clipping
// and splitting: a fragment keeps its source's map.
struct UvMap {
  Vec3 u_axis{0.0}, v_axis{0.0};
  double u0 = 0.0, v0 = 0.0;
  glm::dvec2 at(Vec3 p) const { return {glm::dot(u_axis, p) + u0, glm::dot(v_axis, p) + v0}; }
  glm::dvec2 along(Vec3 d) const { return {glm::dot(u_axis, d), glm::dot(v_axis, d)}; }  // a direction's change
};

// A scene element that polygons belong to (the floor, a wall, an opening's leaf or pane, a solid).
struct SceneObject {
  ElementRef element;    // the floor, a wall, an opening (leaf or pane) or a solid
  bool closed = false;   // faces bound a volume and wind outward: back faces can be skipped
  bool smooth = false;   // shading normals are averaged across faces
  int level = -1;        // its element's level (StaticGeometry::levels), -1: on none
  bool ceiling = false;  // a room's ceiling: a view may leave it out (RenderOptions::ceilings)
  // A piece: the id of the first polygon of each of its parts (parts emit their polygons in order,
  // so a polygon's part is the last one starting at or before its id). Empty for other elements.
  std::vector<uint32_t> part_first_polygon = {};
  // Axis-aligned bounds of its polygons, when `bounded`: bound_objects() fills them once a soup will
  // not change (prepare_scene), so a frame's object culling reads them instead of every vertex. A
  // soup made from another one's pieces keeps them: the pieces lie inside, so culling stays
  // conservative.
  bool bounded = false;
  Vec3 lo{0.0}, hi{0.0};
};

enum PolygonFlags : uint32_t {
  polygon_closed = 1u << 0,       // belongs to a closed object: invisible from behind its plane
  polygon_translucent = 1u << 1,  // its material's opacity < 1
};

struct Polygon {
  uint32_t first_vertex = 0;  // into PolygonSoup::positions / normals
  uint32_t vertex_count = 0;
  uint32_t id = 0;             // stable id; fragments made by clipping/splitting keep it
  uint32_t material = 0;       // into PolygonSoup::materials
  uint32_t object = 0;         // into PolygonSoup::objects
  uint32_t flags = 0;          // PolygonFlags
  uint32_t plane_group = 0;    // > 0: overlaps a polygon in its own plane (coplanar.hpp); 0: none
  uint32_t uv_map = 0;         // textured: 1 + its index in PolygonSoup::uv_maps; 0: untextured
  Vec3 normal{0.0, 1.0, 0.0};  // unit, outward
  double offset = 0.0;         // plane: dot(normal, p) == offset
};

struct PolygonSoup {
  std::vector<Vec3> positions;     // world space
  std::vector<glm::vec3> normals;  // per vertex shading normals (face normal when faceted)
  std::vector<Polygon> polygons;
  std::vector<Material> materials;
  std::vector<SceneObject> objects;
  std::vector<UvMap> uv_maps;  // of the textured polygons (Polygon::uv_map)

  std::span<const Vec3> points(const Polygon& p) const { return {positions.data() + p.first_vertex, p.vertex_count}; }
  std::span<const glm::vec3> vertex_normals(const Polygon& p) const {
    return {normals.data() + p.first_vertex, p.vertex_count};
  }
};

// The part of a piece that polygon `id` belongs to (an index into its Solid::parts), or -1 when its
// object is not a piece.
int polygon_part(const PolygonSoup& soup, uint32_t id);

// What the soup's arrays hold on the heap (their capacities), for cache budgets.
size_t soup_bytes(const PolygonSoup& soup);

// Fills every object's bounds from its polygons (an object with none gets lo > hi). Call it only on a
// soup whose points will not move again.
void bound_objects(PolygonSoup& soup);

// Tessellates validated geometry. Deterministic: the same input gives the same polygons and ids.
PolygonSoup tessellate(const StaticGeometry& geometry);

// An upper bound on tessellate(geometry).polygons.size(), computed without building anything, so
// the limit on polygon count is checked before memory is spent.
size_t estimate_polygon_count(const StaticGeometry& geometry);

// Area of a planar polygon (world units squared).
double polygon_area(std::span<const Vec3> points);

}  // namespace rr

// Internal to the tessellator (tessellate*.cpp, solid_*.cpp); nothing else includes it.
// Every element emits its faces through SoupBuilder, so orientation, degeneracy, ids and flags are
// decided in one place. World space, metres, doubles; emitted polygons obey tessellate.hpp.
#pragma once

#include "render/core/tessellate.hpp"

#include <array>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace rr::detail {

// Where a planar mapping measures from: `origin`, with the plan's axes turned by rotation_y (a
// solid's own space, so its texture turns and moves with it).
struct UvFrame {
  Vec3 origin{0.0};
  double rotation_y_rad = 0.0;
};

class SoupBuilder {
 public:
  uint32_t add_object(ElementRef element, bool closed, bool smooth);
  uint32_t add_material(const Material& material);  // equal materials share one index

  // Appends one convex planar polygon. Its winding is chosen so that the normal agrees with
  // `outward` (any vector on the outward side of the plane: builders need not track handedness).
  // Near-duplicate consecutive vertices are merged first; a polygon left without area is dropped
  // (returns false) and takes no id. `shading` is per vertex, or empty for the face normal. A
  // polygon of a textured material gets a UvMap: from `uvs` (per vertex) when given, else from the
  // texture's planar mapping (planar_uv_map).
  bool add_polygon(std::span<const Vec3> points, Vec3 outward, uint32_t material, uint32_t object,
                   std::span<const glm::vec3> shading = {}, std::span<const glm::dvec2> uvs = {});

  // The polygons added to `object` from now on belong to its next part (a piece's).
  void begin_part(uint32_t object) {
    soup_.objects[object].part_first_polygon.push_back(uint32_t(soup_.polygons.size()));
  }

  // Tags `object` as a room's ceiling: the views that leave ceilings out skip its polygons.
  void mark_ceiling(uint32_t object) { soup_.objects[object].ceiling = true; }

  bool textured(uint32_t material) const { return soup_.materials[material].texture != nullptr; }
  // The frame of the planar mappings of the polygons added from now on (the world's by default).
  void set_uv_frame(const UvFrame& frame) { uv_frame_ = frame; }

  PolygonSoup take() { return std::move(soup_); }

 private:
  PolygonSoup soup_;
  std::unordered_multimap<uint64_t, uint32_t> material_index_;  // material_hash -> index
  std::vector<Vec3> points_;  // scratch, reused so emitting allocates nothing per polygon
  std::vector<glm::vec3> shading_;
  std::vector<glm::dvec2> uvs_;
  UvFrame uv_frame_;
};

// The planar mapping of a texture on a polygon of unit normal n (docs/scene-format.md "Textures"),
// in `frame`: on a horizontal face s along +x and t along -z (the plan's up as Sweet Home 3D draws
// it); on any other face s to the right of someone facing it and t up the face. Then turned by the
// texture's angle, scaled to tiles and shifted by the offsets.
UvMap planar_uv_map(const SurfaceTexture& texture, Vec3 n, const UvFrame& frame);

// Twice the area times the unit normal of a closed polygon (Newell's method, taken about the first
// vertex so far-from-origin coordinates keep their precision). Right-hand rule: CCW -> toward viewer.
Vec3 newell_vector(std::span<const Vec3> points);

// The six faces of the cuboid centre ± half_x ± half_y ± half_z (any handedness), in the order
// +x, -x, +y, -y, +z, -z.
void add_cuboid(SoupBuilder& out, Vec3 centre, Vec3 half_x, Vec3 half_y, Vec3 half_z, uint32_t material,
                uint32_t object);

// Plan geometry (tessellate_faces.cpp). rotation_y is counter-clockwise seen from above, i.e.
// right-handed about +Y: +X turns to -Z.
double cross2(Vec2 a, Vec2 b);
Vec2 rotate_plan(Vec2 xz, double angle_rad);
inline Vec3 plan_to_world(Vec2 xz, double y) { return {xz.x, y, xz.y}; }
double twice_signed_area(std::span<const Vec2> p);  // of a plan polygon in (x, z)

// One face of a solid: a convex planar face stays one polygon; otherwise it is ear-clipped into
// triangles with consecutive ids (tessellate_faces.cpp). `shading` is per vertex, or empty.
void add_face(SoupBuilder& out, std::span<const Vec3> points, std::span<const glm::vec3> shading, Vec3 outward,
              uint32_t material, uint32_t object);

// add_face in two steps, so a mesh placed many times splits each face once (solid_mesh.cpp).
// split_face: false when the face has no area; else `triangles` is empty when the face stays one
// polygon, or holds its ear-clipped triangles (indices into `points`). The decision depends only on
// orientation and relative flatness, so it carries over to any placement of the face.
bool split_face(std::span<const Vec3> points, std::vector<std::array<uint32_t, 3>>& triangles);
void add_face_pieces(SoupBuilder& out, std::span<const Vec3> points, std::span<const glm::vec3> shading,
                     std::span<const std::array<uint32_t, 3>> triangles, Vec3 outward, uint32_t material,
                     uint32_t object, std::span<const glm::dvec2> uvs = {});

// Where a mesh's object space goes: p -> position + rotate_y(scale * (linear * p + offset)), the
// affine step only when `pre` is set (a piece's part in its unit box). `scale` may be negative on an
// axis (a mirrored piece): add_polygon winds each piece to agree with the transformed normal.
struct MeshPlacement {
  Vec3 position{0.0};
  double rotation_y_rad = 0.0;
  Vec3 scale{1.0};
  const PiecePart* pre = nullptr;  // its linear and offset
};

// Emits a mesh's faces placed by `place` (solid_mesh.cpp): the given normals, else the averaged ones
// when `smooth`, else faceted. The per-mesh work is planned once per MeshData and reused.
void add_placed_mesh(SoupBuilder& out, const MeshData& mesh, const MeshPlacement& place, bool smooth, uint32_t material,
                     uint32_t object);
// A face of k >= 3 vertices becomes at most k - 2 triangles.
size_t estimate_mesh_polygons(const MeshData& mesh);

// Walls with their joins, openings, door leaves and panes (tessellate_walls.cpp).
void add_walls(SoupBuilder& out, const std::vector<Wall>& walls);
size_t estimate_wall_polygons(const Wall& wall);

// Room floors and ceilings (tessellate_rooms.cpp).
void add_rooms(SoupBuilder& out, const std::vector<Room>& rooms, const std::vector<Wall>& walls);
size_t estimate_room_polygons(const Room& room);

}  // namespace rr::detail

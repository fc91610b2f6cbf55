// The canonical binary form that scene_id() hashes, in struct member order:
// - numbers (double, and float widened exactly to double) as their IEEE-754 bits, least significant
//   byte first, with -0.0 folded into 0.0; ints as 64-bit two's complement; bools as one byte;
// - a mesh as its content id (mesh_data.hpp), itself a hash of all of its geometry;
// - enums (opening and solid types) as their integer in scene.hpp's declaration order;
// - every vector prefixed by its length (64 bits), so [[1,2],[3]] and [[1],[2,3]] differ;
// - names (`id` members) left out: they label warnings but draw nothing; the floor only when present;
// - an optional member (a texture, a wall side's colour) only when present, after its name, so a
//   scene that uses none of them keeps the id it had before they existed; a texture as its image's
//   content id and its mapping.
// Every member of a solid is hashed, whatever its type reads: the parser leaves the members a type
// does not read at their defaults, so they cannot split one scene's id, and no member the tessellator
// reads can be forgotten. The structured bindings name every member, so a member added to one of
// these structs stops this file compiling until it is hashed here (or deliberately skipped).
#include "render/core/scene_id.hpp"

#include "render/core/hash.hpp"
#include "render/core/texture.hpp"

#include <bit>
#include <optional>
#include <string_view>
#include <vector>

namespace rr {

namespace {

void add(Fnv1a& h, double v) { h.add_u64(std::bit_cast<uint64_t>(v == 0.0 ? 0.0 : v)); }
void add(Fnv1a& h, float v) { add(h, double(v)); }
void add(Fnv1a& h, int v) { h.add_u64(uint64_t(int64_t(v))); }
void add(Fnv1a& h, bool v) { h.add_u8(v ? 1 : 0); }
void add(Fnv1a& h, OpeningType v) { h.add_u64(uint64_t(v)); }
void add(Fnv1a& h, SolidType v) { h.add_u64(uint64_t(v)); }
void add(Fnv1a& h, Vec2 v) {
  add(h, v.x);
  add(h, v.y);
}
void add(Fnv1a& h, Vec3 v) {
  add(h, v.x);
  add(h, v.y);
  add(h, v.z);
}
void add(Fnv1a& h, Color c) {
  add(h, c.r);
  add(h, c.g);
  add(h, c.b);
}
// A mesh by its content id, which hashes all of its geometry: a stored mesh placed by ref and the
// same mesh inline draw alike and share the id, and a different mesh behind a ref changes it.
void add(Fnv1a& h, const std::shared_ptr<const MeshData>& m) { h.add_bytes(m ? m->content_id : std::string(16, '-')); }
// An optional member: nothing when absent, else its name and its value.
void add(Fnv1a& h, std::string_view name, const std::optional<Color>& c) {
  if (!c) return;
  h.add_bytes(name);
  add(h, *c);
}
void add(Fnv1a& h, std::string_view name, const std::shared_ptr<const SurfaceTexture>& t) {
  if (!t) return;
  const auto& [image, decoded, width, height, x_offset, y_offset, angle] = *t;
  (void)image;  // names the image that `decoded` holds
  h.add_bytes(name);
  h.add_bytes(decoded ? decoded->content_id : std::string(16, '-'));
  add(h, width);
  add(h, height);
  add(h, x_offset);
  add(h, y_offset);
  add(h, angle);
}
void add(Fnv1a& h, const MaterialParams& m);
void add(Fnv1a& h, const Opening& o);
void add(Fnv1a& h, const Wall& w);
void add(Fnv1a& h, const PiecePart& p);
void add(Fnv1a& h, const Solid& s);
void add(Fnv1a& h, const Level& l);
void add(Fnv1a& h, const Room& r);

template <class T>
void add(Fnv1a& h, const std::vector<T>& items) {
  h.add_u64(items.size());
  for (const T& item : items) add(h, item);
}

void add(Fnv1a& h, const MaterialParams& m) {
  const auto& [specular, specular_color, shininess] = m;
  add(h, specular);
  add(h, specular_color);
  add(h, shininess);
}

void add(Fnv1a& h, const Floor& f) {
  const auto& [id, origin, cells_x, cells_z, cell_size, elevation, colors, material, texture, level] = f;
  (void)id;
  add(h, origin);
  add(h, cells_x);
  add(h, cells_z);
  add(h, cell_size);
  add(h, elevation);
  add(h, colors);
  add(h, material);
  add(h, "texture", texture);
  add(h, level);
}

void add(Fnv1a& h, const Opening& o) {
  const auto& [type, id, offset, width, height, sill, color, opacity, leaf] = o;
  (void)id;
  add(h, type);
  add(h, offset);
  add(h, width);
  add(h, height);
  add(h, sill);
  add(h, color);
  add(h, opacity);
  add(h, leaf);
}

void add(Fnv1a& h, const Wall& w) {
  const auto& [id, start, end, thickness, height, base, color, material, left_color, right_color, left_texture,
               right_texture, openings, level] = w;
  (void)id;
  add(h, start);
  add(h, end);
  add(h, thickness);
  add(h, height);
  add(h, base);
  add(h, color);
  add(h, material);
  add(h, "left color", left_color);
  add(h, "right color", right_color);
  add(h, "left texture", left_texture);
  add(h, "right texture", right_texture);
  add(h, openings);
  add(h, level);
}

void add(Fnv1a& h, const Mat3& m) {
  for (int col = 0; col < 3; ++col) add(h, m[col]);
}

void add(Fnv1a& h, const PiecePart& p) {
  const auto& [name, mesh, mesh_ref, color, material, texture, transformed, linear, offset] = p;
  (void)name;
  (void)mesh_ref;  // names the mesh that `mesh` holds
  add(h, mesh);
  add(h, color);
  add(h, material);
  add(h, "texture", texture);
  add(h, transformed);
  add(h, linear);
  add(h, offset);
}

void add(Fnv1a& h, const Solid& s) {
  const auto& [type, id, color, material, texture, center, base, rotation_y_deg, size, radius, height, segments, smooth,
               caps, points, mesh, mesh_ref, position, scale, closed, parts, mirrored, level] = s;
  (void)id;
  (void)mesh_ref;  // names the mesh that `mesh` holds
  add(h, type);
  add(h, color);
  add(h, material);
  add(h, "texture", texture);
  add(h, center);
  add(h, base);
  add(h, rotation_y_deg);
  add(h, size);
  add(h, radius);
  add(h, height);
  add(h, segments);
  add(h, smooth);
  add(h, caps);
  add(h, points);
  add(h, mesh);
  add(h, position);
  add(h, scale);
  add(h, closed);
  add(h, parts);
  add(h, mirrored);
  add(h, level);
}

// A level's id is hashed: requests select levels by it.
void add(Fnv1a& h, const Level& l) {
  const auto& [id, elevation, height, viewable] = l;
  h.add_u64(id.size());
  h.add_bytes(id);
  add(h, elevation);
  add(h, height);
  add(h, viewable);
}

void add(Fnv1a& h, const Room& r) {
  const auto& [id, points, elevation, floor, floor_color, floor_material, floor_texture, ceiling, ceiling_height,
               ceiling_color, ceiling_texture, level] = r;
  (void)id;
  add(h, points);
  add(h, elevation);
  add(h, floor);
  add(h, floor_color);
  add(h, floor_material);
  add(h, "floor texture", floor_texture);
  add(h, ceiling);
  add(h, ceiling_height);
  add(h, ceiling_color);
  add(h, "ceiling texture", ceiling_texture);
  add(h, level);
}

}  // namespace

std::string scene_id(const StaticGeometry& geometry) {
  const auto& [has_floor, floor, walls, solids, rooms, levels] = geometry;
  Fnv1a h;
  h.add_bytes("roomrender static geometry 2");  // names this encoding; changed when it changes
  add(h, has_floor);
  if (has_floor) add(h, floor);
  add(h, walls);
  add(h, solids);
  // Appended only when present, so the id of a scene without rooms or levels is unchanged.
  if (!rooms.empty() || !levels.empty()) {
    h.add_bytes("rooms and levels");
    add(h, rooms);
    add(h, levels);
  }
  return hex64(h.value());
}

}  // namespace rr

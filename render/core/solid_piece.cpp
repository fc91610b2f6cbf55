// Solid type "piece": a piece of furniture made of parts, each a mesh with its own colour and
// material, all under one transform. The parts fill the unit box [-0.5, 0.5]^3 (each placed there
// by its own affine map, or as it is); the piece stretches that box to `size`, mirrors it across
// its width axis when asked, turns it by rotation_y and stands it on `base` at `center`, as a box is
// placed. One object of the soup, so culling, picking and the placement checks see one body; each
// part's polygons are a range of it (SceneObject::part_first_polygon). Never closed: a model's parts
// need not bound a volume.
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

namespace rr::detail {

namespace {

// `material` (the piece's own colour) is each part's default, which the reader has applied already.
void add_piece(SoupBuilder& out, const Solid& s, uint32_t, uint32_t object) {
  MeshPlacement place;
  place.position = {s.center.x, s.base + 0.5 * s.size.y, s.center.y};
  place.rotation_y_rad = radians(s.rotation_y_deg);
  place.scale = s.size * Vec3(s.mirrored ? -1.0 : 1.0, 1.0, 1.0);
  for (const PiecePart& part : s.parts) {
    out.begin_part(object);
    place.pre = part.transformed ? &part : nullptr;
    const uint32_t material = out.add_material({part.color, 1.0f, part.material, part.texture});
    add_placed_mesh(out, *part.mesh, place, false, material, object);
  }
}

size_t estimate_piece(const Solid& s) {
  size_t count = 0;
  for (const PiecePart& part : s.parts) count += estimate_mesh_polygons(*part.mesh);
  return count;
}

}  // namespace

extern const SolidInfo piece_solid = {SolidType::piece,
                                      "piece",
                                      add_piece,
                                      estimate_piece,
                                      [](const Solid&) { return false; },
                                      [](const Solid& s) {
                                        for (const PiecePart& part : s.parts) {
                                          if (!part.mesh->normals.empty()) return true;
                                        }
                                        return false;
                                      }};

}  // namespace rr::detail

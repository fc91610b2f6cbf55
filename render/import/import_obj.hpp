// Internals of the OBJ importer that the Sweet Home 3D importer reuses for furniture models: the
// parsed file (positions, normals, faces by group) and one group -> a repaired mesh solid whose
// vertices the caller has already placed (file units for a plain OBJ, world metres for furniture).
#pragma once

#include "render/core/scene.hpp"
#include "render/import/import_common.hpp"

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace rr::import_detail {

constexpr uint32_t no_normal = UINT32_MAX;
constexpr size_t max_faces = 2'000'000;  // the request's polygon limit: more could never render

struct Corner {
  uint32_t v = 0;
  uint32_t vn = no_normal;
};

struct Face {
  uint32_t first_corner = 0;
  uint32_t corner_count = 0;
};

struct Group {
  std::string name;
  std::string material;
  std::vector<Face> faces;
};

struct ObjData {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  size_t texcoords = 0;
  std::vector<Corner> corners;
  std::vector<Group> groups;
  std::vector<std::string> libraries;
};

// Throws InputError naming the line of a bad number, index or face.
ObjData parse_obj(std::string_view text);

// A material of a .mtl file as we draw it: Kd as the colour; Ks as the specular strength (its
// largest channel) and colour, Ns as the shininess (clamped to 1..128, as Java 3D does), when given.
struct MtlMaterial {
  Color diffuse{0.7f};
  MaterialParams params;
  bool specular = false;  // Ks or Ns was given: `params` holds them
};

// newmtl name -> material, from the text of one .mtl file (unknown lines are ignored; a material
// without Kd keeps the grey).
void parse_mtl(std::string_view text, std::map<std::string, MtlMaterial>& materials);

// Sweet Home 3D's default material library, which it resolves models' material names from when they
// have no .mtl of their own: catalogue/default-materials.mtl, compiled in (134 materials).
const std::map<std::string, MtlMaterial>& default_materials();
// That file's text (a source CMake generates from it: default_materials_mtl.cpp.in).
std::string_view default_materials_mtl();

// A material's "material" member ({specular, specular_color, shininess}), or null without specular.
nlohmann::json material_json(const MtlMaterial& material);

struct RepairCounts {
  size_t triangulated = 0;     // non-planar faces split into triangles
  size_t degenerate = 0;       // faces or triangles of zero area dropped
  size_t dropped_normals = 0;  // groups whose normals were incomplete or zero
};

// One group as a mesh solid {"type", "id", "color", "vertices", "faces"[, "normals"]}: vertices split
// per (position, normal) pair, faces repaired. `positions` and `normals` are obj's, already placed
// (normals need not be unit); `mirrored` placements reverse every face. Grows `box` by the vertices.
nlohmann::json group_mesh(const Group& g, const ObjData& obj, const std::vector<Vec3>& positions,
                          const std::vector<Vec3>& normals, bool mirrored, Color color, RepairCounts& repairs,
                          Box3& box);

void add_repair_warnings(const RepairCounts& repairs, std::vector<std::string>& warnings);

}  // namespace rr::import_detail

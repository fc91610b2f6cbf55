// Internals of the OBJ importer that the Sweet Home 3D importer reuses for furniture models: the
// parsed file (positions, normals, faces by group) and one group -> a repaired mesh solid whose
// vertices the caller has already placed (file units for a plain OBJ, world metres for furniture).
#pragma once

#include "render/core/scene.hpp"
#include "render/import/import_common.hpp"

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rr::import_detail {

constexpr uint32_t no_normal = UINT32_MAX;
constexpr uint32_t no_texcoord = UINT32_MAX;
constexpr size_t max_faces = 2'000'000;  // the request's polygon limit: more could never render

struct Corner {
  uint32_t v = 0;
  uint32_t vn = no_normal;
  uint32_t vt = no_texcoord;
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
  std::vector<Vec2> texcoords;  // vt: (u, v), v up as texture.hpp's (a w coordinate is ignored)
  std::vector<Corner> corners;
  std::vector<Group> groups;
  std::vector<std::string> libraries;
};

// Throws InputError naming the line of a bad number, index or face.
ObjData parse_obj(std::string_view text);

// A material of a .mtl file as we draw it: Kd as the colour; Ks as the specular strength (its
// largest channel) and colour, Ns as the shininess (clamped to 1..128, as Java 3D does), when given;
// map_Kd as the image the colour multiplies, its path relative to the .mtl file (options before it
// are skipped: the image is used as it is). map_d is noted only to warn that cut-outs are not drawn.
struct MtlMaterial {
  Color diffuse{0.7f};
  bool has_diffuse = false;  // Kd was given (a textured material without it is white)
  MaterialParams params;
  bool specular = false;     // Ks or Ns was given: `params` holds them
  std::string diffuse_map;   // map_Kd's path as written, "" without one
  std::string library_dir;   // the folder of the .mtl that defined the material ("" or ending in '/')
  bool map_options = false;  // map_Kd had -o, -s or -t, which are not applied
  bool alpha_map = false;    // map_d was given
};

// A material of one colour and nothing else.
inline MtlMaterial plain_material(Color diffuse) {
  MtlMaterial m;
  m.diffuse = diffuse;
  m.has_diffuse = true;
  return m;
}

// newmtl name -> material, from the text of one .mtl file (unknown lines are ignored; a material
// without Kd keeps the grey).
// `library_dir` is the folder of the .mtl, recorded in each material for its map_Kd path.
void parse_mtl(std::string_view text, std::map<std::string, MtlMaterial>& materials,
               const std::string& library_dir = "");

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
  size_t dropped_uvs = 0;      // textured groups with a face lacking texture coordinates
};

// One group as a mesh solid {"type", "id", "color", "vertices", "faces"[, "normals"][, "uvs"]}: vertices
// split per (position, normal) pair, faces repaired. `positions` and `normals` are obj's, already
// placed (normals need not be unit); `mirrored` placements reverse every face. Grows `box` by the
// vertices. With `want_uvs` (a textured group) and a vt on every corner, vertices split per (position,
// normal, vt) and carry "uvs"; without, the mesh is what it was before texture coordinates were read.
nlohmann::json group_mesh(const Group& g, const ObjData& obj, const std::vector<Vec3>& positions,
                          const std::vector<Vec3>& normals, bool mirrored, Color color, RepairCounts& repairs,
                          Box3& box, bool want_uvs = false);

// A data: URI of an image file's bytes ("data:image/png;base64,..."), or nullopt when they are not a
// PNG or JPEG (by their first bytes).
std::optional<std::string> image_data_uri(std::string_view bytes);

// The data: URI of an image file's bytes when a request can use it: at most texture_image_bytes_cap
// bytes, a PNG or JPEG whose header reads and is within the default TextureLimits (checked without
// decoding). Otherwise nullopt and *problem says why, to follow the file's name: "is neither a PNG
// nor a JPEG", "has N bytes, more than ...", "is refused: PNG header says 100000 x 100000 pixels; ...".
std::optional<std::string> usable_image_data_uri(std::string_view bytes, std::string* problem);

void add_repair_warnings(const RepairCounts& repairs, std::vector<std::string>& warnings);

}  // namespace rr::import_detail

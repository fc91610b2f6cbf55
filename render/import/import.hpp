// Importers: the text (or bytes) of a file made by another tool -> a complete render request
// ({"scene", "camera", "options"}) that parse_request accepts as is. Sweet Home 3D homes (Home.xml,
// or a zip holding one and its furniture models), R2V vector floor plans and Wavefront OBJ models (or
// a zip of one and its .mtl); docs/import.md gives every mapping. Errors are InputError whose pointer locates the
// problem in the *source* file
// ("/line/17", or "/home/wall/3" for the fourth <wall>) and whose message names it and its line.
// Pure functions: no file access here; companion files (an OBJ's .mtl) come through a callback.
#pragma once

#include "render/core/math.hpp"
#include "render/import/archive.hpp"
#include "render/scene_io/errors.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rr {

enum class ImportFormat { sweethome3d, r2v, obj };  // one row each in import_format_table()

struct ImportFormatInfo {
  ImportFormat format;
  const char* name;  // as given to --format and in URLs: "sh3d", "r2v", "obj"
  const char* summary;
  double default_scale;  // metres per file unit
};

std::span<const ImportFormatInfo> import_format_table();
const ImportFormatInfo* find_import_format(std::string_view name);
const ImportFormatInfo& import_format_info(ImportFormat format);

// The format of `bytes` from its content, falling back on the file name's extension (".xml"/".sh3d",
// ".txt", ".obj"); nullopt when neither tells.
std::optional<ImportFormat> detect_import_format(std::string_view bytes, std::string_view file_name = "");

struct ImportOptions {
  // Metres per file unit; 0 takes the format's default (Sweet Home 3D 0.01: cm; R2V 0.025: one image
  // pixel is 2.5 cm; OBJ 1). Must be finite and > 0 otherwise.
  double scale = 0.0;
  // Written into the request's "options"; the default camera's field of view is fitted to this aspect.
  int width = 640;
  int height = 480;
  // The text of a file the imported one refers to, by the name written in it (an OBJ's `mtllib`, a
  // Sweet Home 3D piece's `model`), or nullopt when it is not available. Null: none are read.
  std::function<std::optional<std::string>(const std::string& name)> read_companion;
  // Sweet Home 3D only: draw furniture with its OBJ model (through read_companion) where available,
  // instead of a box of the piece's size. Off by default: models multiply the polygon count ~50x.
  bool furniture_models = false;
  // Sweet Home 3D furniture models: leave each distinct mesh once in ImportResult::meshes and let the
  // solids name it by "ref" (for a caller that stores meshes), instead of inlining it in every solid.
  bool mesh_refs = false;
  // Limits on a zip (a .sh3d, a zip of an OBJ and its .mtl); see archive.hpp for the defaults.
  ArchiveLimits archive;
};

struct ImportResult {
  nlohmann::json request;             // {"scene", "camera", "options"}
  std::vector<std::string> warnings;  // what was repaired, approximated or skipped, one line each
  // With ImportOptions::mesh_refs: the meshes the scene's solids and pieces' parts place by "ref": key,
  // by key, each in the mesh solid's form {"vertices", "faces"[, "normals"]}. Empty otherwise.
  std::map<std::string, nlohmann::json> meshes;
};

// A furniture model as the parts of a piece, made as the Sweet Home 3D importer makes a piece's:
// the OBJ's positions turned by `model_rotation` (Sweet Home 3D's modelRotation: 9 numbers, a
// row-major 3x3 matrix; identity when empty), centred on their box and divided by its extent (the
// unit box a piece stretches to its size), one mesh per group with faces (faces repaired as for any
// OBJ), each coloured by the model's .mtl (read through options.read_companion), else Sweet Home
// 3D's default material library, else grey.
struct FurnitureModel {
  nlohmann::json parts;                          // [{"name", "ref": key, "color"[, "material"]}]
  std::map<std::string, nlohmann::json> meshes;  // by key: {"vertices", "faces"[, "normals"]}
  Vec3 extent{0.0};                              // of the turned model, in its file's units
  std::vector<std::string> warnings;             // what was repaired
};
// Throws InputError when the OBJ cannot be read or has nothing to draw.
FurnitureModel import_furniture_model(std::string_view obj_text, const std::string& name, const ImportOptions& options,
                                      std::string_view model_rotation = "");

// Calls `visit` on every object of `solids` that holds a mesh (inline or by "ref"): a mesh solid, and
// each part of a piece.
void for_each_mesh_holder(nlohmann::json& solids, const std::function<void(nlohmann::json&)>& visit);

// Puts each mesh of `result.meshes` into the solids (and pieces' parts) whose "ref" names it, and empties the map: the
// request then stands alone. A solid's placement (position, rotation_y, scale, colour) is kept.
void inline_mesh_refs(ImportResult& result);

// Imports one file. A Sweet Home 3D `bytes` may be Home.xml or a zip (import_archive); an OBJ may be
// OBJ text or a zip.
// Throws InputError: Kind::malformed when the file cannot be read as its format, Kind::invalid when
// it can but describes something we refuse (an opening wider than its wall, an out-of-range index),
// Kind::too_large past a limit.
ImportResult import_file_text(std::string_view bytes, ImportFormat format, const ImportOptions& options = {});

// The importers behind import_file_text, for callers that know the format.
ImportResult import_sweethome3d(std::string_view home_xml, const ImportOptions& options = {});
ImportResult import_r2v(std::string_view text, const ImportOptions& options = {});
ImportResult import_obj(std::string_view text, const ImportOptions& options = {});

// A zip: Sweet Home 3D (a .sh3d holding Home.xml and its models, or one top-level *.xml home and the
// models it names, e.g. under furniture/) or OBJ (one *.obj entry and the .mtl files it names). Its
// other entries are what options.read_companion reads: the name as written, else by base name
// (Archive::resolve). Errors inside an entry point at "/entry/<name>/..." (archive.hpp).
ImportResult import_archive(std::string_view zip_bytes, ImportFormat format, const ImportOptions& options = {});

}  // namespace rr

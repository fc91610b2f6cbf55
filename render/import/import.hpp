// Importers: the text (or bytes) of a file made by another tool -> a complete render request
// ({"scene", "camera", "options"}) that parse_request accepts as is. Sweet Home 3D homes (Home.xml,
// or a .sh3d zip holding one), R2V vector floor plans and Wavefront OBJ models; docs/import.md gives
// every mapping. Errors are InputError whose pointer locates the problem in the *source* file
// ("/line/17", or "/home/wall/3" for the fourth <wall>) and whose message names it and its line.
// Pure functions: no file access here; companion files (an OBJ's .mtl) come through a callback.
#pragma once

#include "render/scene_io/errors.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rr {

enum class ImportFormat { sweethome3d, r2v, obj };  // one row each in import_format_table()

struct ImportFormatInfo {
  ImportFormat format;
  const char* name;     // as given to --format and in URLs: "sh3d", "r2v", "obj"
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
};

struct ImportResult {
  nlohmann::json request;             // {"scene", "camera", "options"}
  std::vector<std::string> warnings;  // what was repaired, approximated or skipped, one line each
};

// Imports one file. A Sweet Home 3D `bytes` may be Home.xml or a .sh3d zip holding Home.xml.
// Throws InputError: Kind::malformed when the file cannot be read as its format, Kind::invalid when
// it can but describes something we refuse (an opening wider than its wall, an out-of-range index),
// Kind::too_large past a limit.
ImportResult import_file_text(std::string_view bytes, ImportFormat format, const ImportOptions& options = {});

// The importers behind import_file_text, for callers that know the format.
ImportResult import_sweethome3d(std::string_view home_xml, const ImportOptions& options = {});
ImportResult import_r2v(std::string_view text, const ImportOptions& options = {});
ImportResult import_obj(std::string_view text, const ImportOptions& options = {});

// Home.xml from a .sh3d zip archive. Throws InputError(malformed) when `zip_bytes` is not a zip or
// holds no Home.xml (homes saved before Sweet Home 3D 5.3 only hold the Java-serialised "Home").
std::string extract_sh3d_home_xml(std::string_view zip_bytes);

}  // namespace rr

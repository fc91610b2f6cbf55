// File access around the importers: the file's bytes, its format, and companion .mtl files.
#include "render/import/import_files.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rr {

namespace {

std::optional<std::string> read_optional(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

ImportResult import_path(const std::filesystem::path& file, std::optional<ImportFormat> format, ImportOptions options) {
  std::optional<std::string> bytes = read_optional(file);
  if (!bytes) throw std::runtime_error("cannot read " + file.string());
  if (!format) format = detect_import_format(*bytes, file.filename().string());
  if (!format) {
    throw std::runtime_error("cannot tell the format of " + file.string() + "; pass --format sh3d|r2v|obj");
  }
  if (!options.read_companion) {
    // Names in the file (mtllib, a piece's model) are relative to its directory, as OBJ readers take them.
    const std::filesystem::path dir = file.parent_path();
    options.read_companion = [dir](const std::string& name) { return read_optional(dir / name); };
  }
  return import_file_text(*bytes, *format, options);
}

}  // namespace rr

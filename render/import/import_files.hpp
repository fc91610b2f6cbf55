// The importers (render/import/import.hpp) on files: read FILE, recognise its format unless one is given,
// and let an OBJ's `mtllib` name a material library beside it. Used by `roomrender import` and
// `roomrender render --obj`.
#pragma once

#include "render/import/import.hpp"

#include <filesystem>
#include <optional>

namespace rr {

// Throws std::runtime_error when the file cannot be read or its format not recognised, and the
// importers' InputError when its content is wrong.
ImportResult import_path(const std::filesystem::path& file, std::optional<ImportFormat> format, ImportOptions options);

}  // namespace rr

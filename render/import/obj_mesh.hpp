// Wavefront OBJ text -> one JSON mesh document {"vertices", "faces"[, "normals"]} (mesh_json.hpp),
// every group merged in order of first appearance, in the file's units, repaired as the OBJ importer
// repairs its groups. Materials are not read: a stored mesh is geometry, its placement gives colour.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace rr {

// Throws InputError naming the line ("/line/N") of a bad number, index or face, or "" when the file
// has no face to draw. Appends the repairs made to `warnings`.
nlohmann::json obj_mesh_document(std::string_view text, std::vector<std::string>& warnings);

}  // namespace rr

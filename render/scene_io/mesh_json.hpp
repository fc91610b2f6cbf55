// The JSON mesh form {"vertices": [[x,y,z]...], "faces": [[i,j,k...]...], "normals": [[x,y,z]...],
// "uvs": [[u,v]...]}
// <-> MeshData (object space). Read both as the geometry of an inline mesh solid and as a stored
// mesh document; every error names its JSON Pointer ("/vertices/3/1", "/faces/7/2"). Written back in
// canonical order, so GET of a stored mesh and a re-upload of it give the same id.
#pragma once

#include "render/core/mesh_data.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <memory>

namespace rr {

// A mesh document (only "vertices", "faces" and optional "normals" and "uvs"), validated as an inline mesh
// solid's geometry is. Throws InputError: invalid (422), too_large (413: more faces than
// limits.max_polygons, more vertices than limits.max_mesh_vertices).
std::shared_ptr<const MeshData> mesh_from_json(const nlohmann::json& document, const ParseLimits& limits);

// The canonical document of a mesh: {"vertices", "faces"} and "normals" and "uvs" when it has them.
nlohmann::json mesh_to_json(const MeshData& mesh);

}  // namespace rr

// An indexed mesh in object space, shared and immutable once made: inline mesh solids and stored
// meshes alike are one MeshData that any number of solids place (shared_ptr, never copied). In:
// vertices, faces (indices into vertices, >= 3 each, validated by the reader), optional unit
// per-vertex normals and texture coordinates. Out: the same in canonical order, its bounds, counts and content id.
#pragma once

#include "render/core/math.hpp"

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace rr {

namespace detail {
struct MeshPlan;  // the tessellator's per-mesh work (solid_mesh.cpp), made once on first use
}

struct MeshData {
  std::vector<Vec3> vertices;                // object space, in order of first use by the faces
  std::vector<std::vector<uint32_t>> faces;  // as given, indices renumbered to that order
  std::vector<Vec3> normals;                 // empty, or one unit shading normal per vertex
  std::vector<glm::dvec2> uvs;               // empty, or texture coordinates (texture.hpp) per vertex
  Vec3 bounds_min{0.0};
  Vec3 bounds_max{0.0};
  size_t index_count = 0;  // sum of the faces' sizes
  std::string content_id;  // mesh_content_id(*this): 16 hex digits

  // Filled by the tessellator the first time the mesh is placed; every later placement reuses it.
  mutable std::once_flag plan_once;
  mutable std::shared_ptr<const detail::MeshPlan> plan;
};

// Makes the canonical mesh: vertices no face uses are dropped and the rest renumbered in order of
// first use, so one mesh written with its vertices in another order (an OBJ's file order, a JSON
// mesh's) is one mesh; then bounds, counts and content id. Expects indices in range.
// `uvs`, like `normals`, is empty or one per vertex, and follows the renumbering.
std::shared_ptr<const MeshData> make_mesh_data(std::vector<Vec3> vertices, std::vector<std::vector<uint32_t>> faces,
                                               std::vector<Vec3> normals, std::vector<glm::dvec2> uvs = {});

// The 64-bit FNV-1a hash (hash.hpp) of the canonical binary form: a name of the encoding, then the
// vertices, faces and normals, each list prefixed by its length, numbers as IEEE-754 bits (-0 as 0),
// indices as 32 bits; then, only when the mesh has them, "uvs" and the texture coordinates, so a mesh
// without them keeps the id it had before they existed. The same parsed mesh has one id whatever text
// it came from.
std::string mesh_content_id(const MeshData& mesh);

// Approximate heap bytes of the mesh (the plan it may grow is about as large again).
size_t mesh_bytes(const MeshData& mesh);

}  // namespace rr

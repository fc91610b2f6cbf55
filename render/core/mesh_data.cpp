// Canonical meshes (mesh_data.hpp): first-use renumbering, bounds and the content hash.
#include "render/core/mesh_data.hpp"

#include "render/core/hash.hpp"

#include <bit>
#include <limits>

namespace rr {

namespace {

void add(Fnv1a& h, double v) { h.add_u64(std::bit_cast<uint64_t>(v == 0.0 ? 0.0 : v)); }
void add(Fnv1a& h, const std::vector<Vec3>& points) {
  h.add_u64(points.size());
  for (const Vec3& p : points) add(h, p.x), add(h, p.y), add(h, p.z);
}

}  // namespace

std::shared_ptr<const MeshData> make_mesh_data(std::vector<Vec3> vertices, std::vector<std::vector<uint32_t>> faces,
                                               std::vector<Vec3> normals, std::vector<glm::dvec2> uvs) {
  auto mesh = std::make_shared<MeshData>();
  constexpr uint32_t unused = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> renumber(vertices.size(), unused);
  for (std::vector<uint32_t>& face : faces) {
    for (uint32_t& index : face) {
      if (renumber[index] == unused) {
        renumber[index] = uint32_t(mesh->vertices.size());
        mesh->vertices.push_back(vertices[index]);
        if (!normals.empty()) mesh->normals.push_back(normals[index]);
        if (!uvs.empty()) mesh->uvs.push_back(uvs[index]);
      }
      index = renumber[index];
    }
    mesh->index_count += face.size();
  }
  mesh->faces = std::move(faces);
  if (!mesh->vertices.empty()) {
    mesh->bounds_min = mesh->bounds_max = mesh->vertices[0];
    for (const Vec3& v : mesh->vertices) {
      mesh->bounds_min = glm::min(mesh->bounds_min, v);
      mesh->bounds_max = glm::max(mesh->bounds_max, v);
    }
  }
  mesh->content_id = mesh_content_id(*mesh);
  return mesh;
}

std::string mesh_content_id(const MeshData& mesh) {
  Fnv1a h;
  h.add_bytes("roomrender mesh 1");  // names this encoding; stored mesh ids depend on it
  add(h, mesh.vertices);
  h.add_u64(mesh.faces.size());
  for (const std::vector<uint32_t>& face : mesh.faces) {
    h.add_u64(face.size());
    for (uint32_t index : face) h.add_u32(index);
  }
  add(h, mesh.normals);
  if (!mesh.uvs.empty()) {
    h.add_bytes("uvs");
    h.add_u64(mesh.uvs.size());
    for (const glm::dvec2& uv : mesh.uvs) add(h, uv.x), add(h, uv.y);
  }
  return hex64(h.value());
}

size_t mesh_bytes(const MeshData& mesh) {
  size_t bytes = sizeof(MeshData) + (mesh.vertices.capacity() + mesh.normals.capacity()) * sizeof(Vec3) +
                 mesh.uvs.capacity() * sizeof(glm::dvec2);
  bytes += mesh.faces.capacity() * sizeof(std::vector<uint32_t>) + mesh.index_count * sizeof(uint32_t);
  return bytes;
}

}  // namespace rr

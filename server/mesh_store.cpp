// StoredMesh, its documents and MeshPins (mesh_store.hpp); the stores themselves are content_store.cpp
// and postgres_store.cpp.
#include "server/mesh_store.hpp"

#include "render/scene_io/mesh_json.hpp"

namespace rr::server {

std::shared_ptr<const StoredMesh> prepare_mesh(std::shared_ptr<const MeshData> mesh) {
  auto out = std::make_shared<StoredMesh>();
  out->id = mesh->content_id;
  out->text = mesh_to_json(*mesh).dump();
  // The text, the mesh and the tessellator's plan for it (about the mesh's size again).
  out->bytes = sizeof(StoredMesh) + out->text.size() + 2 * mesh_bytes(*mesh);
  out->mesh = std::move(mesh);
  return out;
}

std::shared_ptr<const StoredMesh> read_stored_mesh(const std::string& text, const ParseLimits& limits) {
  return prepare_mesh(mesh_from_json(parse_json_text(text, limits), limits));
}

StoredDocument mesh_document(const StoredMesh& mesh) { return {mesh.id, mesh.text, {}, {}}; }

StoredDocument read_mesh_document(const std::string& text, const ParseLimits& limits) {
  return mesh_document(*read_stored_mesh(text, limits));
}

void MeshPins::change(const std::string& scene_id, const std::vector<std::string>& mesh_ids, bool added) {
  std::lock_guard lock(mutex_);
  for (const std::string& mesh : mesh_ids) {
    if (added) {
      scenes_[mesh].insert(scene_id);
    } else if (auto it = scenes_.find(mesh); it != scenes_.end()) {
      it->second.erase(scene_id);
      if (it->second.empty()) scenes_.erase(it);
    }
  }
}

bool MeshPins::pinned(const std::string& mesh_id) const {
  std::lock_guard lock(mutex_);
  return scenes_.contains(mesh_id);
}

std::vector<std::string> MeshPins::scenes_placing(const std::string& mesh_id, size_t most) const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  if (auto it = scenes_.find(mesh_id); it != scenes_.end()) {
    for (const std::string& scene : it->second) {
      if (out.size() == most) break;
      out.push_back(scene);
    }
  }
  return out;
}

}  // namespace rr::server

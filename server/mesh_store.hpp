// Stored meshes: a MeshData stored as its canonical JSON mesh document (in a DocumentStore), its id
// the mesh's content id (mesh_data.hpp), so one mesh sent as OBJ or as JSON is one document. The
// parsed mesh is a StoredMesh, kept in the prepared cache (prepared_cache.hpp) and read again from
// the text when evicted. MeshPins records which stored scenes place which stored meshes: a mesh is
// pinned (neither deleted nor expired) while a stored scene places it.
#pragma once

#include "render/core/mesh_data.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/content_store.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace rr::server {

struct StoredScene;

struct StoredMesh {
  static constexpr const char* kind = "mesh";  // in answers, log events and file or table names
  static constexpr const char* plural = "meshes";
  std::string id;    // mesh->content_id
  std::string text;  // canonical JSON mesh document (mesh_to_json)
  size_t bytes = 0;  // what it costs in memory: charged against the prepared cache's budget
  std::shared_ptr<const MeshData> mesh;
};

std::shared_ptr<const StoredMesh> prepare_mesh(std::shared_ptr<const MeshData> mesh);
// A stored mesh's text -> its StoredMesh. Throws when it does not read.
std::shared_ptr<const StoredMesh> read_stored_mesh(const std::string& text, const ParseLimits& limits);
// What a store keeps of a mesh.
StoredDocument mesh_document(const StoredMesh& mesh);
// A stored mesh file's text -> its document (start-up): parsed, so that its id is its content's.
StoredDocument read_mesh_document(const std::string& text, const ParseLimits& limits);

using MeshStoreConfig = ContentStoreConfig<StoredMesh>;
using MeshStore = ContentStore<StoredMesh>;       // the embedded store
using MeshDocuments = DocumentStore<StoredMesh>;  // either store, as the handlers see it

class MeshPins {
 public:
  // A SceneStore's on_change: the scene `scene_id` placing the meshes `mesh_ids` was added or removed.
  void change(const std::string& scene_id, const std::vector<std::string>& mesh_ids, bool added);
  bool pinned(const std::string& mesh_id) const;
  // Up to `most` stored scenes placing the mesh, in id order.
  std::vector<std::string> scenes_placing(const std::string& mesh_id, size_t most) const;
  // Held across "check the meshes a scene places, store the scene" and across "delete a mesh", so
  // a scene is never stored placing a mesh that a concurrent delete removed.
  std::mutex& writers() { return writers_; }

 private:
  std::mutex writers_;
  mutable std::mutex mutex_;
  std::map<std::string, std::set<std::string>> scenes_;  // mesh id -> stored scenes placing it
};

}  // namespace rr::server

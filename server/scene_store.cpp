// Scene documents -> StoredScene (scene_store.hpp); the store itself is content_store.cpp.
#include "server/scene_store.hpp"

#include "render/core/hash.hpp"

#include <set>

namespace rr::server {

namespace {

// Approximate heap cost of an entry: the text, the parsed scene (about as large as its text, in
// practice smaller), the tessellation's arrays, its hierarchy and its cells.
size_t entry_bytes(const StoredScene& s) {
  size_t bytes = sizeof(StoredScene) + 2 * s.text.size();
  bytes += s.soup.positions.capacity() * sizeof(Vec3) + s.soup.normals.capacity() * sizeof(glm::vec3);
  bytes += s.soup.polygons.capacity() * sizeof(Polygon) + s.soup.materials.capacity() * sizeof(Material);
  bytes += s.soup.objects.capacity() * sizeof(SceneObject) + s.warnings.capacity() * sizeof(PlacementWarning);
  if (s.hierarchy) bytes += s.hierarchy->bytes();
  if (s.cells) bytes += s.cells->bytes();
  return bytes;
}

}  // namespace

std::string scene_document_pointer(const std::string& request_pointer) {
  if (request_pointer == "/scene") return "";
  if (request_pointer.starts_with("/scene/")) return request_pointer.substr(6);
  return request_pointer;
}

std::shared_ptr<const StoredScene> prepare_scene(const nlohmann::json& document, const ParseLimits& limits) {
  RenderRequest parsed;
  try {
    parsed = request_from_json(nlohmann::json{{"scene", document}}, limits);
  } catch (const InputError& e) {
    throw e.with_pointers(scene_document_pointer);
  }
  auto out = std::make_shared<StoredScene>();
  out->text = document.dump();
  out->id = hash_hex(out->text);
  static_cast<PreparedScene&>(*out) = rr::prepare_scene(std::move(parsed.scene));
  out->bytes = entry_bytes(*out);
  std::set<std::string> refs;
  for (const Solid& s : out->scene.geometry.solids) {
    if (!s.mesh_ref.empty()) refs.insert(s.mesh_ref);
  }
  out->mesh_refs.assign(refs.begin(), refs.end());
  return out;
}

}  // namespace rr::server

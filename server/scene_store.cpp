// Scene documents -> StoredScene and StoredDocument (scene_store.hpp); the stores themselves are
// content_store.cpp and postgres_store.cpp.
#include "server/scene_store.hpp"

#include "render/core/hash.hpp"
#include "render/core/scene_id.hpp"
#include "render/core/texture.hpp"
#include "render/scene_io/errors.hpp"

#include <map>
#include <set>
#include <string_view>

namespace rr::server {

namespace {

// Approximate heap cost of a prepared scene: the text, the parsed scene (about as large as its text,
// in practice smaller), the tessellation's arrays, its hierarchy, its cells, its shadow-ray tree, its lamps' sight, the
// meshes it places and its decoded texture images with their mip chains
// (counted with each scene that holds them, though the scenes placing one mesh share it: an overcount
// keeps the cache's budget a bound on what it holds).
size_t entry_bytes(const StoredScene& s) {
  size_t bytes = sizeof(StoredScene) + 2 * s.text.size();
  bytes += soup_bytes(s.soup) + s.warnings.capacity() * sizeof(PlacementWarning);
  std::set<const TextureImage*> images;
  for (const Material& m : s.soup.materials) {
    const TextureImage* image = m.texture ? m.texture->decoded.get() : nullptr;
    if (image && images.insert(image).second) bytes += image->bytes();
  }
  if (s.hierarchy) bytes += s.hierarchy->bytes();
  if (s.cells) bytes += s.cells->bytes();
  if (s.shadow_bvh) bytes += s.shadow_bvh->bytes();
  if (s.lamps) bytes += s.lamps->bytes();
  std::set<const MeshData*> meshes;
  for (const Solid& solid : s.scene.geometry.solids) {
    if (solid.mesh && meshes.insert(solid.mesh.get()).second) bytes += mesh_bytes(*solid.mesh);
  }
  return bytes;
}

// Whether a scene placing mesh `ref` depends on the store for it: the catalogue's meshes are always there.
bool stored_ref(const std::string& ref, const ParseLimits& limits) {
  return !ref.empty() && !(limits.builtin_mesh && limits.builtin_mesh(ref));
}

// The stored meshes a scene document places (a solid's "ref", a piece part's), each once, sorted.
std::vector<std::string> refs_of(const nlohmann::json& document, const ParseLimits& limits) {
  std::set<std::string> refs;
  auto place = [&](const nlohmann::json& holder) {
    if (holder.is_object() && holder.contains("ref") && holder["ref"].is_string()) {
      const std::string& ref = holder["ref"].get_ref<const std::string&>();
      if (stored_ref(ref, limits)) refs.insert(ref);
    }
  };
  if (document.is_object() && document.contains("solids") && document["solids"].is_array()) {
    for (const nlohmann::json& solid : document["solids"]) {
      place(solid);
      if (solid.is_object() && solid.contains("parts") && solid["parts"].is_array()) {
        for (const nlohmann::json& part : solid["parts"]) place(part);
      }
    }
  }
  return {refs.begin(), refs.end()};
}

bool is_stored_image_id(const nlohmann::json& value) {
  if (!value.is_string()) return false;
  const std::string& text = value.get_ref<const std::string&>();
  return text.size() == 16 && text.find_first_not_of("0123456789abcdef") == std::string::npos;
}

// Adds to `refs` the stored images named by id in `value`: the "image" of every texture member
// ("texture", "left_texture", "floor_texture", ...) anywhere in it (floors, rooms, wall sides,
// solids, piece parts), but for those always there (the catalogue's).
void add_texture_refs(const nlohmann::json& value, const ParseLimits& limits, std::set<std::string>& refs) {
  if (value.is_object()) {
    for (const auto& [key, member] : value.items()) {
      if (std::string_view(key).ends_with("texture") && member.is_object() && member.contains("image") &&
          is_stored_image_id(member.at("image"))) {
        const std::string& id = member.at("image").get_ref<const std::string&>();
        if (!(limits.builtin_texture && limits.builtin_texture(id))) refs.insert(id);
      }
      add_texture_refs(member, limits, refs);
    }
  } else if (value.is_array()) {
    for (const nlohmann::json& item : value) add_texture_refs(item, limits, refs);
  }
}

}  // namespace

void for_each_texture(nlohmann::json& value, const std::string& pointer,
                      const std::function<bool(nlohmann::json& texture, const std::string& pointer)>& keep) {
  if (value.is_object()) {
    for (auto it = value.begin(); it != value.end();) {
      const std::string at = pointer_append(pointer, it.key());
      if (std::string_view(it.key()).ends_with("texture") && it->is_object() && it->contains("image") &&
          !keep(*it, at)) {
        it = value.erase(it);
        continue;
      }
      for_each_texture(*it, at, keep);
      ++it;
    }
  } else if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i) for_each_texture(value[i], pointer_append(pointer, i), keep);
  }
}

namespace {

// The stored images a scene document's textures name by id, each once, sorted.
std::vector<std::string> texture_refs_of(const nlohmann::json& document, const ParseLimits& limits) {
  std::set<std::string> refs;
  add_texture_refs(document, limits, refs);
  return {refs.begin(), refs.end()};
}

// `limits` resolving each mesh once however many solids place it: a home places its few dozen
// models hundreds of times, and with a shared store each resolution asks the database.
ParseLimits resolving_each_mesh_once(const ParseLimits& limits) {
  if (!limits.resolve_mesh) return limits;
  ParseLimits out = limits;
  auto resolved = std::make_shared<std::map<std::string, std::shared_ptr<const MeshData>>>();
  out.resolve_mesh = [resolve = limits.resolve_mesh, resolved](const std::string& id) {
    auto [it, added] = resolved->try_emplace(id);
    if (added) it->second = resolve(id);
    return it->second;
  };
  return out;
}

}  // namespace

std::string scene_document_pointer(const std::string& request_pointer) {
  if (request_pointer == "/scene") return "";
  if (request_pointer.starts_with("/scene/")) return request_pointer.substr(6);
  return request_pointer;
}

std::shared_ptr<const StoredScene> prepare_scene(const nlohmann::json& document, const ParseLimits& limits,
                                                 unsigned threads) {
  RenderRequest parsed;
  try {
    parsed = request_from_json(nlohmann::json{{"scene", document}}, resolving_each_mesh_once(limits));
  } catch (const InputError& e) {
    throw e.with_pointers(scene_document_pointer);
  }
  auto out = std::make_shared<StoredScene>();
  out->text = document.dump();
  out->id = hash_hex(out->text);
  static_cast<PreparedScene&>(*out) = rr::prepare_scene(std::move(parsed.scene), threads);
  out->bytes = entry_bytes(*out);
  // The stored meshes it places: those that are always there (the catalogue's) it does not depend on.
  std::set<std::string> refs;
  for (const Solid& s : out->scene.geometry.solids) {
    if (stored_ref(s.mesh_ref, limits)) refs.insert(s.mesh_ref);
    for (const PiecePart& part : s.parts) {
      if (stored_ref(part.mesh_ref, limits)) refs.insert(part.mesh_ref);
    }
  }
  out->mesh_refs.assign(refs.begin(), refs.end());
  out->texture_refs = texture_refs_of(document, limits);
  return out;
}

std::shared_ptr<const StoredScene> read_stored_scene(const std::string& text, const ParseLimits& limits,
                                                     unsigned threads) {
  return prepare_scene(parse_json_text(text, limits), limits, threads);
}

StoredDocument scene_document(const StoredScene& scene) {
  return {scene.id, scene.text, scene.mesh_refs, scene.texture_refs};
}

StoredDocument read_scene_document(const std::string& text, const ParseLimits& limits) {
  const nlohmann::json document = parse_json_text(text, limits);
  return {hash_hex(text), text, refs_of(document, limits), texture_refs_of(document, limits)};
}

std::string static_id_of(const std::string& text, const ParseLimits& limits) {
  return scene_id(
      request_from_json(nlohmann::json{{"scene", parse_json_text(text, limits)}}, resolving_each_mesh_once(limits))
          .scene.geometry);
}

}  // namespace rr::server

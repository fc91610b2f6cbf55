// Stored scenes: a scene document (the "scene" member of a render request) is stored as canonical
// JSON text (keys sorted, no whitespace), its id hash_hex(text), in a DocumentStore (budgets,
// owners, retention, files or rows: content_store.hpp, postgres_store.hpp). What is prepared from it
// (the parsed scene, its tessellation, placement warnings and hierarchy) is a StoredScene, kept in
// the prepared cache (prepared_cache.hpp) and rebuilt from the text when the cache evicted it. Meshes
// placed by "ref" and images named by id are resolved through the limits' resolvers (the stored
// meshes and images).
#pragma once

#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/content_store.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rr::server {

// The prepared scene (render() draws it as is; its warnings point into the scene document,
// "/solids/2") with the document it came from.
struct StoredScene : PreparedScene {
  static constexpr const char* kind = "scene";  // in answers, log events and file or table names
  static constexpr const char* plural = "scenes";
  std::string id;                         // hash_hex(text)
  std::string text;                       // canonical JSON of the scene document
  size_t bytes = 0;                       // what it costs in memory: charged against the prepared cache's budget
  std::vector<std::string> mesh_refs;     // the stored meshes it places, each once, sorted
  std::vector<std::string> texture_refs;  // the stored images its textures name, each once, sorted
};

// Parses and validates one scene document (JSON already parsed with the limits' depth bound) into a
// StoredScene, on `threads` threads where its preparation divides (the result does not depend on
// them). Throws InputError with pointers into the document ("" is the document itself).
std::shared_ptr<const StoredScene> prepare_scene(const nlohmann::json& document, const ParseLimits& limits,
                                                 unsigned threads = 1);

// A stored scene's text -> its StoredScene (the prepared cache's rebuild). Throws InputError when
// it no longer reads (a mesh it places is gone, a limit was lowered).
std::shared_ptr<const StoredScene> read_stored_scene(const std::string& text, const ParseLimits& limits,
                                                     unsigned threads = 1);

// What a store keeps of a prepared scene.
StoredDocument scene_document(const StoredScene& scene);
// A stored scene file's text -> its document: the id it hashes to, the meshes it places and the
// images it names, without
// preparing it (start-up). Throws when it is not JSON.
StoredDocument read_scene_document(const std::string& text, const ParseLimits& limits);
// The static id (X-Scene-Id) of a stored scene's text: parsed, its meshes resolved, not tessellated.
std::string static_id_of(const std::string& text, const ParseLimits& limits);

// Calls keep(texture, its pointer below `pointer`) for every texture object with an "image" in a
// scene document (the members named "texture" or ending in "_texture" of its floors, rooms, walls,
// solids and piece parts) and removes those for which it returns false.
void for_each_texture(nlohmann::json& document, const std::string& pointer,
                      const std::function<bool(nlohmann::json& texture, const std::string& pointer)>& keep);

// "/scene/solids/2" -> "/solids/2": a request pointer made relative to the scene document.
std::string scene_document_pointer(const std::string& request_pointer);

using SceneStoreConfig = ContentStoreConfig<StoredScene>;
using SceneStore = ContentStore<StoredScene>;       // the embedded store
using SceneDocuments = DocumentStore<StoredScene>;  // either store, as the handlers see it

}  // namespace rr::server

// Stored scenes, content-addressed (a ContentStore, content_store.hpp: budgets, owners, retention,
// files): a scene document (the "scene" member of a render request) is kept as canonical JSON text
// (keys sorted, no whitespace), and its id is hash_hex(text). Each entry also keeps the parsed scene,
// its tessellation and its placement warnings, so rendering a stored scene skips both. Meshes placed
// by "ref" are resolved through the limits' resolver (the mesh store) and pinned while it is stored.
#pragma once

#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/content_store.hpp"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace rr::server {

// The prepared scene (render() draws it as is; its warnings point into the scene document,
// "/solids/2") with the document it came from.
struct StoredScene : PreparedScene {
  static constexpr const char* kind = "scene";  // in answers, log events and file or table names
  static constexpr const char* plural = "scenes";
  std::string id;                      // hash_hex(text)
  std::string text;                    // canonical JSON of the scene document
  size_t bytes = 0;                    // charged against the store's budget
  std::vector<std::string> mesh_refs;  // the stored meshes it places, each once, sorted
};

// Parses and validates one scene document (JSON already parsed with the limits' depth bound) into a
// StoredScene. Throws InputError with pointers into the document ("" is the document itself).
std::shared_ptr<const StoredScene> prepare_scene(const nlohmann::json& document, const ParseLimits& limits);

// "/scene/solids/2" -> "/solids/2": a request pointer made relative to the scene document.
std::string scene_document_pointer(const std::string& request_pointer);

using SceneStoreConfig = ContentStoreConfig<StoredScene>;
using SceneStore = ContentStore<StoredScene>;       // the embedded store
using SceneDocuments = DocumentStore<StoredScene>;  // either store, as the handlers see it

}  // namespace rr::server

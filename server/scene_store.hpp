// Stored scenes, content-addressed: a scene document (the "scene" member of a render request) is kept
// as canonical JSON text (keys sorted, no whitespace), and its id is hash_hex(text), so the same
// scene always gets the same id and an id names exactly one content. Each entry also keeps the parsed
// scene, its tessellation and its placement warnings, so rendering a stored scene skips both.
// Bounded in entries and (approximate) bytes, least recently used first out. With a data directory
// every stored scene is also a file <dir>/scenes/<id>.json, written to a temporary file, fsynced and
// renamed (a crash leaves the old state or the new, never a torn file); evicted or deleted scenes
// lose their file, and start-up loads the files back, oldest first.
#pragma once

#include "render/core/lru_cache.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

namespace rr::server {

// The prepared scene (render() draws it as is; its warnings point into the scene document,
// "/solids/2") with the document it came from.
struct StoredScene : PreparedScene {
  std::string id;         // hash_hex(text)
  std::string text;       // canonical JSON of the scene document
  size_t bytes = 0;       // charged against the store's budget
};

// Parses and validates one scene document (JSON already parsed with the limits' depth bound) into a
// StoredScene. Throws InputError with pointers into the document ("" is the document itself).
std::shared_ptr<const StoredScene> prepare_scene(const nlohmann::json& document, const ParseLimits& limits);

// "/scene/solids/2" -> "/solids/2": a request pointer made relative to the scene document.
std::string scene_document_pointer(const std::string& request_pointer);

struct SceneStoreConfig {
  size_t max_entries = 1000;
  size_t max_bytes = 256u << 20;
  std::filesystem::path data_dir;  // empty: memory only
  ParseLimits limits;
};

class SceneStore {
 public:
  // conflict: another content with the same id is stored (ids are 64-bit FNV-1a hashes, not a
  // cryptographic commitment, so a crafted collision is possible; it is refused, never merged).
  enum class PutResult { created, existed, too_large, conflict };
  using Log = std::function<void(const std::string& level, nlohmann::ordered_json fields)>;

  SceneStore(SceneStoreConfig config, Log log);
  SceneStore(const SceneStore&) = delete;
  SceneStore& operator=(const SceneStore&) = delete;

  // Reads the data directory (if any): removes temporary files a crash left, loads every scene file
  // whose content still hashes to its name, oldest first. Returns how many were loaded.
  size_t load();

  // Stores `scene`, on disk first when persistent. Throws std::runtime_error when the file cannot
  // be written (the caller answers 500; nothing is stored).
  PutResult put(const std::shared_ptr<const StoredScene>& scene);
  std::shared_ptr<const StoredScene> find(const std::string& id);
  bool erase(const std::string& id);
  CacheStats stats() const { return cache_.stats(); }
  const SceneStoreConfig& config() const { return config_; }

 private:
  std::filesystem::path file_for(const std::string& id) const;
  void write_file(const StoredScene& scene) const;

  SceneStoreConfig config_;
  Log log_;
  std::mutex mutation_;  // put and erase run one at a time, so a file and its cache entry agree
  SharedLruCache<StoredScene> cache_;
};

}  // namespace rr::server

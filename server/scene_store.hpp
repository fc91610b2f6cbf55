// Stored scenes, content-addressed: a scene document (the "scene" member of a render request) is kept
// as canonical JSON text (keys sorted, no whitespace), and its id is hash_hex(text), so the same
// scene always gets the same id and an id names exactly one content. Each entry also keeps the parsed
// scene, its tessellation and its placement warnings, so rendering a stored scene skips both.
// Stored means kept: a store at its budget (entries or approximate bytes) refuses new scenes rather
// than evict acknowledged ones; only an operator's retention (ttl, time since last access) removes
// them. Each scene has owners (one reference each); it goes when the last reference is dropped.
// With a data directory every scene is also a file <dir>/scenes/<id>.json and, unless its only owner
// is "" and no retention is set, its owners and creation time <dir>/scene-meta/<id>.json, each
// written to a temporary file, fsynced and renamed (a crash leaves the old state or the new, never a
// torn file); start-up loads them back.
#pragma once

#include "render/core/lru_cache.hpp"  // CacheStats
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

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
  std::chrono::seconds ttl{0};     // removed this long after the last access; 0: kept until deleted
};

class SceneStore {
 public:
  using Clock = std::chrono::system_clock;  // persisted (file times), so wall-clock time
  // conflict: another content with the same id is stored (ids are 64-bit FNV-1a hashes, not a
  // cryptographic commitment, so a crafted collision is possible; it is refused, never merged).
  // full: storing it would pass max_entries or max_bytes; nothing stored is given up for it.
  enum class PutResult { created, existed, too_large, full, conflict };
  // not_owner: the scene is stored, but the caller holds no reference to it.
  enum class ReleaseResult { removed, reference_dropped, not_found, not_owner };
  using Log = std::function<void(const std::string& level, nlohmann::ordered_json fields)>;

  struct Listed {
    std::string id;
    int64_t created_us = 0;  // microseconds since the epoch; unique within the store
    std::optional<Clock::time_point> expires;
    size_t bytes = 0;
  };
  struct Page {
    std::vector<Listed> scenes;  // newest first
    std::optional<std::string> next_cursor;
  };

  SceneStore(SceneStoreConfig config, Log log);
  SceneStore(const SceneStore&) = delete;
  SceneStore& operator=(const SceneStore&) = delete;

  // Reads the data directory (if any): removes temporary files a crash left and metadata without a
  // scene, loads every scene file whose content still hashes to its name (also beyond the budget:
  // it was acknowledged), drops those whose retention ran out. Returns how many were loaded.
  size_t load();

  // Stores `scene` with `owner` holding a reference (on disk first when persistent); storing it again
  // adds the owner's reference. Throws std::runtime_error when a file cannot be written (the caller
  // answers 500; nothing changes).
  PutResult put(const std::shared_ptr<const StoredScene>& scene, const std::string& owner);
  // The scene, counting as an access (it restarts the retention clock).
  std::shared_ptr<const StoredScene> find(const std::string& id);
  // Drops `owner`'s reference; nullopt (a server without tokens) drops every reference.
  ReleaseResult release(const std::string& id, const std::optional<std::string>& owner);
  // Scenes newest first, those `owner` holds a reference to (nullopt: all), after `cursor` (from
  // an earlier page). Throws std::invalid_argument for a cursor this store did not make.
  Page list(const std::optional<std::string>& owner, size_t limit, const std::string& cursor);
  // When a scene accessed now expires (nullopt: no retention is set).
  std::optional<Clock::time_point> expiry_from_now() const;
  // Fill (entries, bytes and their budgets) and find()'s hits and misses; evictions stay 0.
  CacheStats stats();
  const SceneStoreConfig& config() const { return config_; }

 private:
  struct Entry {
    std::shared_ptr<const StoredScene> scene;
    std::set<std::string> owners;
    int64_t created_us = 0;
    Clock::time_point last_access;
    Clock::time_point persisted_access;  // the scene file's time, moved forward now and then
  };

  std::filesystem::path file_for(const std::string& id) const;
  std::filesystem::path meta_for(const std::string& id) const;
  void write_meta(const std::string& id, int64_t created_us, const std::set<std::string>& owners) const;
  void remove_files(const std::string& id) const;
  void expire(Clock::time_point now, bool force);  // holds mutation_
  bool expired(const Entry& entry, Clock::time_point now) const;
  int64_t next_created_us(Clock::time_point now);
  bool load_one(const std::filesystem::path& path, Clock::time_point modified);

  SceneStoreConfig config_;
  Log log_;
  // Writers (put, release, expiry, load) take mutation_ first, so a file and its entry agree and
  // owners change one writer at a time; the map itself is guarded by mutex_, which find() takes
  // alone, so renders of stored scenes never wait for a writer's fsync.
  std::mutex mutation_;
  std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  size_t bytes_ = 0;
  int64_t last_created_us_ = 0;
  Clock::time_point last_sweep_;
  CacheStats stats_;
};

}  // namespace rr::server

// What the handlers need of a store of content-addressed documents (stored scenes, meshes, images):
// each a StoredDocument, its canonical text charged against the store's budget of document bytes
// and entries. T (StoredScene, StoredMesh or StoredTexture) names the kind; what is prepared from a document lives
// in the service's prepared cache (prepared_cache.hpp), never here. Two implementations:
// ContentStore (embedded: memory, or files under --data-dir) and PostgresStore (one database
// shared by every replica, --store postgresql://...). Both keep the same promises: stored means
// kept (507 when full, never eviction), owners hold one reference each, retention counts from the
// last access, a pinned entry is neither deleted nor expired.
#pragma once

#include "render/core/lru_cache.hpp"  // CacheStats

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rr::server {

// The store cannot answer now (its database is down, slow or out of connections); nothing changed.
// The service answers 503 with Retry-After; renders that need no stored document go on.
class StoreUnavailable : public std::runtime_error {
 public:
  StoreUnavailable(const std::string& detail, int retry_after_s)
      : std::runtime_error(detail), retry_after_s_(retry_after_s) {}
  int retry_after_s() const { return retry_after_s_; }

 private:
  int retry_after_s_;
};

// One stored document as a store keeps it.
struct StoredDocument {
  std::string id;    // the content id: hash_hex(text) for scenes and images, the mesh's content id for meshes
  std::string text;  // the canonical document (an image's encoded bytes), served byte for byte
  std::vector<std::string> refs;                // the stored meshes it places (scenes), each once, sorted
  std::vector<std::string> texture_refs;        // the stored images its textures name (scenes), each once, sorted
  size_t bytes() const { return text.size(); }  // what it costs against the store's budget
};

template <class T>
class DocumentStore {
 public:
  using Clock = std::chrono::system_clock;  // persisted, so wall-clock time
  // conflict: another content with the same id is stored (ids are 64-bit FNV-1a hashes, not a
  // cryptographic commitment, so a crafted collision is possible; it is refused, never merged).
  // full: storing it would pass the entry or byte budget; nothing stored is given up for it.
  // missing_reference: it places a stored document that is no longer stored (a mesh deleted
  // meanwhile); each backend checks that itself (open_stores.hpp).
  enum class PutResult { created, existed, too_large, full, conflict, missing_reference };
  // not_owner: stored, but the caller holds no reference to it. pinned: the last reference, but
  // something stored depends on it (a mesh that a stored scene places, an image its textures name). read_only: part of
  // what the server ships (a catalogue mesh, catalogue_store.hpp), never deleted.
  enum class ReleaseResult { removed, reference_dropped, not_found, not_owner, pinned, read_only };

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

  virtual ~DocumentStore() = default;

  // Prepares the store at start-up (reads the data directory; creates or migrates the schema).
  // Returns how many entries it loaded into memory.
  virtual size_t load() = 0;
  // Stores `document` with `owner` holding a reference; storing it again adds the owner's reference.
  virtual PutResult put(const StoredDocument& document, const std::string& owner) = 0;
  // Whether `id` is stored, counting as an access (it restarts the retention clock): nullopt when
  // not, else its text when `with_text` (read from memory, the data directory or the database),
  // else "".
  virtual std::optional<std::string> find(const std::string& id, bool with_text) = 0;
  // Drops `owner`'s reference; nullopt (a server without tokens) drops every reference.
  virtual ReleaseResult release(const std::string& id, const std::optional<std::string>& owner) = 0;
  // Entries newest first, those `owner` holds a reference to (nullopt: all), after `cursor` (from
  // an earlier page). Throws std::invalid_argument for a cursor this store did not make.
  virtual Page list(const std::optional<std::string>& owner, size_t limit, const std::string& cursor) = 0;
  // Up to `most` stored documents that pin `id` (the scenes placing a mesh), in id order.
  virtual std::vector<std::string> pinned_by(const std::string& id, size_t most) = 0;
  // When an entry accessed now expires (nullopt: no retention is set).
  virtual std::optional<Clock::time_point> expiry_from_now() const = 0;
  // Fill (entries, document bytes and their budgets) and find()'s hits (stored) and misses.
  virtual CacheStats stats() = 0;
  virtual size_t max_bytes() const = 0;
  // Empty when the store can answer now, else why not (readiness).
  virtual std::string unavailable_reason() { return ""; }

  // Every method but unavailable_reason may throw StoreUnavailable (a shared store only) and
  // std::runtime_error (the store failed: answered 500, nothing changed).
};

}  // namespace rr::server

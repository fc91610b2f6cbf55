// A content-addressed store of immutable documents (scenes, meshes, images: StoredDocument, document_store.hpp)
// within a budget of document bytes and entries. Stored means kept: a store at its budget refuses
// new documents rather than evict acknowledged ones; only an operator's retention (ttl, time since
// last access) removes them, and never a pinned one. Each document has owners (one reference each);
// it goes when the last reference is dropped. Without a data directory the texts live in memory
// (the only copy, for as long as the process). With one every document is a file
// <dir>/<plural>/<id>.json, and memory holds only its index entry (size, owners, times, the meshes
// it places); unless its only owner is "" and no retention is set, its owners and creation time are
// <dir>/<kind>-meta/<id>.json. Each file is written to a temporary file, fsynced and renamed (a
// crash leaves the old state or the new, never a torn file); start-up indexes them again.
#pragma once

#include "server/document_store.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace rr::server {

template <class T>
struct ContentStoreConfig {
  size_t max_entries = 100'000;
  size_t max_bytes = size_t{4} << 30;
  std::filesystem::path data_dir;   // empty: memory only
  std::chrono::seconds ttl{0};      // removed this long after the last access; 0: kept until deleted
  std::string kind = "scene";       // metadata in <dir>/<kind>-meta; log events <kind>_...
  std::string plural = "scenes";    // files in <dir>/<plural>
  std::string extension = ".json";  // of those files: ".json" for documents, ".img" for encoded images
  // A stored file's text -> its document: id and the meshes it places (load()). Throws when it
  // does not read.
  std::function<StoredDocument(const std::string& text)> read;
  // An entry something else depends on: not removed (release answers pinned) nor expired.
  std::function<bool(const std::string& id)> pinned;
  // Told of every document added (put, load) or removed (release, expiry) with the meshes it
  // places and the images its textures name, under the writer's lock.
  std::function<void(const std::string& id, const std::vector<std::string>& refs,
                     const std::vector<std::string>& texture_refs, bool added)>
      on_change;
  // Up to `most` entries of another store that pin an entry (pinned_by()); null: none do.
  std::function<std::vector<std::string>(const std::string& id, size_t most)> pinned_by;
};

template <class T>
class ContentStore : public DocumentStore<T> {
 public:
  using Base = DocumentStore<T>;
  using Clock = std::chrono::system_clock;  // as DocumentStore<T>::Clock
  using typename Base::Listed;
  using typename Base::Page;
  using typename Base::PutResult;
  using typename Base::ReleaseResult;
  using Log = std::function<void(const std::string& level, nlohmann::ordered_json fields)>;

  using Config = ContentStoreConfig<T>;
  ContentStore(Config config, Log log);
  ContentStore(const ContentStore&) = delete;
  ContentStore& operator=(const ContentStore&) = delete;

  // Reads the data directory (if any): removes temporary files a crash left and metadata without a
  // document, indexes every document file whose content still reads and names its id (also beyond
  // the budget: it was acknowledged), drops those whose retention ran out. Returns how many it indexed.
  size_t load() override;

  // Stores `document` with `owner` holding a reference (on disk first when persistent); storing it
  // again adds the owner's reference. Throws std::runtime_error when a file cannot be written (the
  // caller answers 500; nothing changes).
  PutResult put(const StoredDocument& document, const std::string& owner) override;
  // Whether it is stored, counting as an access (it restarts the retention clock), and its text
  // when asked (a file read with a data directory).
  std::optional<std::string> find(const std::string& id, bool with_text) override;
  // Drops `owner`'s reference; nullopt (a server without tokens) drops every reference.
  ReleaseResult release(const std::string& id, const std::optional<std::string>& owner) override;
  // Scenes newest first, those `owner` holds a reference to (nullopt: all), after `cursor` (from
  // an earlier page). Throws std::invalid_argument for a cursor this store did not make.
  Page list(const std::optional<std::string>& owner, size_t limit, const std::string& cursor) override;
  // When a scene accessed now expires (nullopt: no retention is set).
  std::optional<Clock::time_point> expiry_from_now() const override;
  // Fill (entries, document bytes and their budgets) and find()'s hits and misses; evictions stay 0.
  CacheStats stats() override;
  std::vector<std::string> pinned_by(const std::string& id, size_t most) override {
    return config_.pinned_by ? config_.pinned_by(id, most) : std::vector<std::string>{};
  }
  size_t max_bytes() const override { return config_.max_bytes; }
  const Config& config() const { return config_; }

 private:
  struct Entry {
    size_t bytes = 0;
    std::vector<std::string> refs;
    std::vector<std::string> texture_refs;
    std::shared_ptr<const std::string> text;  // without a data directory only: the one copy
    std::set<std::string> owners;
    int64_t created_us = 0;
    Clock::time_point last_access;
    Clock::time_point persisted_access;  // the scene file's time, moved forward now and then
  };

  std::filesystem::path file_for(const std::string& id) const;
  std::filesystem::path meta_for(const std::string& id) const;
  void write_meta(const std::string& id, int64_t created_us, const std::set<std::string>& owners) const;
  void remove_files(const std::string& id) const;
  std::optional<std::string> read_text(const Entry& entry, const std::string& id) const;  // null: file gone
  void expire(Clock::time_point now, bool force);                                         // holds mutation_
  bool expired(const std::string& id, const Entry& entry, Clock::time_point now) const;
  int64_t next_created_us(Clock::time_point now);
  bool load_one(const std::filesystem::path& path, Clock::time_point modified);

  Config config_;
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

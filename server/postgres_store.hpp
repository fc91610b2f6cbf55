// The shared store: content-addressed documents (scenes, meshes, images) in one PostgreSQL database that
// every replica uses (--store postgresql://...). Rows hold the canonical bytes (reads are
// byte-identical), owners and the stored scenes' placements of meshes and images; the budget (507), owners,
// pins and retention are decided inside one transaction per write, under the row lock of the
// kind's fill counter, so replicas never race on a read-modify-write. Every find() asks the database
// whether the id is stored (a delete through another replica is seen at once) and fetches the text
// only when asked: what is prepared from it stays in the replica's prepared cache
// (prepared_cache.hpp), which ids naming content keep from ever going stale.
#pragma once

#include "server/content_store.hpp"  // ContentStoreConfig: the budgets, retention and reader
#include "server/postgres_pool.hpp"

#include <memory>
#include <mutex>

namespace rr::server {

template <class T>
class PostgresStore : public DocumentStore<T> {
 public:
  using Base = DocumentStore<T>;
  using Clock = std::chrono::system_clock;  // as DocumentStore<T>::Clock
  using typename Base::Listed;
  using typename Base::Page;
  using typename Base::PutResult;
  using typename Base::ReleaseResult;
  using Log = std::function<void(const std::string& level, nlohmann::ordered_json fields)>;

  // Uses config's max_entries, max_bytes, ttl and kind ("scene", "mesh" or "texture"); data_dir, read, pinned
  // and on_change belong to the embedded store (pins live in the database here). Adds its
  // statements to `pool`.
  PostgresStore(std::shared_ptr<PostgresPool> pool, ContentStoreConfig<T> config, Log log);

  size_t load() override;
  PutResult put(const StoredDocument& document, const std::string& owner) override;
  std::optional<std::string> find(const std::string& id, bool with_text) override;
  ReleaseResult release(const std::string& id, const std::optional<std::string>& owner) override;
  Page list(const std::optional<std::string>& owner, size_t limit, const std::string& cursor) override;
  std::vector<std::string> pinned_by(const std::string& id, size_t most) override;
  std::optional<Clock::time_point> expiry_from_now() const override;
  CacheStats stats() override;
  size_t max_bytes() const override { return config_.max_bytes; }
  std::string unavailable_reason() override { return pool_->unavailable_reason(); }

 private:
  std::string statement(const char* name) const { return "rr_" + config_.kind + "_" + name; }
  void add_statements();
  PostgresParam ttl_param() const { return {std::to_string(config_.ttl.count())}; }
  // Deletes the entries whose retention ran out (and, for meshes and images, that no scene uses); at most
  // once a second unless forced. Inside the caller's transaction, which holds the fill row.
  void sweep(PostgresSession& session, bool force);
  PutResult put_locked(PostgresSession& session, const StoredDocument& document, const std::string& owner);
  ReleaseResult release_locked(PostgresSession& session, const std::string& id,
                               const std::optional<std::string>& owner);

  std::shared_ptr<PostgresPool> pool_;
  ContentStoreConfig<T> config_;
  Log log_;
  std::mutex stats_mutex_;
  CacheStats stats_;  // find()'s hits and misses
  std::mutex sweep_mutex_;
  std::chrono::steady_clock::time_point last_sweep_;
};

// The pool for `url` as the service configures it (pool size, timeout, Retry-After).
struct ServerConfig;
PostgresConfig postgres_config(const ServerConfig& config);

}  // namespace rr::server

// A bounded pool of PostgreSQL connections (libpq) for the shared store: statements are prepared
// once per connection and run with a deadline. A database that is down, slow or out of connections
// surfaces as StoreUnavailable (503 + Retry-After) within the deadline, never as a hung request; a
// connection that failed is dropped and a new one is opened on the next use, so the store comes back
// by itself when the database does. The schema is created or migrated once per process, on the first
// connection that works (migrations of several replicas are serialised by an advisory lock).
#pragma once

#include "server/document_store.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

struct pg_conn;

namespace rr::server {

struct PostgresConfig {
  std::string url;        // postgresql://user:password@host:port/db or key=value conninfo
  size_t pool_size = 8;   // connections open at most
  int timeout_ms = 2000;  // connect, wait for a free connection, and each statement
  int retry_after_s = 1;  // Retry-After with StoreUnavailable
};

// The database refused a statement (not a connection problem): the SQLSTATE says why.
class PostgresError : public std::runtime_error {
 public:
  PostgresError(const std::string& detail, std::string sqlstate)
      : std::runtime_error(detail), sqlstate_(std::move(sqlstate)) {}
  const std::string& sqlstate() const { return sqlstate_; }

 private:
  std::string sqlstate_;
};

// One statement's rows, as text (bytea comes back as PostgreSQL's hex text; see bytes_value).
struct PostgresRows {
  std::vector<std::vector<std::optional<std::string>>> rows;
  size_t size() const { return rows.size(); }
  const std::optional<std::string>& at(size_t row, size_t column) const { return rows.at(row).at(column); }
};

// A statement parameter: null, text, or raw bytes (sent in binary, so a bytea keeps every byte).
struct PostgresParam {
  std::optional<std::string> value;
  bool binary = false;
};

class PostgresPool;

// One leased connection, inside a transaction when begun with PostgresPool::transaction.
class PostgresSession {
 public:
  // Runs the named statement (PostgresPool::add_statement) with `params`.
  PostgresRows run(const std::string& name, const std::vector<PostgresParam>& params);

 private:
  friend class PostgresPool;
  PostgresRows exec(const std::string& sql);  // fixed text only: transaction control, migrations
  void prepare(const std::string& name, const std::string& sql);
  PostgresRows collect(bool sent);
  PostgresSession(PostgresPool& pool, pg_conn* conn, std::chrono::steady_clock::time_point deadline)
      : pool_(pool), conn_(conn), deadline_(deadline) {}
  PostgresPool& pool_;
  pg_conn* conn_;
  std::chrono::steady_clock::time_point deadline_;
};

class PostgresPool {
 public:
  using Log = std::function<void(const std::string& level, nlohmann::ordered_json fields)>;
  PostgresPool(PostgresConfig config, Log log);
  ~PostgresPool();
  PostgresPool(const PostgresPool&) = delete;
  PostgresPool& operator=(const PostgresPool&) = delete;

  // Statements by name, prepared on every connection as it opens (after the schema exists); add
  // them all before the first use.
  void add_statement(const std::string& name, const std::string& sql);
  // Runs `work` in one transaction (BEGIN ... COMMIT) on a pooled connection, all within the
  // timeout. A throw rolls the transaction back; StoreUnavailable also drops the connection.
  void transaction(const std::function<void(PostgresSession&)>& work);
  // Runs `work` outside a transaction (one statement commits by itself).
  void session(const std::function<void(PostgresSession&)>& work);
  // Empty when a connection answers a trivial query now, else why not.
  std::string unavailable_reason();
  // Creates or migrates the schema unless that was done; throws as a transaction does.
  void ensure_schema();
  const PostgresConfig& config() const { return config_; }

 private:
  friend class PostgresSession;
  pg_conn* connect(std::chrono::steady_clock::time_point deadline);
  void with_connection(bool in_transaction, const std::function<void(PostgresSession&)>& work);
  bool attempt(bool in_transaction, const std::function<void(PostgresSession&)>& work,
               std::chrono::steady_clock::time_point deadline, bool may_retry);
  void give_back(pg_conn* conn, bool keep);
  void note_health(bool ok, const std::string& why);
  void set_up(PostgresSession& session);
  [[noreturn]] void unavailable(const std::string& why) const;
  void migrate(PostgresSession& session);

  PostgresConfig config_;
  Log log_;
  std::mutex mutex_;
  std::condition_variable returned_;
  std::vector<pg_conn*> idle_;
  size_t open_ = 0;                                              // leased now; with idle_ never more than pool_size
  std::vector<std::pair<std::string, std::string>> statements_;  // name, sql; fixed once in use
  std::atomic<bool> schema_ready_{false};
  std::atomic<bool> healthy_{true};
  std::mutex schema_mutex_;
};

// Validates a store URL (or conninfo) without connecting; throws std::invalid_argument saying why.
void check_postgres_url(const std::string& url);
// A bytea column's text ("\x6869") -> its bytes.
std::string bytes_value(const std::string& hex_text);

}  // namespace rr::server

// PostgresPool (postgres_pool.hpp): libpq in non-blocking mode, so every wait (connect, send,
// result) is a poll() bounded by the operation's deadline; the server's statement_timeout bounds the
// work a dropped connection left running. The schema's migrations are the table at the top.
#include "server/postgres_pool.hpp"

#include <libpq-fe.h>
#include <poll.h>

#include <algorithm>

namespace rr::server {

namespace {

using SteadyClock = std::chrono::steady_clock;

// Schema version n is migrations[n - 1]; a database at version v gets the ones after v, in one
// transaction. Documents are bytea so a read returns the stored bytes exactly, whatever the
// database's encoding. rr_usage holds each kind's fill: every write locks its row, which serialises
// the budget check with the insert across replicas (no read-modify-write race).
const char* const migrations[] = {
    R"sql(
CREATE TABLE rr_meshes (id text PRIMARY KEY, body bytea NOT NULL, bytes bigint NOT NULL,
                        created_us bigint NOT NULL, last_access timestamptz NOT NULL);
CREATE TABLE rr_mesh_owners (id text NOT NULL REFERENCES rr_meshes ON DELETE CASCADE, owner text NOT NULL,
                             PRIMARY KEY (id, owner));
CREATE TABLE rr_scenes (id text PRIMARY KEY, body bytea NOT NULL, bytes bigint NOT NULL,
                        created_us bigint NOT NULL, last_access timestamptz NOT NULL);
CREATE TABLE rr_scene_owners (id text NOT NULL REFERENCES rr_scenes ON DELETE CASCADE, owner text NOT NULL,
                              PRIMARY KEY (id, owner));
CREATE INDEX rr_scenes_created ON rr_scenes (created_us DESC, id DESC);
CREATE INDEX rr_meshes_created ON rr_meshes (created_us DESC, id DESC);
CREATE TABLE rr_placements (scene_id text NOT NULL REFERENCES rr_scenes ON DELETE CASCADE,
                            mesh_id text NOT NULL REFERENCES rr_meshes, PRIMARY KEY (scene_id, mesh_id));
CREATE INDEX rr_placements_mesh ON rr_placements (mesh_id);
CREATE TABLE rr_usage (kind text PRIMARY KEY, entries bigint NOT NULL, bytes bigint NOT NULL,
                       last_created_us bigint NOT NULL);
INSERT INTO rr_usage VALUES ('scene', 0, 0, 0), ('mesh', 0, 0, 0);
)sql",
    // Stored images: the encoded PNG or JPEG bytes as the body, and the images scenes' textures name.
    R"sql(
CREATE TABLE rr_textures (id text PRIMARY KEY, body bytea NOT NULL, bytes bigint NOT NULL,
                          created_us bigint NOT NULL, last_access timestamptz NOT NULL);
CREATE TABLE rr_texture_owners (id text NOT NULL REFERENCES rr_textures ON DELETE CASCADE, owner text NOT NULL,
                                PRIMARY KEY (id, owner));
CREATE INDEX rr_textures_created ON rr_textures (created_us DESC, id DESC);
CREATE TABLE rr_texture_placements (scene_id text NOT NULL REFERENCES rr_scenes ON DELETE CASCADE,
                                    texture_id text NOT NULL REFERENCES rr_textures,
                                    PRIMARY KEY (scene_id, texture_id));
CREATE INDEX rr_texture_placements_texture ON rr_texture_placements (texture_id);
INSERT INTO rr_usage VALUES ('texture', 0, 0, 0);
)sql",
};

// SQLSTATE classes that mean "the database cannot answer now", not "this statement is wrong":
// connection exceptions, insufficient resources, operator intervention (shutdown, cancel, timeout),
// system errors, serialisation failures and deadlocks.
bool transient(const std::string& sqlstate) {
  for (const char* prefix : {"08", "53", "57", "58", "40"}) {
    if (sqlstate.starts_with(prefix)) return true;
  }
  return false;
}

// libpq's message on one line (it puts hints on lines of their own).
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\t') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

std::string error_text(pg_conn* conn) { return one_line(conn ? PQerrorMessage(conn) : "out of memory"); }

}  // namespace

void check_postgres_url(const std::string& url) {
  char* error = nullptr;
  PQconninfoOption* options = PQconninfoParse(url.c_str(), &error);
  if (!options) {
    std::string why = error ? error : "not a connection string";
    PQfreemem(error);
    while (!why.empty() && why.back() == '\n') why.pop_back();
    throw std::invalid_argument(why);
  }
  PQconninfoFree(options);
}

std::string bytes_value(const std::string& hex_text) {
  size_t length = 0;
  unsigned char* raw = PQunescapeBytea(reinterpret_cast<const unsigned char*>(hex_text.c_str()), &length);
  if (!raw) throw std::runtime_error("a bytea value did not decode");
  std::string out(reinterpret_cast<const char*>(raw), length);
  PQfreemem(raw);
  return out;
}

PostgresPool::PostgresPool(PostgresConfig config, Log log) : config_(std::move(config)), log_(std::move(log)) {}

PostgresPool::~PostgresPool() {
  for (pg_conn* conn : idle_) PQfinish(conn);
}

void PostgresPool::add_statement(const std::string& name, const std::string& sql) {
  statements_.emplace_back(name, sql);
}

void PostgresPool::unavailable(const std::string& why) const {
  throw StoreUnavailable("The shared store cannot answer now (" + why + "); retry shortly.", config_.retry_after_s);
}

namespace {

// Waits until the connection's socket is ready for `events` or the deadline passes.
bool wait_socket(pg_conn* conn, short events, SteadyClock::time_point deadline) {
  pollfd fd{PQsocket(conn), events, 0};
  for (;;) {
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now()).count();
    if (left <= 0) return false;
    int rc = ::poll(&fd, 1, int(std::min<long long>(left, 1000)));
    if (rc > 0) return true;
    if (rc < 0 && errno != EINTR) return false;
  }
}

}  // namespace

// Non-blocking connect, so a database host that does not answer costs the deadline, not the kernel's
// TCP timeout. statement_timeout bounds what the server keeps doing for a connection we dropped.
pg_conn* PostgresPool::connect(SteadyClock::time_point deadline) {
  const std::string options = "-c statement_timeout=" + std::to_string(config_.timeout_ms);
  const char* keys[] = {"dbname", "options", "application_name", nullptr};
  const char* values[] = {config_.url.c_str(), options.c_str(), "roomrender", nullptr};
  pg_conn* conn = PQconnectStartParams(keys, values, 1);
  if (!conn || PQstatus(conn) == CONNECTION_BAD) {
    std::string why = error_text(conn);
    PQfinish(conn);
    unavailable("cannot connect: " + why);
  }
  for (PostgresPollingStatusType state = PGRES_POLLING_WRITING;;) {
    if (state == PGRES_POLLING_OK) break;
    if (state == PGRES_POLLING_FAILED ||
        !wait_socket(conn, state == PGRES_POLLING_READING ? POLLIN : POLLOUT, deadline)) {
      std::string why = state == PGRES_POLLING_FAILED ? error_text(conn) : "connecting timed out";
      PQfinish(conn);
      unavailable("cannot connect: " + why);
    }
    state = PQconnectPoll(conn);
  }
  PQsetnonblocking(conn, 1);
  // The server's notices ("relation ... already exists, skipping") would go to stderr, beside the
  // service's JSON log lines.
  PQsetNoticeProcessor(
      conn, [](void*, const char*) {}, nullptr);
  return conn;
}

// Waits for every result of the statement just sent (within the deadline) and returns the rows of
// the last one; failures become StoreUnavailable (transient) or PostgresError (the statement).
PostgresRows PostgresSession::collect(bool sent) {
  if (!sent) pool_.unavailable(error_text(conn_));
  for (int flushed; (flushed = PQflush(conn_)) != 0;) {
    if (flushed < 0 || !wait_socket(conn_, POLLOUT, deadline_)) pool_.unavailable("sending a statement timed out");
  }
  PGresult* last = nullptr;
  for (;;) {
    while (PQisBusy(conn_)) {
      if (!wait_socket(conn_, POLLIN, deadline_) || !PQconsumeInput(conn_)) {
        PQclear(last);
        pool_.unavailable(PQstatus(conn_) == CONNECTION_OK
                              ? "the database did not answer within " + std::to_string(pool_.config_.timeout_ms) + " ms"
                              : error_text(conn_));
      }
    }
    PGresult* next = PQgetResult(conn_);
    if (!next) break;
    if (last && PQresultStatus(last) != PGRES_TUPLES_OK && PQresultStatus(last) != PGRES_COMMAND_OK) {
      PQclear(next);  // keep the first failure: it says why
      continue;
    }
    PQclear(last);
    last = next;
  }
  if (!last) pool_.unavailable(error_text(conn_));
  const ExecStatusType status = PQresultStatus(last);
  if (status != PGRES_TUPLES_OK && status != PGRES_COMMAND_OK) {
    const char* state = PQresultErrorField(last, PG_DIAG_SQLSTATE);
    std::string sqlstate = state ? state : "";
    std::string detail = one_line(PQresultErrorMessage(last));
    PQclear(last);
    if (PQstatus(conn_) != CONNECTION_OK || sqlstate.empty() || transient(sqlstate)) pool_.unavailable(detail);
    throw PostgresError(detail, sqlstate);
  }
  PostgresRows out;
  for (int r = 0; r < PQntuples(last); ++r) {
    std::vector<std::optional<std::string>> row;
    for (int c = 0; c < PQnfields(last); ++c) {
      if (PQgetisnull(last, r, c)) {
        row.emplace_back();
      } else {
        row.emplace_back(std::string(PQgetvalue(last, r, c), size_t(PQgetlength(last, r, c))));
      }
    }
    out.rows.push_back(std::move(row));
  }
  PQclear(last);
  return out;
}

PostgresRows PostgresSession::run(const std::string& name, const std::vector<PostgresParam>& params) {
  std::vector<const char*> values;
  std::vector<int> lengths, formats;
  for (const PostgresParam& p : params) {
    values.push_back(p.value ? p.value->data() : nullptr);
    lengths.push_back(p.value ? int(p.value->size()) : 0);
    formats.push_back(p.binary ? 1 : 0);
  }
  return collect(PQsendQueryPrepared(conn_, name.c_str(), int(params.size()), values.data(), lengths.data(),
                                     formats.data(), 0) == 1);
}

PostgresRows PostgresSession::exec(const std::string& sql) { return collect(PQsendQuery(conn_, sql.c_str()) == 1); }

void PostgresSession::prepare(const std::string& name, const std::string& sql) {
  collect(PQsendPrepare(conn_, name.c_str(), sql.c_str(), 0, nullptr) == 1);
}

// A connection that sat idle may have died with a database restart; a read, or a transaction whose
// BEGIN failed, has changed nothing, so it is tried once more on a new connection (and the other
// idle ones, likely dead too, are closed) instead of answering 503 for a database that is back.
void PostgresPool::with_connection(bool in_transaction, const std::function<void(PostgresSession&)>& work) {
  const SteadyClock::time_point deadline = SteadyClock::now() + std::chrono::milliseconds(config_.timeout_ms);
  bool may_retry = true;
  while (!attempt(in_transaction, work, deadline, may_retry)) {
    may_retry = false;
    std::lock_guard lock(mutex_);
    for (pg_conn* conn : idle_) PQfinish(conn);
    idle_.clear();
  }
}

// One try on a pooled (or new) connection; false when it should be retried on a new one.
bool PostgresPool::attempt(bool in_transaction, const std::function<void(PostgresSession&)>& work,
                           SteadyClock::time_point deadline, bool may_retry) {
  pg_conn* conn = nullptr;
  {
    std::unique_lock lock(mutex_);
    if (!returned_.wait_until(lock, deadline, [&] { return !idle_.empty() || open_ < config_.pool_size; })) {
      unavailable("all " + std::to_string(config_.pool_size) + " store connections are busy");
    }
    if (!idle_.empty()) {
      conn = idle_.back();
      idle_.pop_back();
    }
    ++open_;
  }
  const bool reused = conn != nullptr;
  bool keep = true, changed_nothing = true;
  try {
    if (!conn) {
      try {
        conn = connect(deadline);
        PostgresSession fresh(*this, conn, deadline);
        set_up(fresh);
      } catch (...) {
        keep = false;  // a connection without its statements is of no use
        throw;
      }
    }
    PostgresSession session(*this, conn, deadline);
    if (!in_transaction) {
      work(session);
    } else {
      session.exec("BEGIN");
      changed_nothing = false;
      try {
        work(session);
        session.exec("COMMIT");
      } catch (const StoreUnavailable&) {
        throw;
      } catch (...) {
        session.exec("ROLLBACK");
        throw;
      }
    }
  } catch (const StoreUnavailable& e) {
    const bool dead = conn && PQstatus(conn) == CONNECTION_BAD;
    give_back(conn, false);
    if (may_retry && reused && dead && changed_nothing && SteadyClock::now() < deadline) return false;
    note_health(false, e.what());
    throw;
  } catch (...) {
    give_back(conn, keep);
    throw;
  }
  give_back(conn, true);
  note_health(true, "");
  return true;
}

void PostgresPool::give_back(pg_conn* conn, bool keep) {
  if (!keep && conn) PQfinish(conn);
  std::lock_guard lock(mutex_);
  --open_;
  if (keep) idle_.push_back(conn);
  returned_.notify_one();
}

// One log line when the store stops answering and one when it answers again, not one per request.
void PostgresPool::note_health(bool ok, const std::string& why) {
  if (healthy_.exchange(ok) == ok) return;
  if (ok) {
    log_("info", {{"event", "store_available"}});
  } else {
    log_("warn", {{"event", "store_unavailable"}, {"reason", why}});
  }
}

void PostgresPool::transaction(const std::function<void(PostgresSession&)>& work) { with_connection(true, work); }

void PostgresPool::session(const std::function<void(PostgresSession&)>& work) { with_connection(false, work); }

std::string PostgresPool::unavailable_reason() {
  try {
    session([](PostgresSession& s) { s.run("rr_ping", {}); });
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

void PostgresPool::ensure_schema() {
  session([](PostgresSession&) {});  // a new connection migrates; an idle one exists only after that
}

// On a new connection: the schema (once per process), then every statement prepared.
void PostgresPool::set_up(PostgresSession& session) {
  if (!schema_ready_) {
    std::lock_guard lock(schema_mutex_);
    if (!schema_ready_) {
      migrate(session);
      schema_ready_ = true;
    }
  }
  session.prepare("rr_ping", "SELECT 1");
  for (const auto& [name, sql] : statements_) session.prepare(name, sql);
}

// Brings the schema to the newest version in one transaction; the advisory lock makes replicas
// that start together migrate one after another (the later ones then find nothing to do).
void PostgresPool::migrate(PostgresSession& session) {
  constexpr int newest = int(std::size(migrations));
  session.exec("BEGIN");
  try {
    session.exec("SELECT pg_advisory_xact_lock(7262531)");
    session.exec("CREATE TABLE IF NOT EXISTS rr_schema_version (version integer NOT NULL)");
    PostgresRows rows = session.exec("SELECT coalesce(max(version), 0) FROM rr_schema_version");
    const int found = std::stoi(rows.at(0, 0).value_or("0"));
    if (found > newest) {
      throw std::runtime_error("the store's schema is version " + std::to_string(found) + ", newer than this build's " +
                               std::to_string(newest));
    }
    for (int v = found; v < newest; ++v) {
      session.exec(migrations[v]);
      session.exec("INSERT INTO rr_schema_version VALUES (" + std::to_string(v + 1) + ")");
    }
    session.exec("COMMIT");
    if (found < newest) log_("info", {{"event", "store_schema_migrated"}, {"from", found}, {"to", newest}});
  } catch (const StoreUnavailable&) {
    throw;
  } catch (...) {
    session.exec("ROLLBACK");
    throw;
  }
}

}  // namespace rr::server

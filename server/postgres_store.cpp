// PostgresStore (postgres_store.hpp), instantiated for scenes, meshes and images at the end. Tables
// (schema in postgres_pool.cpp): rr_<plural> (id, body, bytes, created_us, last_access; an image's
// body is its encoded bytes), rr_<kind>_owners (id, owner), rr_placements (scene_id, mesh_id: pins
// a mesh), rr_texture_placements (scene_id, texture_id: pins an image), rr_usage (kind, entries, bytes,
// last_created_us: the fill, locked by every write of that kind).
#include "server/postgres_store.hpp"

#include "server/http_server.hpp"
#include "server/mesh_store.hpp"
#include "server/scene_store.hpp"
#include "server/texture_store.hpp"

#include <algorithm>
#include <charconv>
#include <limits>
#include <regex>

namespace rr::server {

namespace {

constexpr const char* pg_true = "t";

int64_t to_int(const std::optional<std::string>& text) { return text ? std::stoll(*text) : 0; }

// "<created_us>-<id>" of the last entry of the previous page (the embedded store's form).
std::pair<int64_t, std::string> parse_cursor(const std::string& cursor) {
  static const std::regex id_pattern("[0-9a-f]{16}");
  std::pair<int64_t, std::string> after;
  size_t dash = cursor.find('-');
  if (dash == std::string::npos) throw std::invalid_argument("not a cursor of this listing");
  auto [end, ec] = std::from_chars(cursor.data(), cursor.data() + dash, after.first);
  if (ec != std::errc() || end != cursor.data() + dash || !std::regex_match(cursor.substr(dash + 1), id_pattern)) {
    throw std::invalid_argument("not a cursor of this listing");
  }
  after.second = cursor.substr(dash + 1);
  return after;
}

// Ids (the stored meshes or images a scene uses) as a PostgreSQL array.
std::string references_array(const std::vector<std::string>& ids) {
  std::string out = "{";
  for (const std::string& id : ids) out += (out.size() > 1 ? "," : "") + id;  // hex ids: no quoting
  return out + "}";
}

// Where the stored scenes that pin an entry of `kind` are listed: table and column, or nullptr for
// a kind nothing pins (scenes).
struct Placements {
  const char* table;
  const char* column;
};
const Placements* placements_of(const std::string& kind) {
  static constexpr Placements meshes{"rr_placements", "mesh_id"}, textures{"rr_texture_placements", "texture_id"};
  if (kind == "mesh") return &meshes;
  if (kind == "texture") return &textures;
  return nullptr;
}

}  // namespace

PostgresConfig postgres_config(const ServerConfig& c) {
  return {c.store_url, c.store_pool_size, c.store_timeout_ms, c.retry_after_s};
}

template <class T>
PostgresStore<T>::PostgresStore(std::shared_ptr<PostgresPool> pool, ContentStoreConfig<T> config, Log log)
    : pool_(std::move(pool)), config_(std::move(config)), log_(std::move(log)) {
  add_statements();
}

template <class T>
void PostgresStore<T>::add_statements() {
  const std::string items = "rr_" + config_.plural, owners = "rr_" + config_.kind + "_owners";
  const std::string kind = "'" + config_.kind + "'";
  // $1 is the retention in seconds everywhere it appears; a mesh that a stored scene places, or an
  // image that its textures name, never expires.
  const Placements* pins = placements_of(config_.kind);
  std::string expired = "($1::float8 > 0 AND i.last_access < now() - make_interval(secs => $1::float8)";
  if (pins) {
    expired += " AND NOT EXISTS (SELECT 1 FROM " + std::string(pins->table) + " p WHERE p." + pins->column + " = i.id)";
  }
  expired += ")";
  auto add = [&](const char* name, const std::string& sql) { pool_->add_statement(statement(name), sql); };
  add("lock", "SELECT entries, bytes FROM rr_usage WHERE kind = " + kind + " FOR UPDATE");
  // SKIP LOCKED: an entry another transaction holds (a scene being stored that places this mesh)
  // is left for a later sweep rather than waited for or failed on.
  add("sweep",
      "WITH gone AS (DELETE FROM " + items + " WHERE id IN (SELECT i.id FROM " + items + " i WHERE " + expired +
          " FOR UPDATE SKIP LOCKED) RETURNING bytes) UPDATE rr_usage SET "
          "entries = entries - (SELECT count(*) FROM gone), bytes = bytes - (SELECT coalesce(sum(bytes), 0) FROM gone) "
          "WHERE kind = " +
          kind + " RETURNING entries, bytes, (SELECT count(*) FROM gone)");
  add("get", "SELECT i.body = $3::bytea, " + expired + " FROM " + items + " i WHERE i.id = $2 FOR UPDATE");
  add("touch", "UPDATE " + items + " SET last_access = now() WHERE id = $1");
  add("add_owner", "INSERT INTO " + owners + " (id, owner) VALUES ($1, $2) ON CONFLICT DO NOTHING");
  add("reserve",
      "UPDATE rr_usage SET entries = entries + 1, bytes = bytes + $1::bigint, last_created_us = "
      "GREATEST(last_created_us + 1, (extract(epoch FROM clock_timestamp()) * 1000000)::bigint) WHERE kind = " +
          kind + " RETURNING last_created_us");
  add("insert", "INSERT INTO " + items + " (id, body, bytes, created_us, last_access) VALUES ($1, $2, $3, $4, now())");
  add("place", "INSERT INTO rr_placements (scene_id, mesh_id) SELECT $1, unnest($2::text[])");
  add("place_textures", "INSERT INTO rr_texture_placements (scene_id, texture_id) SELECT $1, unnest($2::text[])");
  // A read restarts the retention clock, written at most every $3 seconds (not on every read).
  add("find", "WITH touched AS (UPDATE " + items +
                  " i SET last_access = now() WHERE i.id = $2 AND $1::float8 > 0 AND "
                  "i.last_access < now() - make_interval(secs => $3::float8) AND NOT " +
                  expired +
                  " RETURNING 1) "
                  "SELECT CASE WHEN $4::boolean THEN i.body END FROM " +
                  items + " i WHERE i.id = $2 AND NOT " + expired);
  add("owners", "SELECT owner FROM " + owners + " WHERE id = $1");
  add("drop_owner", "DELETE FROM " + owners + " WHERE id = $1 AND owner = $2");
  add("remove", "WITH gone AS (DELETE FROM " + items +
                    " WHERE id = $1 RETURNING bytes) UPDATE rr_usage SET "
                    "entries = entries - 1, bytes = bytes - (SELECT bytes FROM gone) WHERE kind = " +
                    kind + " AND EXISTS (SELECT 1 FROM gone)");
  if (pins) {
    add("pinned_by", "SELECT scene_id FROM " + std::string(pins->table) + " WHERE " + pins->column +
                         " = $1 ORDER BY scene_id LIMIT $2::bigint");
  }
  add("list", "SELECT i.id, i.created_us, (extract(epoch FROM i.last_access) * 1000000)::bigint, i.bytes FROM " +
                  items + " i WHERE NOT " + expired + " AND ($2::text IS NULL OR EXISTS (SELECT 1 FROM " + owners +
                  " o WHERE o.id = i.id AND o.owner = $2)) AND ($3::bigint IS NULL OR (i.created_us, i.id) < "
                  "($3::bigint, $4::text)) "
                  "ORDER BY i.created_us DESC, i.id DESC LIMIT $5::bigint");
  add("usage", "SELECT entries, bytes FROM rr_usage WHERE kind = " + kind);
}

template <class T>
size_t PostgresStore<T>::load() {
  try {
    pool_->ensure_schema();
  } catch (const std::exception& e) {  // served as 503 until the database answers; readiness says so
    log_("warn", {{"event", "store_unavailable"}, {"kind", config_.kind}, {"reason", e.what()}});
  }
  return 0;
}

template <class T>
void PostgresStore<T>::sweep(PostgresSession& session, bool force) {
  if (config_.ttl.count() == 0) return;
  {
    std::lock_guard lock(sweep_mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (!force && now - last_sweep_ < std::chrono::seconds(1)) return;
    last_sweep_ = now;
  }
  PostgresRows rows = session.run(statement("sweep"), {ttl_param()});
  if (const int64_t gone = to_int(rows.at(0, 2)); gone > 0) {
    log_("info", {{"event", config_.kind + "_expired"}, {"count", gone}});
  }
}

template <class T>
typename PostgresStore<T>::PutResult PostgresStore<T>::put_locked(PostgresSession& s, const StoredDocument& item,
                                                                  const std::string& owner) {
  const PostgresParam id{item.id}, body{item.text, true};
  const size_t bytes = item.bytes();
  // Storing what is stored needs only its row's lock; the fill row (which serialises every new
  // entry of this kind) is taken only to add one.
  PostgresRows held = s.run(statement("get"), {ttl_param(), id, body});
  if (held.size() == 0 || held.at(0, 1) == pg_true) {
    s.run(statement("lock"), {});
    sweep(s, false);
    held = s.run(statement("get"), {ttl_param(), id, body});  // stored meanwhile by another replica?
  }
  if (held.size() == 1 && held.at(0, 1) == pg_true) {  // gone, though not swept yet
    sweep(s, true);
    held = s.run(statement("get"), {ttl_param(), id, body});
  }
  if (held.size() == 1) {
    if (held.at(0, 0) != pg_true) return PutResult::conflict;
    s.run(statement("touch"), {id});
    s.run(statement("add_owner"), {id, {owner}});
    return PutResult::existed;
  }
  if (bytes > config_.max_bytes) return PutResult::too_large;
  PostgresRows fill = s.run(statement("usage"), {});
  auto fits = [&] {
    return size_t(to_int(fill.at(0, 0))) < config_.max_entries &&
           size_t(to_int(fill.at(0, 1))) + bytes <= config_.max_bytes;
  };
  if (!fits()) {
    sweep(s, true);
    fill = s.run(statement("usage"), {});
    if (!fits()) return PutResult::full;
  }
  PostgresRows created = s.run(statement("reserve"), {{std::to_string(bytes)}});
  s.run(statement("insert"), {id, body, {std::to_string(bytes)}, PostgresParam{created.at(0, 0)}});
  s.run(statement("add_owner"), {id, {owner}});
  for (const auto& [refs, place] : {std::pair{&item.refs, "place"}, std::pair{&item.texture_refs, "place_textures"}}) {
    if (refs->empty()) continue;
    try {
      s.run(statement(place), {id, {references_array(*refs)}});
    } catch (const PostgresError& e) {
      if (e.sqlstate() != "23503") throw;   // a foreign key: a mesh or image it uses was deleted meanwhile
      return PutResult::missing_reference;  // the commit that follows rolls the aborted transaction back
    }
  }
  return PutResult::created;
}

template <class T>
typename PostgresStore<T>::PutResult PostgresStore<T>::put(const StoredDocument& document, const std::string& owner) {
  PutResult result = PutResult::full;
  pool_->transaction([&](PostgresSession& s) { result = put_locked(s, document, owner); });
  return result;
}

template <class T>
std::optional<std::string> PostgresStore<T>::find(const std::string& id, bool with_text) {
  const double touch_every = std::min(60.0, double(config_.ttl.count()) / 8.0);
  PostgresRows rows;
  pool_->session([&](PostgresSession& s) {
    rows = s.run(statement("find"), {ttl_param(), {id}, {std::to_string(touch_every)}, {with_text ? "true" : "false"}});
  });
  {
    std::lock_guard lock(stats_mutex_);
    ++(rows.size() > 0 ? stats_.hits : stats_.misses);
  }
  if (rows.size() == 0) return std::nullopt;
  return with_text ? bytes_value(rows.at(0, 0).value_or("")) : std::string();
}

template <class T>
typename PostgresStore<T>::ReleaseResult PostgresStore<T>::release_locked(PostgresSession& s, const std::string& id,
                                                                          const std::optional<std::string>& owner) {
  s.run(statement("lock"), {});
  sweep(s, false);
  PostgresRows held = s.run(statement("get"), {ttl_param(), {id}, {std::string()}});
  if (held.size() == 0 || held.at(0, 1) == pg_true) return ReleaseResult::not_found;
  if (owner) {
    PostgresRows owners = s.run(statement("owners"), {{id}});
    auto holds =
        std::any_of(owners.rows.begin(), owners.rows.end(), [&](const auto& row) { return row.at(0) == *owner; });
    if (!holds) return ReleaseResult::not_owner;
    if (owners.size() > 1) {
      s.run(statement("drop_owner"), {{id}, {*owner}});
      return ReleaseResult::reference_dropped;
    }
  }
  if (placements_of(config_.kind) && s.run(statement("pinned_by"), {{id}, {"1"}}).size() > 0) {
    return ReleaseResult::pinned;
  }
  s.run(statement("remove"), {{id}});
  return ReleaseResult::removed;
}

template <class T>
typename PostgresStore<T>::ReleaseResult PostgresStore<T>::release(const std::string& id,
                                                                   const std::optional<std::string>& owner) {
  ReleaseResult result = ReleaseResult::not_found;
  pool_->transaction([&](PostgresSession& s) { result = release_locked(s, id, owner); });
  return result;
}

template <class T>
typename PostgresStore<T>::Page PostgresStore<T>::list(const std::optional<std::string>& owner, size_t limit,
                                                       const std::string& cursor) {
  PostgresParam after_us, after_id;
  if (!cursor.empty()) {
    auto [us, id] = parse_cursor(cursor);
    after_us.value = std::to_string(us);
    after_id.value = id;
  }
  PostgresRows rows;
  pool_->session([&](PostgresSession& s) {
    rows = s.run(statement("list"), {ttl_param(), {owner}, after_us, after_id, {std::to_string(limit + 1)}});
  });
  Page page;
  for (const auto& row : rows.rows) {
    Listed entry{row.at(0).value_or(""), to_int(row.at(1)), std::nullopt, size_t(to_int(row.at(3)))};
    if (config_.ttl.count() > 0) {
      entry.expires = Clock::time_point(std::chrono::microseconds(to_int(row.at(2)))) + config_.ttl;
    }
    page.scenes.push_back(std::move(entry));
  }
  if (page.scenes.size() > limit) {
    page.scenes.resize(limit);
    page.next_cursor = std::to_string(page.scenes.back().created_us) + "-" + page.scenes.back().id;
  }
  return page;
}

template <class T>
std::vector<std::string> PostgresStore<T>::pinned_by(const std::string& id, size_t most) {
  std::vector<std::string> out;
  if (!placements_of(config_.kind)) return out;
  pool_->session([&](PostgresSession& s) {
    for (const auto& row : s.run(statement("pinned_by"), {{id}, {std::to_string(most)}}).rows) {
      out.push_back(row.at(0).value_or(""));
    }
  });
  return out;
}

template <class T>
std::optional<std::chrono::system_clock::time_point> PostgresStore<T>::expiry_from_now() const {
  if (config_.ttl.count() == 0) return std::nullopt;
  return Clock::now() + config_.ttl;
}

// The fill as the database holds it; while it cannot answer, the budgets and the hit counts alone
// (metrics must not fail with the store).
template <class T>
CacheStats PostgresStore<T>::stats() {
  CacheStats out;
  {
    std::lock_guard lock(stats_mutex_);
    out = stats_;
  }
  out.budget_bytes = config_.max_bytes;
  out.max_entries = config_.max_entries;
  try {
    pool_->session([&](PostgresSession& s) {
      PostgresRows fill = s.run(statement("usage"), {});
      out.entries = size_t(to_int(fill.at(0, 0)));
      out.bytes = size_t(to_int(fill.at(0, 1)));
    });
  } catch (const StoreUnavailable&) {
  }
  return out;
}

template class PostgresStore<StoredScene>;
template class PostgresStore<StoredMesh>;
template class PostgresStore<StoredTexture>;

}  // namespace rr::server

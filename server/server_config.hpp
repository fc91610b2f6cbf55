// The service's configuration: ServerConfig (every setting, its default as the member's
// initializer), what its 0 / -1 defaults resolve to on this machine, and the effective configuration
// as JSON. Flags and variables reach it through the settings table (server/settings.hpp).
#pragma once

#include "render/scene_io/scene_json.hpp"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace rr::server {

// Every setting of `roomrender serve`. A member's initializer is its default; the settings table
// (server/settings.hpp) gives each settable member its flag and ROOMRENDER_* variable, and shows
// that default in `serve --help` and docs/api.md. Sizes in bytes, times as named.
struct ServerConfig {
  std::string bind = "127.0.0.1";
  int port = 8080;                 // 0: any free port, reported by Service::port()
  int threads = 0;                 // request worker threads; 0: render_workers + render_queue + 8 (see request_workers)
  int render_workers = 0;          // renders running at once; 0: the number of cores
  int render_threads = 0;          // threads drawing one render's tiles; 0: the number of cores
  int render_queue = -1;           // renders waiting for a slot; -1: 4 per render worker
  int render_timeout_ms = 10'000;  // deadline per render, counted from arrival at the gate
  int retry_after_s = 1;           // Retry-After sent with 503
  int drain_timeout_ms = 10'000;   // on SIGTERM: how long in-flight renders may still run
  // After a render slot's work ran at least this long, free heap pages go back to the OS
  // (malloc_trim); -1: never. Short renders skip it: they free little and the walk is not free.
  int trim_after_work_ms = 100;
  std::filesystem::path web_dir;        // holds index.html, served at GET /
  std::filesystem::path examples_dir;   // holds <name>.json, served under /examples/
  std::filesystem::path schemas_dir;    // holds *.schema.json and openapi.json
  std::filesystem::path catalogue_dir;  // holds catalogue.json, models/ and icons/ (GET /v1/catalogue)
  std::filesystem::path data_dir;       // stored scenes and meshes persist here; empty: memory only
  size_t max_body_bytes = 8u << 20;     // larger bodies get 413 before they are read
  size_t max_import_bytes = 64u << 20;  // POST /v1/import/{format}: files of other tools (an OBJ interior)
  ParseLimits limits;                   // JSON depth, image size, polygons, ... (render/scene_io/scene_json.hpp)
  // The prepared cache (server/prepared_cache.hpp): what is prepared from stored documents and for
  // static scenes (prepared scenes, parsed meshes, BSP trees, shadow maps), one LRU within this.
  size_t cache_bytes = size_t{4} << 30;
  size_t bsp_cache_entries = 1024;         // BSP trees in it at most
  size_t shadow_cache_bytes = 256u << 20;  // its part that shadow maps may take; 0: none are kept
  // The document stores (server/document_store.hpp): what is acknowledged, budgeted by document
  // bytes (the canonical text; on disk with data_dir, in memory without).
  size_t scene_store_bytes = size_t{4} << 30;
  size_t scene_store_entries = 100'000;
  int scene_ttl_s = 0;                        // stored scenes go this long after their last access; 0: kept
  size_t mesh_store_bytes = size_t{4} << 30;  // stored meshes (POST /v1/meshes); their ttl is scene_ttl_s
  size_t mesh_store_entries = 100'000;
  size_t texture_store_bytes = size_t{4} << 30;  // stored images (POST /v1/textures), their encoded bytes
  size_t texture_store_entries = 100'000;
  // The shared store (server/postgres_store.hpp): stored scenes and meshes in PostgreSQL, so any
  // replica answers any stored id. Empty: the embedded store (memory, and data_dir when given).
  std::string store_url;        // postgresql://user:password@host:port/database
  size_t store_pool_size = 8;   // database connections per replica
  int store_timeout_ms = 2000;  // connect, wait for a connection, each statement; then 503
  // Access (server/access.hpp). Reads are open to every origin; writes come from these origins (or
  // the server's own pages) only, and need a bearer token from this file when one is given.
  std::vector<std::string> cors_origins;
  std::filesystem::path api_token_file;  // empty: writes are open to anyone who reaches the port
  bool allow_listing = false;            // GET /v1/scenes on a server without tokens
  // Connections (server/connection_front.hpp). Deadlines are totals, not per read: a client that
  // sends one byte at a time gets no more time than one that sends nothing.
  size_t max_connections = 4096;      // beyond: close the oldest idle, else the oldest unfinished head, else 503
  size_t max_idle_connections = 512;  // idle keep-alive connections kept; beyond: the oldest is closed
  int keep_alive_timeout_s = 5;       // an idle keep-alive connection is closed after this
  size_t keep_alive_max_requests = 100;
  int header_timeout_ms = 10'000;         // the whole request head, from accept or from its first byte; then 408
  int body_timeout_ms = 20'000;           // the whole body: this plus Content-Length / min_transfer_rate; then 408
  size_t min_body_rate = 500;             // ... but only 1 s more per this many bytes received; 0: no minimum
  int write_timeout_s = 10;               // the whole answer: this plus its size / min_transfer_rate; then closed
  size_t min_transfer_rate = 256u << 10;  // bytes per second granted on top of the body and write timeouts
  size_t max_request_line_bytes = 8190;   // longer: 414; also the cap on one header line (431); httplib's limit
  size_t max_header_bytes = 64u << 10;    // the whole head; larger: 431
  size_t max_header_count = 100;          // more header fields: 431
  int max_pending_requests = -1;          // complete requests waiting for a worker; -1: request_workers
  size_t max_buffered_body_bytes = 512u << 20;  // bodies being received at once; beyond: 503
  int listen_backlog = 1024;
  bool log_requests = true;        // one JSON line per request (level info)
  std::string log_level = "info";  // info, warn, error or off
  // Where log lines go (one JSON object per line, no newline); null: stderr. Tests capture them.
  std::function<void(const std::string& line)> log_sink;
  // Called on the render's thread once it holds a render slot, before any work. A seam for tests
  // that must hold slots deterministically; null in the service.
  std::function<void()> on_render_admitted;
};

// The defaults above, with web_dir, examples_dir and schemas_dir pointing into the source tree.
ServerConfig default_server_config();

// What the 0 / -1 defaults resolve to.
size_t render_workers(const ServerConfig& config);
unsigned render_threads(const ServerConfig& config);
size_t render_queue_length(const ServerConfig& config);
size_t request_workers(const ServerConfig& config);
size_t max_pending_requests(const ServerConfig& config);

// The effective configuration as one JSON object (printed once at start): every setting under its
// flag's name (settings.hpp), 0 / -1 defaults resolved, then the parse limits no flag sets.
std::string config_json(const ServerConfig& config);

}  // namespace rr::server

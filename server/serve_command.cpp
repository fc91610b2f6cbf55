// `roomrender serve`: the settings table (flag, ROOMRENDER_* variable, meaning, default), the
// configuration built from it, and the process life cycle: print the configuration once, serve until
// SIGTERM or SIGINT, drain, exit 0. Declared in cli.hpp.
#include "server/serve_command.hpp"

#include "server/open_stores.hpp"

#include <nlohmann/json.hpp>

#include <pthread.h>

#if defined(__GLIBC__)
#include <malloc.h>  // mallopt
#endif

#include <algorithm>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <thread>
#include <vector>

namespace rr::server {

#ifndef ROOMRENDER_VERSION
#define ROOMRENDER_VERSION "0.0.0"
#endif

std::string_view version() { return ROOMRENDER_VERSION; }

namespace {

using Apply = void (*)(ServerConfig& config, const std::string& value, const std::string& source);

struct Setting {
  const char* flag;  // "--port"; the variable is ROOMRENDER_PORT
  const char* help;
  Apply apply;
};

long long parse_integer(const std::string& text, const std::string& what, long long lo, long long hi) {
  long long value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || value < lo || value > hi) {
    throw UsageError(what + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], not '" +
                     text + "'");
  }
  return value;
}

// "https://a.example, http://localhost:5173" -> each origin as a browser sends it (scheme://host[:port]).
std::vector<std::string> parse_origins(const std::string& text, const std::string& what) {
  std::vector<std::string> origins;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = std::min(text.find(',', begin), text.size());
    std::string origin = text.substr(begin, end - begin);
    origin.erase(0, origin.find_first_not_of(' '));
    origin.erase(origin.find_last_not_of(' ') + 1);
    begin = end + 1;
    if (origin.empty()) continue;
    size_t scheme = origin.find("://");
    if (origin != "*" && (scheme == std::string::npos || scheme == 0 || origin.size() == scheme + 3 ||
                          origin.find('/', scheme + 3) != std::string::npos)) {
      throw UsageError(what + ": '" + origin + "' is not an origin (scheme://host[:port], no path) or *");
    }
    origins.push_back(origin);
  }
  return origins;
}

constexpr long long int_max = std::numeric_limits<int>::max();
constexpr long long big = 1LL << 40;  // a byte or count limit beyond any sensible value

// clang-format off
const Setting settings[] = {
  {"--port", "TCP port; 0 picks a free one (default 8080)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.port = int(parse_integer(v, s, 0, 65535)); }},
  {"--bind", "address to listen on (default 127.0.0.1; 0.0.0.0 for every interface)",
   [](ServerConfig& c, const std::string& v, const std::string&) { c.bind = v; }},
  {"--threads", "request worker threads; 0: render-workers + render-queue + 8 (default 0)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.threads = int(parse_integer(v, s, 0, 1024)); }},
  {"--render-workers", "renders running at once; 0: one per core (default 0)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.render_workers = int(parse_integer(v, s, 0, 256)); }},
  {"--render-threads", "threads drawing one render's screen tiles; 0: one per core (default 0)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.render_threads = int(parse_integer(v, s, 0, 64)); }},
  {"--render-queue", "renders waiting for a slot before 503; -1: 4 per worker (default -1)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.render_queue = int(parse_integer(v, s, -1, 4096)); }},
  {"--render-timeout-ms", "deadline per render from arrival, then 503/504 (default 10000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.render_timeout_ms = int(parse_integer(v, s, 1, int_max)); }},
  {"--retry-after", "seconds in Retry-After with 503 (default 1)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.retry_after_s = int(parse_integer(v, s, 0, 3600)); }},
  {"--drain-timeout-ms", "on SIGTERM, how long in-flight renders may finish (default 10000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.drain_timeout_ms = int(parse_integer(v, s, 0, int_max)); }},
  {"--trim-after-ms", "after a render that worked this long, return free heap to the OS; -1: never (default 100)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.trim_after_work_ms = int(parse_integer(v, s, -1, int_max)); }},
  {"--max-body-bytes", "largest request body (default 8388608)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_body_bytes = size_t(parse_integer(v, s, 1, big)); }},
  {"--max-import-bytes", "largest file POSTed to /v1/import/{format} (default 67108864)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_import_bytes = size_t(parse_integer(v, s, 1, big)); }},
  {"--max-json-depth", "deepest JSON nesting (default 64)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.limits.max_depth = size_t(parse_integer(v, s, 4, 10000)); }},
  {"--max-image-side", "largest width or height in pixels (default 4096)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.limits.max_image_side = int(parse_integer(v, s, 1, 65536)); }},
  {"--max-pixels", "largest width * height (default 16800000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.limits.max_pixels = parse_integer(v, s, 1, big); }},
  {"--max-render-bytes", "a frame's buffer memory, the A-buffer of options.antialias included (default 536870912)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.limits.max_render_bytes = parse_integer(v, s, 1, big); }},
  {"--max-polygons", "most polygons after tessellation (default 2000000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.limits.max_polygons = size_t(parse_integer(v, s, 1, big)); }},
  {"--bsp-cache-bytes", "BSP tree cache budget (default 268435456)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.bsp_cache_bytes = size_t(parse_integer(v, s, 0, big)); }},
  {"--bsp-cache-entries", "most BSP trees cached (default 1024)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.bsp_cache_entries = size_t(parse_integer(v, s, 0, big)); }},
  {"--shadow-cache-bytes", "shadow map cache budget (default 268435456; 0 keeps none)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.shadow_cache_bytes = size_t(parse_integer(v, s, 0, big)); }},
  {"--scene-store-bytes", "stored scenes budget (default 268435456)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.scene_store_bytes = size_t(parse_integer(v, s, 0, big)); }},
  {"--scene-store-entries", "most stored scenes (default 1000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.scene_store_entries = size_t(parse_integer(v, s, 0, big)); }},
  {"--scene-ttl", "seconds a stored scene is kept after its last access; 0: until deleted (default 0)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.scene_ttl_s = int(parse_integer(v, s, 0, int_max)); }},
  {"--mesh-store-bytes", "stored meshes budget (default 536870912)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.mesh_store_bytes = size_t(parse_integer(v, s, 0, big)); }},
  {"--mesh-store-entries", "most stored meshes (default 10000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.mesh_store_entries = size_t(parse_integer(v, s, 0, big)); }},
  {"--cors-origins", "comma-separated origins (https://app.example.com) whose pages may write; * for any (default: none)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.cors_origins = parse_origins(v, s); }},
  {"--api-token-file", "file of bearer tokens, one per line as name:token; writes then need one (default: none, writes open)",
   [](ServerConfig& c, const std::string& v, const std::string&) { c.api_token_file = v; }},
  {"--allow-listing", "1: GET /v1/scenes lists every stored scene on a server without tokens (default 0)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.allow_listing = parse_integer(v, s, 0, 1) == 1; }},
  {"--store", "postgresql://user:password@host:port/db: stored scenes and meshes in PostgreSQL, shared by every replica (default: embedded, in memory and --data-dir)",
   [](ServerConfig& c, const std::string& v, const std::string& s) {
     try {
       check_store_url(v);
     } catch (const std::invalid_argument& e) {
       throw UsageError(s + " " + e.what());
     }
     c.store_url = v;
   }},
  {"--store-pool", "connections to the --store database per replica (default 8)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.store_pool_size = size_t(parse_integer(v, s, 1, 1000)); }},
  {"--store-timeout-ms", "connect, wait for a connection and run each store statement within this, then 503 (default 2000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.store_timeout_ms = int(parse_integer(v, s, 1, 3'600'000)); }},
  {"--store-cache-bytes", "parsed stored scenes and meshes kept per replica with --store (default 67108864)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.store_cache_bytes = size_t(parse_integer(v, s, 0, big)); }},
  {"--data-dir", "directory where stored scenes and meshes persist (default: none, memory only)",
   [](ServerConfig& c, const std::string& v, const std::string&) { c.data_dir = v; }},
  {"--web-dir", "directory holding index.html (default: the source tree's clients/web)",
   [](ServerConfig& c, const std::string& v, const std::string&) { c.web_dir = v; }},
  {"--examples-dir", "directory of example requests (default: the source tree's examples)",
   [](ServerConfig& c, const std::string& v, const std::string&) { c.examples_dir = v; }},
  {"--schemas-dir", "directory of JSON Schemas and openapi.json (default: the source tree's schemas)",
   [](ServerConfig& c, const std::string& v, const std::string&) { c.schemas_dir = v; }},
  {"--max-connections", "open client connections; when full the oldest idle one, else the oldest unfinished head, is closed (default 4096)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_connections = size_t(parse_integer(v, s, 1, 1000000)); }},
  {"--max-idle-connections", "idle keep-alive connections kept; beyond, the oldest is closed (default 512)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_idle_connections = size_t(parse_integer(v, s, 0, 1000000)); }},
  {"--keep-alive-timeout", "seconds an idle keep-alive connection is kept (default 5)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.keep_alive_timeout_s = int(parse_integer(v, s, 0, 3600)); }},
  {"--keep-alive-max", "requests per connection (default 100)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.keep_alive_max_requests = size_t(parse_integer(v, s, 1, 1000000)); }},
  {"--header-timeout-ms", "the whole request head must arrive within this, then 408 (default 10000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.header_timeout_ms = int(parse_integer(v, s, 1, 3'600'000)); }},
  {"--body-timeout-ms", "the whole body must arrive within this plus its length / min-transfer-rate, then 408 (default 20000)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.body_timeout_ms = int(parse_integer(v, s, 1, 3'600'000)); }},
  {"--write-timeout", "seconds to write a whole answer, plus its size / min-transfer-rate (default 10)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.write_timeout_s = int(parse_integer(v, s, 1, 3600)); }},
  {"--min-transfer-rate", "bytes per second granted to bodies and answers on top of their timeouts (default 262144)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.min_transfer_rate = size_t(parse_integer(v, s, 1, big)); }},
  {"--max-request-line-bytes", "longest request line (414) and header line (431) (default 8192)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_request_line_bytes = size_t(parse_integer(v, s, 64, 1 << 20)); }},
  {"--max-header-bytes", "largest request head, then 431 (default 65536)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_header_bytes = size_t(parse_integer(v, s, 256, 16 << 20)); }},
  {"--max-header-count", "most header fields in a request, then 431 (default 100)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_header_count = size_t(parse_integer(v, s, 1, 100000)); }},
  {"--max-pending-requests", "complete requests waiting for a worker before 503; -1: one per worker (default -1)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_pending_requests = int(parse_integer(v, s, -1, 1000000)); }},
  {"--max-buffered-body-bytes", "request bodies being received at once, then 503 (default 536870912)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.max_buffered_body_bytes = size_t(parse_integer(v, s, 1, big)); }},
  {"--listen-backlog", "pending connections the kernel queues (default 1024)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.listen_backlog = int(parse_integer(v, s, 1, 65535)); }},
  {"--log-level", "info, warn, error or off (default info)",
   [](ServerConfig& c, const std::string& v, const std::string& s) {
     if (v != "info" && v != "warn" && v != "error" && v != "off") throw UsageError(s + " must be info, warn, error or off, not '" + v + "'");
     c.log_level = v;
   }},
  {"--log-requests", "1: one JSON line per request at level info; 0: none (default 1)",
   [](ServerConfig& c, const std::string& v, const std::string& s) { c.log_requests = parse_integer(v, s, 0, 1) == 1; }},
};
// clang-format on

// "--render-queue" -> "ROOMRENDER_RENDER_QUEUE".
std::string variable_for(std::string_view flag) {
  std::string name = "ROOMRENDER_";
  for (char c : flag.substr(2)) name += c == '-' ? '_' : char(std::toupper(static_cast<unsigned char>(c)));
  return name;
}

const Setting* find_setting(std::string_view flag) {
  for (const Setting& s : settings) {
    if (flag == s.flag) return &s;
  }
  return nullptr;
}

// `--name VALUE` and `--name=VALUE`; every flag takes a value and may appear once.
std::map<std::string, std::string> parse_serve_flags(std::span<const std::string> args) {
  std::map<std::string, std::string> flags;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string name = args[i], value;
    if (!name.starts_with("--")) throw UsageError("unexpected argument " + name);
    if (size_t eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name.resize(eq);
    } else if (i + 1 < args.size()) {
      value = args[++i];
    } else {
      throw UsageError(name + " needs a value");
    }
    if (!find_setting(name)) throw UsageError("unknown option " + name);
    if (!flags.emplace(name, value).second) throw UsageError(name + " given twice");
  }
  return flags;
}

void print_json_line(std::FILE* stream, const nlohmann::ordered_json& line) {
  std::string text = line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  std::fwrite(text.data(), 1, text.size(), stream);
  std::fflush(stream);
}

}  // namespace

std::string serve_usage() {
  std::string text =
      "usage: roomrender serve [OPTIONS]\n\nEvery option may also come from the variable named "
      "after it (--render-queue: ROOMRENDER_RENDER_QUEUE); flags win.\n\n";
  for (const Setting& s : settings) {
    std::string flag = std::string(s.flag) + " VALUE";
    flag.resize(std::max<size_t>(flag.size() + 1, 26), ' ');
    text += "  " + flag + s.help + "\n";
  }
  return text;
}

ServerConfig serve_config_from(std::span<const std::string> argv,
                               const std::function<std::optional<std::string>(const char*)>& getenv) {
  std::map<std::string, std::string> flags = parse_serve_flags(argv);
  ServerConfig config = default_server_config();
  for (const Setting& s : settings) {
    if (auto it = flags.find(s.flag); it != flags.end()) {
      s.apply(config, it->second, s.flag);
    } else if (std::string variable = variable_for(s.flag); auto value = getenv(variable.c_str())) {
      s.apply(config, *value, variable);
    }
  }
  return config;
}

// glibc gives threads up to 8 malloc arenas per core, and malloc_trim cannot return the free top of
// an arena other than the main one: after large requests parsed on 18 worker threads, each arena
// kept 4-8 MiB (+190 MiB in all). One arena per core bounds that; renders measured no slower
// (docs/api.md, "Connections"). MALLOC_ARENA_MAX in the environment still decides when set.
void limit_malloc_arenas() {
#if defined(__GLIBC__)
  if (std::getenv("MALLOC_ARENA_MAX")) return;
  mallopt(M_ARENA_MAX, int(std::max(2u, std::thread::hardware_concurrency())));
#endif
}

int run_serve(std::span<const std::string> argv) {
  if (std::find(argv.begin(), argv.end(), "--help") != argv.end() ||
      std::find(argv.begin(), argv.end(), "-h") != argv.end()) {
    std::fputs(serve_usage().c_str(), stdout);
    return 0;
  }
  ServerConfig config;
  try {
    config = serve_config_from(argv, [](const char* name) -> std::optional<std::string> {
      const char* value = std::getenv(name);
      return value ? std::optional<std::string>(value) : std::nullopt;
    });
  } catch (const UsageError& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", nullptr}, {"usage", "roomrender serve --help"}});
    return 2;
  }
  try {
    // Block the stop signals before any thread starts, so every thread inherits the mask and
    // sigwait below is the only place they arrive.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
    std::signal(SIGPIPE, SIG_IGN);  // a client that hangs up must not end the process
    limit_malloc_arenas();
    Service service(config);
    service.start();
    nlohmann::ordered_json line = {{"event", "listening"},
                                   {"port", service.port()},
                                   {"url", "http://" + config.bind + ":" + std::to_string(service.port()) + "/"},
                                   {"version", version()}};
    line["config"] = nlohmann::ordered_json::parse(config_json(config));
    print_json_line(stdout, line);
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    DrainReport report = service.stop();
    print_json_line(
        stdout,
        {{"event", "stopped"}, {"signal", signal_number}, {"drained", report.drained}, {"seconds", report.seconds}});
    return 0;
  } catch (const std::exception& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", nullptr}});
    return 1;
  }
}

}  // namespace rr::server

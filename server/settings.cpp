// The settings table (see settings.hpp) and the member kinds its rows are made of. Each kind reads
// text into one member, with the message a user sees when the text is wrong, and shows and reports
// the member's value. A member is a ServerConfig member or a ParseLimits one, reached through
// ServerConfig::limits.
#include "server/settings.hpp"

#include "render/core/raster.hpp"
#include "server/open_stores.hpp"
#include "server/request_head.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <limits>
#include <regex>
#include <type_traits>

namespace rr::server {
namespace {

template <class T>
T& at(ServerConfig& config, T ServerConfig::*member) {
  return config.*member;
}
template <class T>
const T& at(const ServerConfig& config, T ServerConfig::*member) {
  return config.*member;
}
template <class T>
T& at(ServerConfig& config, T ParseLimits::*member) {
  return config.limits.*member;
}
template <class T>
const T& at(const ServerConfig& config, T ParseLimits::*member) {
  return config.limits.*member;
}

long long parse_integer(const std::string& text, const std::string& source, long long lo, long long hi) {
  long long value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || value < lo || value > hi) {
    throw UsageError(source + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], not '" +
                     text + "'");
  }
  return value;
}

// A whole number in [lo, hi].
template <class Member>
SettingMember integer(Member member, long long lo, long long hi) {
  return {[member, lo, hi](ServerConfig& c, const std::string& text, const std::string& source) {
            using T = std::remove_cvref_t<decltype(at(c, member))>;
            at(c, member) = static_cast<T>(parse_integer(text, source, lo, hi));
          },
          [member](const ServerConfig& c) { return std::to_string(at(c, member)); },
          [member](const ServerConfig& c) { return nlohmann::ordered_json(at(c, member)); }};
}

// 1 or 0.
SettingMember switch_01(bool ServerConfig::*member) {
  return {[member](ServerConfig& c, const std::string& text, const std::string& source) {
            c.*member = parse_integer(text, source, 0, 1) == 1;
          },
          [member](const ServerConfig& c) { return std::string(c.*member ? "1" : "0"); },
          [member](const ServerConfig& c) { return nlohmann::ordered_json(c.*member); }};
}

std::string as_text(const std::string& value) { return value; }
std::string as_text(const std::filesystem::path& value) { return value.string(); }

// Any text (a string or a path); an empty one is shown as `when_empty`.
template <class Member>
SettingMember text(Member member, std::string_view when_empty = "none") {
  return {[member](ServerConfig& c, const std::string& value, const std::string&) { at(c, member) = value; },
          [member, when_empty](const ServerConfig& c) {
            std::string value = as_text(at(c, member));
            return value.empty() ? std::string(when_empty) : value;
          },
          [member](const ServerConfig& c) { return nlohmann::ordered_json(as_text(at(c, member))); }};
}

// One of `choices`.
SettingMember one_of(std::string ServerConfig::*member, std::vector<std::string> choices) {
  return {[member, choices](ServerConfig& c, const std::string& text, const std::string& source) {
            if (std::find(choices.begin(), choices.end(), text) == choices.end()) {
              std::string list;
              for (size_t i = 0; i < choices.size(); ++i) {
                list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
              }
              throw UsageError(source + " must be " + list + ", not '" + text + "'");
            }
            c.*member = text;
          },
          [member](const ServerConfig& c) { return c.*member; },
          [member](const ServerConfig& c) { return nlohmann::ordered_json(c.*member); }};
}

// "https://a.example, http://localhost:5173" -> each origin as a browser sends it (scheme://host[:port]).
std::vector<std::string> parse_origins(const std::string& text, const std::string& source) {
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
      throw UsageError(source + ": '" + origin + "' is not an origin (scheme://host[:port], no path) or *");
    }
    origins.push_back(origin);
  }
  return origins;
}

// A comma-separated list of origins, or *.
SettingMember origins(std::vector<std::string> ServerConfig::*member) {
  return {[member](ServerConfig& c, const std::string& text, const std::string& source) {
            c.*member = parse_origins(text, source);
          },
          [member](const ServerConfig& c) {
            std::string list;
            for (const std::string& origin : c.*member) list += (list.empty() ? "" : ",") + origin;
            return list.empty() ? std::string("none") : list;
          },
          [member](const ServerConfig& c) { return nlohmann::ordered_json(c.*member); }};
}

// --store: a PostgreSQL connection URL or key=value string.
void check_store_flag(const std::string& text, const std::string& source) {
  try {
    check_store_url(text);
  } catch (const std::invalid_argument& e) {
    throw UsageError(source + " " + e.what());
  }
}

// The store URL as config_json reports it: without a password.
nlohmann::ordered_json redacted_store_url(const ServerConfig& config) {
  if (config.store_url.empty()) return "embedded";
  static const std::regex password("(://[^:/@]*:)[^@]*@|(password=)[^ ]*");
  return std::regex_replace(config.store_url, password, "$1$2***@");
}

constexpr long long int_max = std::numeric_limits<int>::max();
constexpr long long big = 1LL << 40;  // a byte or count limit beyond any sensible value

}  // namespace

SettingMember SettingMember::reported_as(Report effective) const {
  SettingMember out = *this;
  out.report = std::move(effective);
  return out;
}

SettingMember SettingMember::checked_by(
    std::function<void(const std::string& text, const std::string& source)> check) const {
  SettingMember out = *this;
  out.set = [unchecked = set, check_first = std::move(check)](ServerConfig& c, const std::string& text,
                                                              const std::string& source) {
    check_first(text, source);
    unchecked(c, text, source);
  };
  return out;
}

const std::vector<ServerSetting>& server_settings() {
  using C = ServerConfig;
  using L = ParseLimits;
  // clang-format off
  static const std::vector<ServerSetting> table = {
    // flag, member (with the values it takes), unit, help
    {"--port", integer(&C::port, 0, 65535), "", "TCP port; 0 picks a free one"},
    {"--bind", text(&C::bind), "", "address to listen on; 0.0.0.0 for every interface"},
    {"--threads", integer(&C::threads, 0, 1024).reported_as(request_workers), "",
     "request worker threads; 0: render-workers + render-queue + 8"},
    {"--render-workers", integer(&C::render_workers, 0, 256).reported_as(render_workers), "",
     "renders running at once; 0: one per core"},
    {"--render-threads", integer(&C::render_threads, 0, 64).reported_as(render_threads), "",
     "threads drawing one render's screen tiles; 0: one per core"},
    {"--render-queue", integer(&C::render_queue, -1, 4096).reported_as(render_queue_length), "",
     "renders waiting for a slot before 503; -1: 4 per worker"},
    {"--render-timeout-ms", integer(&C::render_timeout_ms, 1, int_max), "ms", "deadline per render from arrival, then 503/504"},
    {"--retry-after", integer(&C::retry_after_s, 0, 3600), "s", "seconds in Retry-After with 503"},
    {"--drain-timeout-ms", integer(&C::drain_timeout_ms, 0, int_max), "ms", "on SIGTERM, how long in-flight renders may finish"},
    {"--trim-after-ms", integer(&C::trim_after_work_ms, -1, int_max), "ms",
     "after a render that worked this long, return free heap to the OS; -1: never"},
    {"--max-body-bytes", integer(&C::max_body_bytes, 1, big), "bytes", "largest request body"},
    {"--max-import-bytes", integer(&C::max_import_bytes, 1, big), "bytes", "largest file POSTed to /v1/import/{format}"},
    {"--max-json-depth", integer(&L::max_depth, 4, 10000), "", "deepest JSON nesting"},
    {"--max-image-side", integer(&L::max_image_side, 1, max_image_side_for_raster), "pixels",
     "largest width or height"},
    {"--max-pixels", integer(&L::max_pixels, 1, big), "pixels", "largest width * height"},
    {"--max-render-bytes", integer(&L::max_render_bytes, 1, big), "bytes",
     "a frame's buffer memory, the A-buffer of options.antialias included"},
    {"--max-polygons", integer(&L::max_polygons, 1, big), "", "most polygons after tessellation"},
    {"--cache-bytes", integer(&C::cache_bytes, 0, big), "bytes",
     "memory for prepared scenes and meshes, BSP trees and shadow maps (one LRU cache, rebuilt on a miss)"},
    {"--bsp-cache-entries", integer(&C::bsp_cache_entries, 0, big), "", "most BSP trees in that cache"},
    {"--shadow-cache-bytes", integer(&C::shadow_cache_bytes, 0, big), "bytes",
     "most of that cache shadow maps may take; 0 keeps none"},
    {"--scene-store-bytes", integer(&C::scene_store_bytes, 0, big), "bytes",
     "stored scene documents at most (their text); kept, 507 when full"},
    {"--scene-store-entries", integer(&C::scene_store_entries, 0, big), "", "most stored scenes"},
    {"--scene-ttl", integer(&C::scene_ttl_s, 0, int_max), "s",
     "seconds a stored scene (or mesh) is kept after its last access; 0: until deleted"},
    {"--mesh-store-bytes", integer(&C::mesh_store_bytes, 0, big), "bytes",
     "stored mesh documents at most (their text); kept, 507 when full"},
    {"--mesh-store-entries", integer(&C::mesh_store_entries, 0, big), "", "most stored meshes"},
    {"--texture-store-bytes", integer(&C::texture_store_bytes, 0, big), "bytes",
     "stored images at most (their encoded bytes); kept, 507 when full"},
    {"--texture-store-entries", integer(&C::texture_store_entries, 0, big), "", "most stored images"},
    {"--cors-origins", origins(&C::cors_origins), "",
     "comma-separated origins (https://app.example.com) whose pages may write; * for any"},
    {"--api-token-file", text(&C::api_token_file), "",
     "file of bearer tokens, one per line as name:token; writes then need one; none: writes are open"},
    {"--allow-listing", switch_01(&C::allow_listing), "",
     "1: GET /v1/scenes lists every stored scene on a server without tokens"},
    {"--store", text(&C::store_url, "embedded").checked_by(check_store_flag).reported_as(redacted_store_url), "",
     "postgresql://user:password@host:port/db: stored scenes and meshes in PostgreSQL, shared by every replica; embedded: in memory and --data-dir"},
    {"--store-pool", integer(&C::store_pool_size, 1, 1000), "", "connections to the --store database per replica"},
    {"--store-timeout-ms", integer(&C::store_timeout_ms, 1, 3'600'000), "ms",
     "connect, wait for a connection and run each store statement within this, then 503"},
    {"--data-dir", text(&C::data_dir), "",
     "directory where stored scenes and meshes persist; none: memory only, gone when the process ends"},
    {"--web-dir", text(&C::web_dir, "the source tree's clients/web"), "", "directory holding index.html"},
    {"--examples-dir", text(&C::examples_dir, "the source tree's examples"), "", "directory of example requests"},
    {"--schemas-dir", text(&C::schemas_dir, "the source tree's schemas"), "", "directory of JSON Schemas and openapi.json"},
    {"--catalogue-dir", text(&C::catalogue_dir, "the source tree's catalogue"), "",
     "directory of the furniture and texture catalogues (catalogue.json, models/, icons/, textures.json, textures/); none there: an empty catalogue"},
    {"--max-connections", integer(&C::max_connections, 1, 1000000), "",
     "open client connections; when full the oldest idle one, else the oldest unfinished head, is closed"},
    {"--max-idle-connections", integer(&C::max_idle_connections, 0, 1000000), "",
     "idle keep-alive connections kept; beyond, the oldest is closed"},
    {"--keep-alive-timeout", integer(&C::keep_alive_timeout_s, 0, 3600), "s", "seconds an idle keep-alive connection is kept"},
    {"--keep-alive-max", integer(&C::keep_alive_max_requests, 1, 1000000), "", "requests per connection"},
    {"--header-timeout-ms", integer(&C::header_timeout_ms, 1, 3'600'000), "ms",
     "the whole request head must arrive within this, then 408"},
    {"--body-timeout-ms", integer(&C::body_timeout_ms, 1, 3'600'000), "ms",
     "the whole body must arrive within this plus its length / min-transfer-rate, then 408"},
    {"--write-timeout", integer(&C::write_timeout_s, 1, 3600), "s",
     "seconds to write a whole answer, plus its size / min-transfer-rate"},
    {"--min-transfer-rate", integer(&C::min_transfer_rate, 1, big), "bytes/s",
     "bytes per second granted to bodies and answers on top of their timeouts"},
    {"--min-body-rate", integer(&C::min_body_rate, 0, big), "bytes/s",
     "a body earns time beyond body-timeout-ms only as it arrives, 1 s per this many bytes; 0: no minimum"},
    {"--max-request-line-bytes", integer(&C::max_request_line_bytes, 64, httplib_max_line_bytes), "bytes",
     "longest request line (414) and header line (431); httplib reads no longer ones"},
    {"--max-header-bytes", integer(&C::max_header_bytes, 256, 16 << 20), "bytes", "largest request head, then 431"},
    {"--max-header-count", integer(&C::max_header_count, 1, 100000), "", "most header fields in a request, then 431"},
    {"--max-pending-requests", integer(&C::max_pending_requests, -1, 1000000).reported_as(max_pending_requests), "",
     "complete requests waiting for a worker before 503; -1: one per worker"},
    {"--max-buffered-body-bytes", integer(&C::max_buffered_body_bytes, 1, big), "bytes",
     "request bodies being received at once, then 503"},
    {"--listen-backlog", integer(&C::listen_backlog, 1, 65535), "", "pending connections the kernel queues"},
    {"--log-level", one_of(&C::log_level, {"info", "warn", "error", "off"}), "", "info, warn, error or off"},
    {"--log-requests", switch_01(&C::log_requests), "", "1: one JSON line per request at level info; 0: none"},
  };
  // clang-format on
  return table;
}

const ServerSetting* find_setting(std::string_view flag) {
  for (const ServerSetting& s : server_settings()) {
    if (flag == s.flag) return &s;
  }
  return nullptr;
}

std::string ServerSetting::env() const {
  std::string name = "ROOMRENDER_";
  for (char c : flag.substr(2)) name += c == '-' ? '_' : char(std::toupper(static_cast<unsigned char>(c)));
  return name;
}

std::string ServerSetting::key() const {
  std::string name(flag.substr(2));
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

std::string ServerSetting::default_text() const { return member.show(ServerConfig{}); }

}  // namespace rr::server

// The HTTP service (see http_server.hpp). cpp-httplib 0.11.4 from Debian is a compiled library: its
// CPPHTTPLIB_* macros change nothing here, and its thread-per-connection server lets one slow or
// idle client hold a thread, so its listener is not used. Our connection front owns the sockets and
// hands each complete request, as bytes, to httplib's request processing on an in-memory stream
// (Server::process_request, reached through a subclass). A request passes screen_request first
// (route, method, Accept and body framing, before any body byte is read), then dispatch() calls its
// route's handler; handlers just throw, and answer_exception turns whatever went wrong into
// problem+json. One log line and the metrics per request come from the logger, which httplib calls
// after writing every response.
#include "server/http_server.hpp"

#include "server/connection_front.hpp"
#include "server/http_util.hpp"
#include "server/problem.hpp"
#include "server/routes.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#if defined(__GLIBC__)
#include <malloc.h>  // malloc_trim
#endif

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstring>
#include <regex>
#include <stdexcept>

#ifndef ROOMRENDER_SOURCE_DIR
#define ROOMRENDER_SOURCE_DIR "."
#endif

namespace rr::server {
namespace {

using httplib::Request;
using httplib::Response;
using HandlerResponse = httplib::Server::HandlerResponse;
using Clock = std::chrono::steady_clock;

// Headers a handler may have set for a success that must not survive into an error answer (an
// immutable Cache-Control on a 422 would pin the error in caches for a year).
constexpr const char* success_headers[] = {"Server-Timing",  "X-Scene-Id", "X-Cache",
                                           "X-Shadow-Cache", "ETag",       "X-Warning-Count",
                                           "Cache-Control",  "Location",   "Vary"};

void send_problem(Response& res, const Problem& problem) {
  for (const char* name : success_headers) res.headers.erase(name);
  // The CORS headers screening set stay, so a page can read the problem; Vary went with the rest.
  if (request_context().vary_origin) res.set_header("Vary", "Origin");
  res.status = problem.status;
  for (const auto& [name, value] : problem.headers) res.set_header(name, value);
  res.set_header("Cache-Control", "no-store");
  res.set_content(problem.body, problem_content_type);
}

void send_problem(Response& res, int status, std::string_view detail, HeaderList headers = {}) {
  send_problem(res, Problem{status, make_problem(status, "", detail), std::move(headers)});
}

// Ends the connection once `res` is written. A request refused before its body was read leaves that
// body on the socket, where it must not be taken for the next request. httplib decides keep-alive
// from the request alone; the connection front reads this header of the answer and closes.
void close_after_response(Response& res) { res.set_header("Connection", "close"); }

// httplib parses Range itself and would cut our answers to the requested bytes (also with status
// 200, and also problem bodies); and it adds REMOTE_ADDR and friends as headers *after* any the
// client sent, so get_header_value would return the client's. The Request is a mutable object that
// httplib hands to handlers as const, so clearing these here is well-defined.
void sanitize_request(const Request& req) {
  Request& mutable_req = const_cast<Request&>(req);
  mutable_req.ranges.clear();
  for (const char* name : {"REMOTE_ADDR", "REMOTE_PORT", "LOCAL_ADDR", "LOCAL_PORT"}) mutable_req.headers.erase(name);
  mutable_req.set_header("REMOTE_ADDR", req.remote_addr);
  mutable_req.set_header("REMOTE_PORT", std::to_string(req.remote_port));
  mutable_req.set_header("LOCAL_ADDR", req.local_addr);
  mutable_req.set_header("LOCAL_PORT", std::to_string(req.local_port));
}

// 404 for an unknown path, 405 (with Allow) for a known path and another method; else the route,
// with its captures stored in the request context.
const Route* screen_route(const std::vector<Route>& routes, const Request& req, Response& res) {
  std::string allow;
  for (const Route& r : routes) {
    std::smatch groups;
    if (!std::regex_match(req.path, groups, r.regex)) continue;
    if (r.method == req.method || (r.method == "GET" && req.method == "HEAD")) {
      RequestContext& context = request_context();
      context.route = &r;
      for (size_t i = 1; i < groups.size(); ++i) context.match.params.push_back(groups[i].str());
      return &r;
    }
    allow += (allow.empty() ? "" : ", ") + r.method + (r.method == "GET" ? ", HEAD" : "");
  }
  if (allow.empty()) {
    send_problem(res, 404, "There is no resource at this path.");
  } else {
    send_problem(res, 405, req.method + " is not allowed here; use " + allow + ".", {{"Allow", allow}});
  }
  return nullptr;
}

bool screen_accept(const Route& route, const Request& req, Response& res) {
  if (route.produces.empty()) return true;
  auto chosen = negotiate(req.get_header_value("Accept"), route.produces);
  if (!chosen) {
    std::string offered;
    for (const std::string& type : route.produces) offered += (offered.empty() ? "" : ", ") + type;
    send_problem(res, 406, "This resource is available as " + offered + "; the Accept header rules that out.");
    return false;
  }
  request_context().match.media_type = *chosen;
  return true;
}

// Body framing we accept: only Content-Length (no Transfer-Encoding, whose chunked bodies httplib
// 0.11 reads without a size limit), no Content-Encoding (httplib inflates gzip and brotli bodies, a
// decompression bomb), at most max_body_bytes, and none at all for routes that take no body.
// Returns false after answering.
bool screen_body_headers(const Route& route, const ServerConfig& config, const Request& req, Response& res) {
  const bool takes_body = !route.consumes.empty();
  if (req.has_header("Transfer-Encoding")) {
    send_problem(res, 411, "Send the body with a Content-Length; Transfer-Encoding is not accepted.");
    return false;
  }
  if (req.has_header("Content-Encoding")) {
    send_problem(res, 415, "Content-Encoding is not accepted; send the body uncompressed.");
    return false;
  }
  if (req.get_header_value_count("Content-Length") > 1) {
    send_problem(res, 400, "The request has more than one Content-Length header.");
    return false;
  }
  uint64_t length = 0;
  if (req.has_header("Content-Length")) {
    std::string value = req.get_header_value("Content-Length");
    auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), length);
    if (ec == std::errc::invalid_argument || end != value.data() + value.size() || value.empty()) {
      send_problem(res, 400, "The Content-Length header is not a number.");
      return false;
    }
    uint64_t limit = takes_body ? (route.max_body_bytes ? route.max_body_bytes : config.max_body_bytes) : 0;
    if (ec == std::errc::result_out_of_range || length > limit) {
      send_problem(res, 413,
                   takes_body ? "The body exceeds the limit of " + std::to_string(limit) + " bytes."
                              : "This request takes no body.");
      return false;
    }
  } else if (takes_body) {
    // Without either header httplib would read until the client closes the connection.
    send_problem(res, 411, "This request needs a Content-Length header.");
    return false;
  }
  std::string type = media_type(req.get_header_value("Content-Type"));
  if (takes_body && !type.empty() &&
      std::find(route.consumes.begin(), route.consumes.end(), type) == route.consumes.end()) {
    send_problem(res, 415, "Send the request body as " + route.consumes.front() + ".");
    return false;
  }
  return true;
}

// OPTIONS: a CORS preflight (with Access-Control-Request-Method) gets 204 and the allow headers or a
// refusal; a plain OPTIONS gets 204 with Allow. The context's route is the path's first, for the log.
void answer_options(const std::vector<Route>& routes, const AccessPolicy& policy, const Request& req, Response& res) {
  std::vector<RouteMethod> methods;
  for (const Route& r : routes) {
    if (!std::regex_match(req.path, r.regex)) continue;
    if (methods.empty()) request_context().route = &r;
    methods.push_back({r.method, r.access});
  }
  if (methods.empty()) return send_problem(res, 404, "There is no resource at this path.");
  if (!req.has_header("Access-Control-Request-Method")) {
    std::string allow = "OPTIONS";
    for (const RouteMethod& m : methods) allow += ", " + m.method + (m.method == "GET" ? ", HEAD" : "");
    res.set_header("Allow", allow);
    res.status = 204;
    return;
  }
  Preflight preflight = answer_preflight(policy, req, methods);
  if (preflight.refusal) {
    request_context().vary_origin = true;
    return send_problem(res, preflight.refusal->status, preflight.refusal->detail, preflight.refusal->headers);
  }
  for (const auto& [name, value] : preflight.headers) res.set_header(name, value);
  res.status = 204;
}

// CORS (which origins may make this call) and, for writes on a server with tokens, the bearer token.
// Returns false after answering 403 or 401.
bool screen_access(const Route& route, const AccessPolicy& policy, const Request& req, Response& res) {
  RequestContext& context = request_context();
  const bool write = is_write(route.access, req);
  for (const auto& [name, value] : cors_headers(policy, req, write)) res.set_header(name, value);
  context.vary_origin = write;
  std::optional<Refusal> refusal = screen_origin(policy, req, write);
  if (!refusal && (write || route.access == Access::owner_read)) refusal = screen_token(policy, req, context.owner);
  if (!refusal) return true;
  send_problem(res, refusal->status, refusal->detail, refusal->headers);
  return false;
}

// Runs before httplib reads the body (and before it answers "100 Continue").
HandlerResponse screen_request(const std::vector<Route>& routes, const ServiceState& state, const Request& req,
                               Response& res) {
  RequestContext& context = request_context();
  context = RequestContext{};
  context.start = Clock::now();
  context.active = true;
  sanitize_request(req);
  if (req.method == "OPTIONS") {
    answer_options(routes, state.access, req, res);
    if (req.has_header("Content-Length") || req.has_header("Transfer-Encoding")) close_after_response(res);
    return HandlerResponse::Handled;
  }
  const Route* route = screen_route(routes, req, res);
  if (route && screen_access(*route, state.access, req, res) && screen_accept(*route, req, res) &&
      screen_body_headers(*route, state.config, req, res)) {
    return HandlerResponse::Unhandled;
  }
  // A GET or HEAD without body framing has nothing left on the socket; anything else may.
  bool body_may_follow = (req.method != "GET" && req.method != "HEAD") || req.has_header("Content-Length") ||
                         req.has_header("Transfer-Encoding");
  if (body_may_follow) close_after_response(res);
  return HandlerResponse::Handled;
}

// Set by the logger when a request's work was large; the worker trims the heap once the answer has
// been handed to the front, so the trim delays no answer.
thread_local bool heap_trim_pending = false;

// Requests at least this large return their freed heap to the OS after the answer, like long renders.
constexpr size_t large_request_bytes = 1u << 20;

void trim_heap_if_pending() {
  if (!heap_trim_pending) return;
  heap_trim_pending = false;
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

void log_request(ServiceState& state, const Request& req, const Response& res) {
  RequestContext& context = request_context();
  // Requests httplib refused before screening (a broken request line) have no route or start.
  const bool screened = context.active;
  const std::string route = screened && context.route ? context.route->path_template : "unmatched";
  double seconds = screened ? std::chrono::duration<double>(Clock::now() - context.start).count() : 0.0;
  state.metrics.record_request(route, req.method, res.status, seconds);
  if (state.config.log_requests) {
    // httplib has set Content-Length by now, also for bodies written through a provider.
    nlohmann::ordered_json line = {
        {"event", "request"},
        {"method", req.method},
        {"route", route},
        {"path", req.path},
        {"status", res.status},
        {"bytes", res.get_header_value<uint64_t>("Content-Length")},
        {"duration_ms", screened ? nlohmann::ordered_json(seconds * 1000.0) : nlohmann::ordered_json(nullptr)},
        {"remote", req.remote_addr}};  // the socket's peer, never a client-supplied header
    if (!context.scene_id.empty()) line["scene_id"] = context.scene_id;
    if (!context.pipeline.empty()) line["pipeline"] = context.pipeline;
    if (!context.cache.empty()) line["cache"] = context.cache;
    if (!context.owner.empty()) line["owner"] = context.owner;  // the token's name; tokens are never logged
    state.log("info", std::move(line));
  }
  heap_trim_pending = heap_trim_pending || context.trim_heap_after_response;
  context = RequestContext{};
}

void answer_exception(ServiceState& state, const Request& req, Response& res, std::exception_ptr error) {
  std::string log_detail;
  Problem problem = problem_from_exception(error, log_detail);
  if (!log_detail.empty()) {  // our fault: logged with the text the client does not see
    state.log("error",
              {{"event", "internal_error"}, {"method", req.method}, {"path", req.path}, {"detail", log_detail}});
  }
  send_problem(res, problem);
}

// httplib's own error answers (unparsable request, URI too long, bad Range, ...) come without a
// body; give them a problem body too. Our answers always carry a Content-Type and are left alone.
HandlerResponse fill_error_body(const Request&, Response& res) {
  if (res.has_header("Content-Type")) return HandlerResponse::Unhandled;
  send_problem(res, status_problem(res.status));
  return HandlerResponse::Handled;
}

// httplib's request processing, reachable: process_request is protected in 0.11.
class RequestProcessor : public httplib::Server {
 public:
  bool process(httplib::Stream& stream, bool close_connection, bool& connection_closed) {
    return process_request(stream, close_connection, connection_closed, nullptr);
  }
};

// One complete request as httplib's input, its answer collected as bytes. Reading past the request
// gives 0 (end of stream), so a handler never waits for a client.
class MemoryStream final : public httplib::Stream {
 public:
  MemoryStream(const FrontRequest& request, std::string& out) : request_(request), out_(out) {}
  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    size_t n = std::min(size, request_.bytes.size() - offset_);
    std::memcpy(ptr, request_.bytes.data() + offset_, n);
    offset_ += n;
    return ssize_t(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    out_.append(ptr, size);
    return ssize_t(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = request_.remote_ip;
    port = request_.remote_port;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = request_.local_ip;
    port = request_.local_port;
  }
  socket_t socket() const override { return INVALID_SOCKET; }

 private:
  const FrontRequest& request_;
  std::string& out_;
  size_t offset_ = 0;
};

void configure_limits(httplib::Server& server, const ServerConfig& config) {
  // Backstop only: the front and screen_request refuse large bodies before they are read.
  server.set_payload_max_length(std::max(config.max_body_bytes, config.max_import_bytes));
  // httplib advertises these in its Keep-Alive header; the front enforces them.
  server.set_keep_alive_timeout(config.keep_alive_timeout_s);
  server.set_keep_alive_max_count(config.keep_alive_max_requests);
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"}});
}

std::shared_ptr<std::vector<Route>> make_routes(const ServerConfig& config) {
  return std::make_shared<std::vector<Route>>(service_routes(config));
}

std::unique_ptr<RequestProcessor> make_server(ServiceState& state, std::shared_ptr<std::vector<Route>> routes) {
  auto server = std::make_unique<RequestProcessor>();
  configure_limits(*server, state.config);
  // httplib only dispatches: screening already chose the route.
  auto dispatch = [&state](const Request& req, Response& res) {
    const RequestContext& context = request_context();
    context.route->handler(state, req, res, context.match);
  };
  server->Get(".*", dispatch);
  server->Post(".*", dispatch);
  server->Put(".*", dispatch);
  server->Delete(".*", dispatch);
  auto screen = [routes, &state](const Request& req, Response& res) {
    return screen_request(*routes, state, req, res);
  };
  server->set_pre_routing_handler(screen);
  // A request whose body the front did not read keeps its Expect header: answer it from the head.
  server->set_expect_100_continue_handler([screen](const Request& req, Response& res) {
    return screen(req, res) == HandlerResponse::Unhandled ? 100 : res.status;
  });
  server->set_exception_handler([&state](const Request& req, Response& res, std::exception_ptr error) {
    answer_exception(state, req, res, error);
  });
  server->set_error_handler(httplib::Server::HandlerWithResponse(fill_error_body));
  server->set_logger([&state](const Request& req, const Response& res) { log_request(state, req, res); });
  return server;
}

// The target's path, percent-decoded as httplib decodes it before routing.
std::string decoded_path(std::string_view target) {
  target = target.substr(0, target.find('?'));
  std::string path;
  for (size_t i = 0; i < target.size(); ++i) {
    unsigned value = 0;
    if (target[i] == '%' && i + 2 < target.size() &&
        std::from_chars(target.data() + i + 1, target.data() + i + 3, value, 16).ptr == target.data() + i + 3) {
      path += char(value);
      i += 2;
    } else {
      path += target[i];
    }
  }
  return path;
}

// The largest body the route of (method, target) takes, as screen_body_headers will judge it; 0 for
// a route that takes none or a path with no route (its answer then comes from the head alone).
uint64_t route_body_limit(const std::vector<Route>& routes, const ServerConfig& config, std::string_view method,
                          std::string_view target) {
  const std::string path = decoded_path(target);
  for (const Route& r : routes) {
    if (r.method != method || r.consumes.empty() || !std::regex_match(path, r.regex)) continue;
    return r.max_body_bytes ? r.max_body_bytes : config.max_body_bytes;
  }
  return 0;
}

// The answers the front gives without a worker (408, 414, 431, 503), as whole HTTP responses.
std::string front_refusal(ServiceState& state, int status, std::string_view detail, bool close) {
  std::string body = make_problem(status, "", detail);
  std::string head = "HTTP/1.1 " + std::to_string(status) + " " + std::string(status_title(status)) + "\r\n" +
                     "Content-Type: " + problem_content_type + "\r\nContent-Length: " + std::to_string(body.size()) +
                     "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\n"
                     // Refused unread, so nothing happened: any page may see why (and when to retry).
                     "Access-Control-Allow-Origin: *\r\nAccess-Control-Expose-Headers: Retry-After\r\n";
  if (status == 503) head += "Retry-After: " + std::to_string(state.config.retry_after_s) + "\r\n";
  if (close) head += "Connection: close\r\n";
  state.metrics.record_request("unmatched", "", status, 0.0);
  if (state.config.log_requests) {
    state.log("info", {{"event", "refused"}, {"status", status}, {"detail", std::string(detail)}});
  }
  return head + "\r\n" + body;
}

// True when the answer's head says "Connection: close" (close_after_response, or httplib's own).
bool answer_closes(std::string_view answer) {
  std::string_view head = answer.substr(0, answer.find("\r\n\r\n"));
  return head.find("\r\nConnection: close\r\n") != std::string_view::npos || head.ends_with("\r\nConnection: close");
}

FrontAnswer answer_request(RequestProcessor& server, ServiceState& state, FrontRequest& request) {
  FrontAnswer answer;
  MemoryStream stream(request, answer.bytes);
  bool client_closes = false;
  bool whole = server.process(stream, request.last, client_closes);
  if (answer.bytes.empty()) {  // httplib gave up before writing anything (no request line at all)
    answer.bytes = front_refusal(state, 400, "The request could not be read.", true);
    whole = false;
  }
  answer.close = !whole || client_closes || request.last || answer_closes(answer.bytes);
  // Each worker thread has its own malloc arena, which keeps what a large body's parse freed.
  if (request.bytes.size() >= large_request_bytes) heap_trim_pending = true;
  answer.then = trim_heap_if_pending;
  return answer;
}

FrontConfig front_config(const ServerConfig& c) {
  FrontConfig f;
  f.bind = c.bind;
  f.port = c.port;
  f.listen_backlog = c.listen_backlog;
  f.workers = request_workers(c);
  f.max_pending = max_pending_requests(c);
  f.max_connections = c.max_connections;
  f.max_idle_connections = c.max_idle_connections;
  f.keep_alive_timeout = std::chrono::seconds(c.keep_alive_timeout_s);
  f.header_timeout = std::chrono::milliseconds(c.header_timeout_ms);
  f.body_timeout = std::chrono::milliseconds(c.body_timeout_ms);
  f.write_timeout = std::chrono::seconds(c.write_timeout_s);
  f.min_transfer_rate = c.min_transfer_rate;
  f.max_buffered_body_bytes = c.max_buffered_body_bytes;
  f.max_requests_per_connection = c.keep_alive_max_requests;
  f.head_limits = {c.max_request_line_bytes, c.max_header_bytes, c.max_header_count};
  return f;
}

}  // namespace

ServerConfig default_server_config() {
  ServerConfig config;
  config.web_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "clients" / "web";
  config.examples_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "examples";
  config.schemas_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "schemas";
  return config;
}

size_t render_workers(const ServerConfig& config) {
  if (config.render_workers > 0) return size_t(config.render_workers);
  return std::max<size_t>(1, std::thread::hardware_concurrency());
}

unsigned render_threads(const ServerConfig& config) {
  if (config.render_threads > 0) return unsigned(config.render_threads);
  return std::max(1u, std::thread::hardware_concurrency());
}

size_t render_queue_length(const ServerConfig& config) {
  if (config.render_queue >= 0) return size_t(config.render_queue);
  return 4 * render_workers(config);
}

size_t request_workers(const ServerConfig& config) {
  // Every admitted or queued render holds a worker; the 8 beyond those answer health checks,
  // metrics, stored scenes and 503s while renders run.
  if (config.threads > 0) return size_t(config.threads);
  return render_workers(config) + render_queue_length(config) + 8;
}

size_t max_pending_requests(const ServerConfig& config) {
  if (config.max_pending_requests >= 0) return std::max<size_t>(1, size_t(config.max_pending_requests));
  return request_workers(config);
}

// The store URL as the start-up line prints it: without a password.
static std::string redacted_store_url(const std::string& url) {
  if (url.empty()) return "embedded";
  static const std::regex password("(://[^:/@]*:)[^@]*@|(password=)[^ ]*");
  return std::regex_replace(url, password, "$1$2***@");
}

std::string config_json(const ServerConfig& c) {
  const ParseLimits& l = c.limits;
  nlohmann::ordered_json j = {{"bind", c.bind},
                              {"port", c.port},
                              {"threads", request_workers(c)},
                              {"render_workers", render_workers(c)},
                              {"render_threads", render_threads(c)},
                              {"render_queue", render_queue_length(c)},
                              {"render_timeout_ms", c.render_timeout_ms},
                              {"trim_after_work_ms", c.trim_after_work_ms},
                              {"retry_after_s", c.retry_after_s},
                              {"drain_timeout_ms", c.drain_timeout_ms},
                              {"max_body_bytes", c.max_body_bytes},
                              {"max_import_bytes", c.max_import_bytes},
                              {"max_json_depth", l.max_depth},
                              {"max_image_side", l.max_image_side},
                              {"max_pixels", l.max_pixels},
                              {"max_render_bytes", l.max_render_bytes},
                              {"max_polygons", l.max_polygons},
                              {"max_cylinder_segments", l.max_cylinder_segments},
                              {"max_floor_cells", l.max_floor_cells},
                              {"max_abs_coordinate", l.max_abs_coordinate},
                              {"max_far_over_near", l.max_far_over_near},
                              {"max_mesh_vertices", l.max_mesh_vertices},
                              {"bsp_cache_bytes", c.bsp_cache_bytes},
                              {"bsp_cache_entries", c.bsp_cache_entries},
                              {"shadow_cache_bytes", c.shadow_cache_bytes},
                              {"scene_store_bytes", c.scene_store_bytes},
                              {"scene_store_entries", c.scene_store_entries},
                              {"scene_ttl_s", c.scene_ttl_s},
                              {"mesh_store_bytes", c.mesh_store_bytes},
                              {"mesh_store_entries", c.mesh_store_entries},
                              {"store", redacted_store_url(c.store_url)},
                              {"store_pool", c.store_pool_size},
                              {"store_timeout_ms", c.store_timeout_ms},
                              {"store_cache_bytes", c.store_cache_bytes},
                              {"cors_origins", c.cors_origins},
                              {"api_token_file", c.api_token_file.string()},
                              {"allow_listing", c.allow_listing},
                              {"data_dir", c.data_dir.string()},
                              {"web_dir", c.web_dir.string()},
                              {"examples_dir", c.examples_dir.string()},
                              {"schemas_dir", c.schemas_dir.string()},
                              {"max_connections", c.max_connections},
                              {"max_idle_connections", c.max_idle_connections},
                              {"keep_alive_timeout_s", c.keep_alive_timeout_s},
                              {"keep_alive_max_requests", c.keep_alive_max_requests},
                              {"header_timeout_ms", c.header_timeout_ms},
                              {"body_timeout_ms", c.body_timeout_ms},
                              {"write_timeout_s", c.write_timeout_s},
                              {"min_transfer_rate", c.min_transfer_rate},
                              {"max_request_line_bytes", c.max_request_line_bytes},
                              {"max_header_bytes", c.max_header_bytes},
                              {"max_header_count", c.max_header_count},
                              {"max_pending_requests", max_pending_requests(c)},
                              {"max_buffered_body_bytes", c.max_buffered_body_bytes},
                              {"listen_backlog", c.listen_backlog},
                              {"log_level", c.log_level},
                              {"log_requests", c.log_requests}};
  return j.dump();
}

Service::Service(ServerConfig config) : config_(std::move(config)) {}

Service::~Service() { stop(); }

void Service::start() {
  if (server_) throw std::logic_error("Service::start called twice");
  state_ = std::make_unique<ServiceState>(config_);
  // Meshes first: stored scenes place them by ref.
  size_t meshes_loaded = state_->meshes->load();
  size_t loaded = state_->scenes->load();
  if (!config_.data_dir.empty()) {
    state_->log("info", {{"event", "meshes_loaded"}, {"count", meshes_loaded}});
    state_->log("info", {{"event", "scenes_loaded"}, {"count", loaded}});
  }
  if (!config_.store_url.empty() && !config_.data_dir.empty()) {  // said, so nobody backs up an empty directory
    state_->log("warn",
                {{"event", "data_dir_unused"}, {"reason", "--store keeps stored scenes and meshes in the database"}});
  }
  const TokenTable& tokens = state_->access.tokens;
  // Said once at start, so an operator sees an open server for what it is.
  const bool loopback = config_.bind == "127.0.0.1" || config_.bind == "::1" || config_.bind == "localhost";
  state_->log(tokens.empty() && !loopback ? "warn" : "info", {{"event", "write_access"},
                                                              {"writes", tokens.empty() ? "open" : "token"},
                                                              {"tokens", tokens.size()},
                                                              {"cors_origins", config_.cors_origins},
                                                              {"listing", !tokens.empty() || config_.allow_listing}});
  auto routes = make_routes(config_);
  auto server = make_server(*state_, routes);
  RequestProcessor& processor = *server;
  ServiceState& state = *state_;
  front_ = std::make_unique<ConnectionFront>(
      front_config(config_),
      [routes, &state](std::string_view method, std::string_view target) {
        return route_body_limit(*routes, state.config, method, target);
      },
      [&processor, &state](FrontRequest& request) { return answer_request(processor, state, request); },
      [&state](int status, std::string_view detail, bool close) {
        return front_refusal(state, status, detail, close);
      });
  server_ = std::move(server);
  port_ = front_->bind();
  if (front_->max_connections() < config_.max_connections) {
    state_->log("warn", {{"event", "connection_cap_lowered"},
                         {"max_connections", front_->max_connections()},
                         {"configured", config_.max_connections},
                         {"reason", "the open-file limit (ulimit -n) leaves no room for more"}});
  }
  const ConnectionFront& front = *front_;
  state_->front_stats = [&front] { return front.stats(); };
  front_->start();
}

DrainReport Service::stop() {
  DrainReport report;
  if (stopped_ || !front_) return report;
  stopped_ = true;
  auto begin = Clock::now();
  state_->draining = true;
  state_->gate.close();      // new renders get 503; queued and running ones go on
  front_->stop_accepting();  // no new connections; idle ones close, open ones after their answer
  report.drained = state_->gate.wait_idle(begin + std::chrono::milliseconds(config_.drain_timeout_ms));
  if (!report.drained) state_->gate.abort();  // cancelled renders answer 503
  // Answers still being written get the write timeout, then whatever is left is closed.
  front_->finish(Clock::now() + std::chrono::seconds(config_.write_timeout_s));
  report.seconds = std::chrono::duration<double>(Clock::now() - begin).count();
  return report;
}

}  // namespace rr::server

// Screening (see screening.hpp): route and method, CORS and tokens, Accept and body framing, each
// checked from the request head alone and refused with a problem+json answer.
#include "server/screening.hpp"

#include "server/http_util.hpp"

#include <httplib.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <regex>

namespace rr::server {

void send_problem(httplib::Response& res, const Problem& problem) {
  // Headers a handler may have set for a success that must not survive into an error answer (an
  // immutable Cache-Control on a 422 would pin the error in caches for a year).
  static constexpr const char* success_headers[] = {"Server-Timing", "X-Scene-Id", "X-Cache",         "X-Shadow-Cache",
                                                    "X-Exposure",    "ETag",       "X-Warning-Count", "Cache-Control",
                                                    "Location",      "Vary"};
  for (const char* name : success_headers) res.headers.erase(name);
  // The CORS headers screening set stay, so a page can read the problem; Vary went with the rest.
  if (request_context().vary_origin) res.set_header("Vary", "Origin");
  res.status = problem.status;
  for (const auto& [name, value] : problem.headers) res.set_header(name, value);
  res.set_header("Cache-Control", "no-store");
  res.set_content(problem.body, problem_content_type);
}

namespace {

using httplib::Request;
using httplib::Response;
using Clock = std::chrono::steady_clock;

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

}  // namespace

bool screen_request(const std::vector<Route>& routes, const ServiceState& state, const Request& req, Response& res) {
  RequestContext& context = request_context();
  context = RequestContext{};
  context.start = Clock::now();
  context.active = true;
  sanitize_request(req);
  if (req.method == "OPTIONS") {
    answer_options(routes, state.access, req, res);
    if (req.has_header("Content-Length") || req.has_header("Transfer-Encoding")) close_after_response(res);
    return false;
  }
  const Route* route = screen_route(routes, req, res);
  if (route && screen_access(*route, state.access, req, res) && screen_accept(*route, req, res) &&
      screen_body_headers(*route, state.config, req, res)) {
    return true;
  }
  // A GET or HEAD without body framing has nothing left on the socket; anything else may.
  bool body_may_follow = (req.method != "GET" && req.method != "HEAD") || req.has_header("Content-Length") ||
                         req.has_header("Transfer-Encoding");
  if (body_may_follow) close_after_response(res);
  return false;
}

}  // namespace rr::server

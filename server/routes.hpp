// The service's route table and the state its handlers share. A route names its method, its path
// template (the label in logs and metrics, and its path's regex), the body media types it consumes
// and the response types it produces; screening (screening.cpp) uses those to answer
// 404/405/406/411/413/415 before a body is read, so handlers only see requests they can serve.
// Adding an endpoint (e.g. POST /v1/import/{format}) is one row in a *_routes() list, one handler and
// its path in schemas/openapi.json (unit.Routes holds the two to each other).
#pragma once

#include "render/core/timer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "server/access.hpp"
#include "server/catalogue.hpp"
#include "server/http_server.hpp"
#include "server/metrics.hpp"
#include "server/open_stores.hpp"
#include "server/prepared_cache.hpp"
#include "server/render_gate.hpp"
#include "server/render_workers.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace rr::server {

// Everything shared by handlers for the life of a Service.
struct ServiceState {
  explicit ServiceState(const ServerConfig& config);
  void log(const std::string& level, nlohmann::ordered_json fields) const;  // one JSON line

  // Read before the rest: the configuration's limits resolve its meshes, and the mesh store answers for them.
  std::shared_ptr<const Catalogue> catalogue;
  const ServerConfig config;
  RenderGate gate;
  RenderWorkers
      workers;          // where admitted renders run: one thread per render the gate admits at once (--render-workers)
  Stores stores;        // the stored scene and mesh documents, in the store --store names (open_stores.hpp),
                        // the catalogue's meshes in front (catalogue_store.hpp)
  PreparedCache cache;  // what is prepared from them, BSP trees and shadow maps: one budget (prepared_cache.hpp)
  ParseLimits limits;   // config.limits with "ref" resolved through the catalogue, then the cache: parse
                        // requests with these
  AccessPolicy access;  // CORS origins and tokens; loading the token file may throw
  Metrics metrics;
  std::atomic<bool> draining{false};
  std::function<FrontStats()> front_stats;  // the connection front's counts, set once it exists
};

struct RouteMatch {
  std::vector<std::string> params;  // the pattern's capture groups, in order
  std::string media_type;           // the negotiated response type ("" when the route has none)
};

using RouteHandler = std::function<void(ServiceState&, const httplib::Request&, httplib::Response&, const RouteMatch&)>;

struct Route {
  std::string method;                 // "GET" routes also answer HEAD
  std::string path_template;          // "/v1/scenes/{id}": logs, metrics, Allow lookups, OpenAPI's path
  std::vector<std::string> consumes;  // body media types accepted; empty: the route takes no body
  std::vector<std::string> produces;  // response types offered, preferred first; empty: not negotiated
  RouteHandler handler;
  // The regex for the whole decoded path where the template cannot say it all (an optional trailing
  // slash, a file name the template leaves out, a whitelist); empty: route_pattern derives it.
  std::string pattern = {};
  std::regex regex = {};         // route_pattern's, compiled by service_routes
  size_t max_body_bytes = 0;     // 0: ServerConfig::max_body_bytes
  Access access = Access::read;  // which origins may call it, and whether it needs a token
};

// The regex of a route's whole path, its groups the placeholders in order: `pattern` when the row
// gives one, else the template with each {placeholder} as its group (routes.cpp lists them) and
// every other character literal. Throws std::logic_error for a placeholder it does not know.
std::string route_pattern(const Route& route);

// Per request, on the thread that handles it from screening to the log line (httplib runs one
// request on one thread). Handlers add what the log line reports.
struct RequestContext {
  bool active = false;  // set by screening; a request httplib refused earlier has no context
  std::chrono::steady_clock::time_point start;
  const Route* route = nullptr;
  RouteMatch match;
  std::string scene_id;
  std::string pipeline;
  std::string cache;
  bool vary_origin = false;               // the answer depends on Origin (writes): error answers keep Vary: Origin
  std::string owner;                      // the token's owner name on a server with tokens (never the token itself)
  bool trim_heap_after_response = false;  // a large render ran: give free heap back once answered
};
RequestContext& request_context();

std::vector<Route> render_routes();                            // render_endpoints.cpp
std::vector<Route> scene_routes();                             // scene_endpoints.cpp
std::vector<Route> mesh_routes(const ServerConfig& config);    // mesh_endpoints.cpp
std::vector<Route> texture_routes();                           // texture_endpoints.cpp
std::vector<Route> import_routes(const ServerConfig& config);  // import_endpoints.cpp
std::vector<Route> meta_routes(const ServerConfig& config);    // meta_endpoints.cpp
std::vector<Route> pick_routes();                              // pick_endpoints.cpp
std::vector<Route> catalogue_routes();                         // catalogue_endpoints.cpp
// The web page's own routes (the page, the API page's assets, the example requests): served beside
// the API but not part of it, so schemas/openapi.json leaves them out. meta_endpoints.cpp.
std::vector<Route> page_routes(const ServerConfig& config);
// Every route above, in that order, each with its regex compiled (routes.cpp).
std::vector<Route> service_routes(const ServerConfig& config);

// Helpers shared by the endpoint files.
// A drawn camera as a request's camera object (pick answers; render answers of a framed view).
nlohmann::json camera_json(const Camera& camera);
void send_json(httplib::Response& res, const nlohmann::json& body, int status = 200);
// Answers 304 (and returns true) when If-None-Match matches `etag`; sets ETag either way.
bool answer_not_modified(const httplib::Request& req, httplib::Response& res, const std::string& etag);
// A stored, content-addressed document (`id` is its hash): cacheable forever, ETag "id", 304 on a match.
void send_stored_document(const httplib::Request& req, httplib::Response& res, const std::string& id,
                          const std::string& text, std::string_view media_type = "application/json");
// Whose reference a DELETE drops: the caller's with tokens, every reference (nullopt) without.
std::optional<std::string> releasing_owner(const ServiceState& state);
// The request body as JSON, parsed with the configured depth bound (InputError -> 400).
nlohmann::json parse_body(const ServiceState& state, const httplib::Request& req);
// Where a stored scene, mesh or image is served: "/v1/scenes/{id}", "/v1/meshes/{id}", "/v1/textures/{id}".
template <class T>
std::string location_of(const std::string& id) {
  return std::string("/v1/") + T::plural + "/" + id;
}
// A time as answers write it: RFC 3339 in UTC with milliseconds ("2026-12-02T04:00:00.123Z"), or null.
nlohmann::json time_or_null(const std::optional<std::chrono::system_clock::time_point>& t);
// Stores a scene or mesh for the caller (request_context().owner); returns whether it was created
// now (false: it was stored already). Throws HttpError 409 (another document has its id: a hash
// collision), 413 (larger than the whole store), 507 (the store is full) or 422 (a scene placing a
// mesh that was deleted meanwhile). store_answer.cpp.
template <class T>
bool store_document(ServiceState& state, const std::shared_ptr<const T>& item);
// store_document, then the answer: `body` (the caller's members) with id, location, created (and a
// scene's scene_id and expires), 201 when created else 200, Location (and a scene's X-Scene-Id).
template <class T>
void store_and_answer(ServiceState& state, httplib::Response& res, const std::shared_ptr<const T>& item,
                      nlohmann::json body);
// What a DELETE's refusals say of a scene, mesh or image ("The mesh ID is placed by stored scenes
// (...); delete those scenes first. A mesh stays while a stored scene places it.").
struct ReleaseWording {
  const char* noun;                        // "scene", "mesh", "image"
  const char* pinned_detail = nullptr;     // per pinning scene: "placed by stored scene"; null: never pinned
  const char* pinned_summary = nullptr;    // "placed by stored scenes"
  const char* pinned_rule = nullptr;       // "A mesh stays while a stored scene places it."
  const char* read_only_reason = nullptr;  // after "The mesh ID": why it cannot go; null: never read-only
};
// Drops the caller's reference (releasing_owner) to the stored `id` and answers 204, or throws
// HttpError 404 (not stored), 403 (stored by another owner; read-only, with a reason), 409 (pinned:
// names up to five stored scenes). Forgets the cached document when it is removed. store_answer.cpp.
template <class T>
void release_and_answer(ServiceState& state, httplib::Response& res, const std::string& id,
                        const ReleaseWording& wording);
// Throws HttpError 503 (+ Retry-After) unless `admission` is admitted.
void require_admission(ServiceState& state, RenderGate::Admission admission);
// A stopwatch started on admission, and how long the request waited for its slot (the `queue` stage).
struct SlotClock : Stopwatch {
  double queue_ms = 0.0;
};
// Runs `work` holding a render slot, with the configured deadline (counted from arrival, so queueing
// spends it) in the token and a SlotClock. Refusals and cancellations become HttpErrors: 503
// (saturated, deadline passed in the queue, draining) or 504 (deadline passed while drawing).
void with_render_slot(ServiceState& state, const std::function<void(const CancelToken&, SlotClock&)>& work);

}  // namespace rr::server

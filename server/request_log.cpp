// The request log and metrics (see request_log.hpp).
#include "server/request_log.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <string>

namespace rr::server {

void log_request(ServiceState& state, const httplib::Request& req, const httplib::Response& res) {
  const RequestContext& context = request_context();
  // Requests httplib refused before screening (a broken request line) have no route or start.
  const bool screened = context.active;
  const std::string route = screened && context.route ? context.route->path_template : "unmatched";
  double seconds =
      screened ? std::chrono::duration<double>(std::chrono::steady_clock::now() - context.start).count() : 0.0;
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
}

void log_refusal(ServiceState& state, int status, std::string_view detail) {
  state.metrics.record_request("unmatched", "", status, 0.0);
  if (state.config.log_requests) {
    state.log("info", {{"event", "refused"}, {"status", status}, {"detail", std::string(detail)}});
  }
}

}  // namespace rr::server

// The request log and request metrics: one JSON line (level info, with --log-requests) and one
// count per answer, from the request's context (server/routes.hpp): its route template, status,
// size, duration and what the handler noted (scene id, pipeline, cache, the token's owner).
#pragma once

#include "server/routes.hpp"

#include <string_view>

namespace rr::server {

// An answer httplib has written: called as httplib's logger, after the last byte.
void log_request(ServiceState& state, const httplib::Request& req, const httplib::Response& res);

// An answer the connection front gave without a worker (408, 414, 431, 503): no route, no duration.
void log_refusal(ServiceState& state, int status, std::string_view detail);

}  // namespace rr::server

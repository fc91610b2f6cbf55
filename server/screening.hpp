// Screening: what a request's head alone decides, before httplib reads a body byte (and before it
// answers "100 Continue"). The route and method (404, 405 with Allow), access (a CORS preflight,
// origins 403, bearer tokens 401), Accept (406) and body framing (400, 411, 413, 415), each refused
// with a problem+json answer; a refusal that may leave an unread body on the socket closes the
// connection. The connection front asks the same route table for a body's limit before reading it.
#pragma once

#include "server/problem.hpp"
#include "server/routes.hpp"

#include <cstdint>
#include <string_view>
#include <vector>

namespace rr::server {

// Answers `problem` as problem+json: success headers a handler may have set are dropped, the CORS
// headers screening set stay, and the answer is never cached.
void send_problem(httplib::Response& res, const Problem& problem);

// Starts the request's context (route, captures, negotiated type, owner) and screens it. True when
// it goes on to its route's handler; false once it has been answered (OPTIONS included).
bool screen_request(const std::vector<Route>& routes, const ServiceState& state, const httplib::Request& req,
                    httplib::Response& res);

// The largest body the route of (method, target) takes, as screening will judge it; 0 for a route
// that takes none or a path with no route (its answer then comes from the head alone).
uint64_t route_body_limit(const std::vector<Route>& routes, const ServerConfig& config, std::string_view method,
                          std::string_view target);

}  // namespace rr::server

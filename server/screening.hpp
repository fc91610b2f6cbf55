// Screening: what a request's head alone decides, before a body byte is read and before "100
// Continue" is sent. The route and method (404, 405 with Allow), access (a CORS preflight, origins
// 403, bearer tokens 401), Accept (406) and body framing (400, 411, 413, 415), each refused with a
// problem+json answer; a refusal that may leave an unread body on the socket closes the connection.
// It runs twice on a request with a body: on the connection front's event thread, from the front's
// parse of the head, to decide whether the body is read at all (http_server.cpp, screen_head); and
// on the worker from httplib's parse, which answers the refusal or goes on to the handler.
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

}  // namespace rr::server

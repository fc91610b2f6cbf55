// The HTTP service (see http_server.hpp). cpp-httplib 0.11.4 from Debian is a compiled library: its
// CPPHTTPLIB_* macros change nothing here, and its thread-per-connection server lets one slow or idle
// client hold a thread, so its listener is not used. Our connection front owns the sockets and parses
// each head; screening judges a head that announces a body from that parse, on the event thread,
// before the body is read. Each complete request then goes, as bytes, to httplib's request
// processing on an in-memory stream (httplib_bridge.hpp), which parses it again: where its parse
// differs from the front's the request is refused, so the handlers only ever see the request the
// front framed and screened. A request passes screen_request (screening.hpp: route, method, access,
// Accept and body framing) once more there, then dispatch() calls its route's handler; handlers just
// throw, and answer_exception turns whatever went wrong into problem+json. The logger, which httplib
// calls after writing every response, writes the log line and the metrics (request_log.hpp).
#include "server/http_server.hpp"

#include "server/connection_front.hpp"
#include "server/httplib_bridge.hpp"
#include "server/problem.hpp"
#include "server/request_log.hpp"
#include "server/routes.hpp"
#include "server/screening.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#if defined(__GLIBC__)
#include <malloc.h>  // malloc_trim
#endif

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace rr::server {
namespace {

using httplib::Request;
using httplib::Response;
using HandlerResponse = httplib::Server::HandlerResponse;
using Clock = std::chrono::steady_clock;

// Set by the logger when a request's work was large; the worker trims the heap once the answer has
// been handed to the front, so the trim delays no answer.
thread_local bool heap_trim_pending = false;

// Where httplib's parse of the request in process differs from the front's ("" when it does not),
// set by answer_request before httplib screens the request.
thread_local std::string parse_mismatch;

// Requests at least this large return their freed heap to the OS after the answer, like long renders.
constexpr size_t large_request_bytes = 1u << 20;

void trim_heap_if_pending() {
  if (!heap_trim_pending) return;
  heap_trim_pending = false;
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
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

void configure_limits(httplib::Server& server, const ServerConfig& config) {
  // Backstop only: the front and screen_request refuse large bodies before they are read.
  server.set_payload_max_length(std::max(config.max_body_bytes, config.max_import_bytes));
  // httplib advertises these in its Keep-Alive header; the front enforces them.
  server.set_keep_alive_timeout(config.keep_alive_timeout_s);
  server.set_keep_alive_max_count(config.keep_alive_max_requests);
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"}});
}

// A request the two parsers read differently is not answered as either reads it (request_head.hpp
// keeps them from differing; this is the net under that): 400, the connection closed, and the
// difference logged for the operator.
void refuse_mismatch(ServiceState& state, const Request& req, Response& res) {
  state.log("error", {{"event", "parse_mismatch"}, {"method", req.method}, {"detail", parse_mismatch}});
  send_problem(res, {400, make_problem(400, "", "The request head is ambiguous: it cannot be read one way only."), {}});
  res.set_header("Connection", "close");
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
    if (!parse_mismatch.empty()) {
      refuse_mismatch(state, req, res);
      return HandlerResponse::Handled;
    }
    return screen_request(*routes, state, req, res) ? HandlerResponse::Unhandled : HandlerResponse::Handled;
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
  server->set_logger([&state](const Request& req, const Response& res) {
    log_request(state, req, res);
    RequestContext& context = request_context();
    heap_trim_pending = heap_trim_pending || context.trim_heap_after_response;
    context = RequestContext{};
  });
  return server;
}

// The answers the front gives without a worker (408, 414, 431, 501, 503), as whole HTTP responses.
std::string front_refusal(ServiceState& state, int status, std::string_view detail, bool close) {
  std::string body = make_problem(status, "", detail);
  std::string head = "HTTP/1.1 " + std::to_string(status) + " " + std::string(status_title(status)) + "\r\n" +
                     "Content-Type: " + problem_content_type + "\r\nContent-Length: " + std::to_string(body.size()) +
                     "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\n"
                     // Refused unread, so nothing happened: any page may see why (and when to retry).
                     "Access-Control-Allow-Origin: *\r\nAccess-Control-Expose-Headers: Retry-After\r\n";
  if (status == 503) head += "Retry-After: " + std::to_string(state.config.retry_after_s) + "\r\n";
  if (close) head += "Connection: close\r\n";
  log_refusal(state, status, detail);
  return head + "\r\n" + body;
}

// Screening's verdict on a head that announces a body, from the front's parse, on the event thread:
// true when the body is to be read. The refusal itself is answered by a worker from the head alone,
// screened again there from httplib's parse, which agrees with this one.
bool screen_head(const std::vector<Route>& routes, const ServiceState& state, const RequestHead& head) {
  Request req = request_from_head(head);
  Response res;
  const bool pass = screen_request(routes, state, req, res);
  request_context() = RequestContext{};  // the event thread's context belongs to no request
  return pass;
}

FrontAnswer answer_request(RequestProcessor& server, ServiceState& state, FrontRequest& request) {
  FrontAnswer answer;
  const MemoryStream::Peer peer{request.remote_ip, request.local_ip, request.remote_port, request.local_port};
  MemoryStream stream(request.bytes, answer.bytes, peer);
  bool client_closes = false;
  // `last` carries the front's keep-alive decision: httplib then says "Connection: close" itself.
  bool whole = server.process(stream, request.last, client_closes,
                              [&request](Request& parsed) { parse_mismatch = parse_difference(request.head, parsed); });
  parse_mismatch.clear();
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
  f.deadlines.keep_alive_timeout = std::chrono::seconds(c.keep_alive_timeout_s);
  f.deadlines.header_timeout = std::chrono::milliseconds(c.header_timeout_ms);
  f.deadlines.body_timeout = std::chrono::milliseconds(c.body_timeout_ms);
  f.deadlines.write_timeout = std::chrono::seconds(c.write_timeout_s);
  f.deadlines.min_transfer_rate = c.min_transfer_rate;
  f.deadlines.min_body_rate = c.min_body_rate;
  f.max_buffered_body_bytes = c.max_buffered_body_bytes;
  f.max_requests_per_connection = c.keep_alive_max_requests;
  f.head_limits = {c.max_request_line_bytes, c.max_header_bytes, c.max_header_count};
  return f;
}

}  // namespace

Service::Service(ServerConfig config) : config_(std::move(config)) {}

Service::~Service() { stop(); }

void Service::start() {
  if (server_) throw std::logic_error("Service::start called twice");
  state_ = std::make_unique<ServiceState>(config_);
  // Meshes and images first: stored scenes place them by ref and name them by id.
  size_t meshes_loaded = state_->stores.meshes->load();
  size_t textures_loaded = state_->stores.textures->load();
  size_t loaded = state_->stores.scenes->load();
  if (!config_.data_dir.empty()) {
    state_->log("info", {{"event", "meshes_loaded"}, {"count", meshes_loaded}});
    state_->log("info", {{"event", "textures_loaded"}, {"count", textures_loaded}});
    state_->log("info", {{"event", "scenes_loaded"}, {"count", loaded}});
  }
  if (config_.store_url.empty() && config_.data_dir.empty()) {  // said, so nobody trusts a restart with them
    state_->log("warn", {{"event", "store_in_memory"},
                         {"reason",
                          "no --data-dir: stored scenes and meshes live only as long as this process; "
                          "give --data-dir DIR (ROOMRENDER_DATA_DIR) to keep them"}});
  }
  for (const std::string& problem : state_->catalogue->problems) {
    state_->log("warn", {{"event", "catalogue_entry_left_out"}, {"detail", problem}});
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
      front_config(config_), [routes, &state](const RequestHead& head) { return screen_head(*routes, state, head); },
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

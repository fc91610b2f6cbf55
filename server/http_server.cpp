// The HTTP service (see http_server.hpp). A request passes screen_request first (route, method and
// header checks, before any body byte is read), then its handler; handlers just throw, and the
// exception and error handlers turn whatever went wrong into problem+json via server/problem.hpp.
// One JSON log line per request goes to stderr when config.log_requests is set.
#include "server/http_server.hpp"

#include "render/pipeline.hpp"
#include "server/problem.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
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

// A route as the screen sees it. "GET" routes also answer HEAD, as httplib dispatches them.
struct Route {
  std::string method;
  std::string pattern;     // matched against the whole decoded path
  bool json_body = false;  // takes a JSON request body: needs Content-Length and a JSON media type
  httplib::Server::Handler handler;
  std::regex regex;
};

// Set when screening starts, read by the logger. httplib handles a request on one worker thread
// from screening to logging, so a thread_local needs no locking; requests httplib rejects before
// screening (a broken request line) log no duration.
thread_local std::optional<Clock::time_point> t_request_start;

void send_problem(Response& res, const Problem& problem) {
  res.status = problem.status;
  res.set_content(problem.body, problem_content_type);
}

void send_problem(Response& res, int status, std::string_view detail,
                  const std::vector<FieldError>& errors = {}) {
  send_problem(res, Problem{status, make_problem(status, "", detail, errors)});
}

// Ends the connection once `res` (already holding its body) is written. A request refused before
// its body was read leaves that body on the socket, where httplib would take it for the next
// request. httplib 0.11 decides keep-alive from the request before routing, but drops a connection
// whose content provider reports failure; so the body is handed over through a provider that writes
// all of it and then reports failure.
void close_after_response(Response& res) {
  auto body = std::make_shared<std::string>(std::move(res.body));
  res.body.clear();
  std::string type = res.get_header_value("Content-Type");
  res.headers.erase("Content-Type");
  res.set_header("Connection", "close");
  res.set_content_provider(body->size(), type, [body](size_t offset, size_t length, httplib::DataSink& sink) {
    sink.write(body->data() + offset, length);
    return false;
  });
}

std::optional<std::string> read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// "application/json; charset=utf-8" -> "application/json".
std::string media_type(const std::string& content_type) {
  std::string type = content_type.substr(0, content_type.find(';'));
  auto first = type.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return lowercase(type.substr(first, type.find_last_not_of(" \t") - first + 1));
}

// W3C Server-Timing with every stage timings_json reports, in its order, so this header and the
// CLI's timings line always name the same stages.
std::string server_timing(const RenderResult& result) {
  auto report = nlohmann::ordered_json::parse(timings_json(result.timings, result.stats));
  std::string header;
  char buffer[96];
  for (const auto& [name, ms] : report.at("timings_ms").items()) {
    std::snprintf(buffer, sizeof buffer, "%s%s;dur=%.3f", header.empty() ? "" : ", ", name.c_str(),
                  ms.get<double>());
    header += buffer;
  }
  return header;
}

void handle_render(const Request& req, Response& res) {
  EncodedRender out = render_request_text(req.body);  // InputError -> answer_exception
  res.status = 200;
  res.set_header("Server-Timing", server_timing(out.result));
  res.set_header("X-Scene-Id", out.scene_id);
  res.set_header("Cache-Control", "no-store");
  res.set_header("Content-Type", "image/png");
  res.body = std::move(out.png);
}

void handle_pipelines(const Request&, Response& res) {
  nlohmann::json list = nlohmann::json::array();
  for (const PipelineInfo& p : pipeline_table()) list.push_back({{"name", p.name}, {"summary", p.summary}});
  res.set_content(nlohmann::json{{"pipelines", list}}.dump(), "application/json");
}

void handle_health(const Request&, Response& res) {
  res.set_header("Cache-Control", "no-store");
  res.set_content(R"({"status":"ok"})", "application/json");
}

// Example names are [a-z0-9_]+ so a name can never leave the directory.
const std::regex example_name("[a-z0-9_]+");

httplib::Server::Handler make_examples_list_handler(std::filesystem::path dir) {
  return [dir](const Request&, Response& res) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      std::string stem = entry.path().stem().string();
      if (entry.path().extension() == ".json" && std::regex_match(stem, example_name)) {
        names.push_back(stem);
      }
    }
    std::sort(names.begin(), names.end());
    res.set_content(nlohmann::json{{"examples", names}}.dump(), "application/json");
  };
}

httplib::Server::Handler make_example_handler(std::filesystem::path dir) {
  return [dir](const Request& req, Response& res) {
    std::string name = req.matches[1];  // the route's pattern already admits only [a-z0-9_]+
    if (auto text = read_text_file(dir / (name + ".json"))) {
      res.set_content(*text, "application/json");
    } else {
      send_problem(res, 404, "There is no example named '" + name + "'.");
    }
  };
}

httplib::Server::Handler make_index_handler(std::filesystem::path dir) {
  return [dir](const Request&, Response& res) {
    auto text = read_text_file(dir / "index.html");
    if (!text) {
      send_problem(res, 404, "The web client is not installed on this server.");
      return;
    }
    // The page is self-contained: nothing may load from elsewhere.
    res.set_header("Content-Security-Policy",
                   "default-src 'self'; script-src 'self' 'unsafe-inline'; "
                   "style-src 'self' 'unsafe-inline'; img-src 'self' blob: data:");
    res.set_content(*text, "text/html; charset=utf-8");
  };
}

std::vector<Route> make_routes(const ServerConfig& config) {
  std::vector<Route> routes = {
      {"POST", "/v1/render", true, handle_render, {}},
      {"GET", "/v1/pipelines", false, handle_pipelines, {}},
      {"GET", "/healthz", false, handle_health, {}},
      {"GET", "/livez", false, handle_health, {}},
      {"GET", "/", false, make_index_handler(config.web_dir), {}},
      {"GET", "/examples/?", false, make_examples_list_handler(config.examples_dir), {}},
      {"GET", "/examples/([a-z0-9_]+)\\.json", false, make_example_handler(config.examples_dir), {}},
  };
  for (Route& r : routes) r.regex = std::regex(r.pattern);
  return routes;
}

// 404 for an unknown path, 405 (with Allow) for a known path and another method; else the route.
const Route* screen_route(const std::vector<Route>& routes, const Request& req, Response& res) {
  std::string allow;
  for (const Route& r : routes) {
    if (!std::regex_match(req.path, r.regex)) continue;
    if (r.method == req.method || (r.method == "GET" && req.method == "HEAD")) return &r;
    allow += (allow.empty() ? "" : ", ") + r.method + (r.method == "GET" ? ", HEAD" : "");
  }
  if (allow.empty()) {
    send_problem(res, 404, "There is no resource at this path.");
  } else {
    res.set_header("Allow", allow);
    send_problem(res, 405, req.method + " is not allowed here; use " + allow + ".");
  }
  return nullptr;
}

// Body framing we accept: only Content-Length (no Transfer-Encoding, whose chunked bodies httplib
// reads without a size limit), no Content-Encoding (a small gzip body can inflate without bound),
// at most max_body_bytes. Returns false after answering.
bool screen_body_headers(const Route& route, const ServerConfig& config, const Request& req, Response& res) {
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
    if (ec == std::errc::result_out_of_range || length > config.max_body_bytes) {
      send_problem(res, 413, "The body exceeds the limit of " + std::to_string(config.max_body_bytes) + " bytes.");
      return false;
    }
  } else if (route.json_body) {
    // Without either header httplib would read until the client closes the connection.
    send_problem(res, 411, "This request needs a Content-Length header.");
    return false;
  }
  std::string type = media_type(req.get_header_value("Content-Type"));
  if (route.json_body && !type.empty() && type != "application/json") {
    send_problem(res, 415, "Send the request as application/json.");
    return false;
  }
  return true;
}

// Runs before httplib reads the body (and before it answers "100 Continue").
HandlerResponse screen_request(const std::vector<Route>& routes, const ServerConfig& config,
                               const Request& req, Response& res) {
  t_request_start = Clock::now();
  const Route* route = screen_route(routes, req, res);
  if (route && screen_body_headers(*route, config, req, res)) return HandlerResponse::Unhandled;
  // A GET or HEAD without body framing has nothing left on the socket; anything else may.
  bool body_may_follow = (req.method != "GET" && req.method != "HEAD") || req.has_header("Content-Length") ||
                         req.has_header("Transfer-Encoding");
  if (body_may_follow) close_after_response(res);
  return HandlerResponse::Handled;
}

void write_log_line(const nlohmann::ordered_json& line) {
  std::string text = line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  std::fwrite(text.data(), 1, text.size(), stderr);  // one write per line keeps lines whole
}

void log_request(const Request& req, const Response& res) {
  // httplib has set Content-Length by now, also for bodies written through a provider.
  nlohmann::ordered_json line = {{"event", "request"}, {"method", req.method}, {"path", req.path},
                                 {"status", res.status},
                                 {"bytes", res.get_header_value<uint64_t>("Content-Length")},
                                 {"duration_ms", nullptr}};
  if (t_request_start) {
    line["duration_ms"] = std::chrono::duration<double, std::milli>(Clock::now() - *t_request_start).count();
  }
  t_request_start.reset();
  write_log_line(line);
}

void answer_exception(const Request& req, Response& res, std::exception_ptr error) {
  std::string log_detail;
  Problem problem = problem_from_exception(error, log_detail);
  if (!log_detail.empty()) {  // our fault, so always logged, with the text the client does not see
    write_log_line({{"event", "internal_error"}, {"method", req.method}, {"path", req.path},
                    {"detail", log_detail}});
  }
  res.headers.erase("Server-Timing");
  res.headers.erase("X-Scene-Id");
  send_problem(res, problem);
}

// httplib's own error answers (unparsable request, URI too long, ...) come without a body; give
// them a problem body too. Our answers always carry a Content-Type and are left alone.
HandlerResponse fill_error_body(const Request&, Response& res) {
  if (res.has_header("Content-Type")) return HandlerResponse::Unhandled;
  send_problem(res, status_problem(res.status));
  return HandlerResponse::Handled;
}

void configure_limits(httplib::Server& server, const ServerConfig& config) {
  // Backstop only: screen_request rejects large bodies before httplib would read them.
  server.set_payload_max_length(config.max_body_bytes);
  server.set_read_timeout(config.read_timeout_s, 0);
  server.set_write_timeout(config.write_timeout_s, 0);
  server.set_keep_alive_timeout(config.keep_alive_timeout_s);
  server.set_keep_alive_max_count(config.keep_alive_max_requests);
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"}});
  // httplib's default sets SO_REUSEPORT, which lets a second server bind the same port and take
  // half the connections; SO_REUSEADDR alone still allows a quick restart.
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // A fixed pool: connections beyond it wait in httplib's queue (0.11 cannot refuse them there).
  server.new_task_queue = [threads = worker_threads(config)] { return new httplib::ThreadPool(threads); };
}

std::unique_ptr<httplib::Server> make_server(const ServerConfig& config) {
  auto server = std::make_unique<httplib::Server>();
  configure_limits(*server, config);
  auto routes = std::make_shared<const std::vector<Route>>(make_routes(config));
  for (const Route& r : *routes) {
    if (r.method == "GET") server->Get(r.pattern, r.handler);
    if (r.method == "POST") server->Post(r.pattern, r.handler);
  }
  auto screen = [routes, config](const Request& req, Response& res) {
    return screen_request(*routes, config, req, res);
  };
  server->set_pre_routing_handler(screen);
  // curl sends "Expect: 100-continue" for larger bodies; answer a request we would reject at once
  // instead of inviting its body.
  server->set_expect_100_continue_handler([screen](const Request& req, Response& res) {
    if (screen(req, res) == HandlerResponse::Unhandled) return 100;
    // httplib writes this early answer without deriving Content-Length from the provider.
    if (!res.has_header("Content-Length")) res.set_header("Content-Length", std::to_string(res.content_length_));
    return res.status;
  });
  server->set_exception_handler(answer_exception);
  server->set_error_handler(httplib::Server::HandlerWithResponse(fill_error_body));
  if (config.log_requests) server->set_logger(log_request);
  return server;
}

}  // namespace

ServerConfig default_server_config() {
  ServerConfig config;
  config.web_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "clients" / "web";
  config.examples_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "examples";
  return config;
}

size_t worker_threads(const ServerConfig& config) {
  // Each open connection holds one worker for its keep-alive life, so browsers need a few.
  if (config.threads > 0) return size_t(config.threads);
  return std::max<size_t>(4, std::thread::hardware_concurrency());
}

Service::Service(ServerConfig config) : config_(std::move(config)) {}

Service::~Service() { stop(); }

void Service::start() {
  if (server_) throw std::logic_error("Service::start called twice");
  server_ = make_server(config_);
  int bound = config_.port == 0 ? server_->bind_to_any_port(config_.bind)
              : server_->bind_to_port(config_.bind, config_.port) ? config_.port
                                                                  : -1;
  if (bound < 0) {
    throw std::runtime_error("cannot listen on " + config_.bind + ":" + std::to_string(config_.port));
  }
  port_ = bound;
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    loop_exited_ = true;
  });
  // Until the accept loop runs, Server::stop() would do nothing and stop() would then wait forever.
  while (!server_->is_running() && !loop_exited_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (loop_exited_) {
    thread_.join();
    throw std::runtime_error("the accept loop on port " + std::to_string(port_) + " stopped at once");
  }
}

void Service::stop() {
  if (!server_) return;
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace rr::server

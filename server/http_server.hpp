// The HTTP service: ServerConfig -> routes and limits on an httplib::Server -> listen on a thread.
// Routes: POST /v1/render, GET /v1/pipelines, /healthz, /livez, /, /examples/, /examples/{name}.json.
// Every error is an RFC 9457 problem+json body (server/problem.hpp); requests whose headers already
// rule them out are answered before their body is read.
#pragma once

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace rr::server {

struct ServerConfig {
  std::string bind = "127.0.0.1";
  int port = 8080;  // 0: any free port, reported by Service::port()
  int threads = 0;  // worker threads (one per open connection); 0: hardware concurrency, at least 2
  std::filesystem::path web_dir;       // holds index.html, served at GET /
  std::filesystem::path examples_dir;  // holds <name>.json, served under /examples/
  size_t max_body_bytes = 8u << 20;    // larger bodies get 413 before they are read
  int read_timeout_s = 10;
  int write_timeout_s = 10;
  int keep_alive_timeout_s = 5;
  size_t keep_alive_max_requests = 100;
  bool log_requests = true;  // one JSON line per request on stderr; tests turn it off
};

// The defaults above, with web_dir and examples_dir pointing into the source tree.
ServerConfig default_server_config();

// The worker thread count config.threads stands for (resolving 0).
size_t worker_threads(const ServerConfig& config);

// One running server. start() binds and serves on a background thread until stop() (or
// destruction). Not copyable; start() may be called once.
class Service {
 public:
  explicit Service(ServerConfig config);
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  // Binds (port 0: any free port), starts the accept loop and returns once it runs. Throws
  // std::runtime_error when the address cannot be bound.
  void start();
  int port() const { return port_; }
  const ServerConfig& config() const { return config_; }
  // Stops accepting, finishes the requests in flight and joins the thread. Idempotent.
  void stop();

 private:
  ServerConfig config_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  std::atomic<bool> loop_exited_{false};
  int port_ = 0;
};

}  // namespace rr::server

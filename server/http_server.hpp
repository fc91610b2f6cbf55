// The HTTP service: ServerConfig -> routes on an httplib::Server -> a connection front that owns the
// sockets (server/connection_front.hpp) and hands complete requests to httplib on worker threads.
// The route table (server/routes.hpp) lists every endpoint; docs/api.md and schemas/openapi.json
// describe them. Every error is an RFC 9457 problem+json body (server/problem.hpp); requests whose
// headers already rule them out are answered before their body is read.
#pragma once

#include "server/server_config.hpp"

#include <memory>

namespace httplib {
class Server;
}

namespace rr::server {

struct ServiceState;
class ConnectionFront;

struct DrainReport {
  bool drained = true;   // every in-flight render finished within drain_timeout_ms
  double seconds = 0.0;  // from stop() to the last connection closed
};

// One running server. start() loads stored scenes, binds and serves on a background thread until
// stop() (or destruction). Not copyable; start() may be called once.
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
  // Graceful stop: readiness fails, no new connections are accepted, idle ones close, renders in
  // flight get up to drain_timeout_ms to finish (then they are cancelled and answer 503), and open
  // connections close after their current answer is written. Idempotent.
  DrainReport stop();

 private:
  ServerConfig config_;
  std::unique_ptr<ServiceState> state_;
  std::unique_ptr<httplib::Server> server_;
  std::unique_ptr<ConnectionFront> front_;
  int port_ = 0;
  bool stopped_ = false;
};

}  // namespace rr::server

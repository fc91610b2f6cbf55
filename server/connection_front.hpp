// The service's connection front: one epoll thread owns the listening socket, every client
// connection, every read and write, and every deadline and cap; a fixed pool of worker threads gets
// only complete requests (head and whole body, as bytes) and gives back complete answers (bytes).
// A slow or idle client therefore holds a connection record of a few hundred bytes, never a thread.
// The front parses each head (request_head.hpp) and asks `screen` whether the body is to be read at
// all, so a refused request's body never is; what a request means is not decided here: the `answer`
// callback (cpp-httplib on an in-memory stream, server/http_server.cpp) routes and answers, and
// `refusal` formats the answers the front gives itself (408, 414, 431, 501, 503).
// The parts: front_listener (the listening socket), front_deadlines (how long each phase may take),
// front_workers (the pool), and the event loop over connections in connection_front.cpp.
#pragma once

#include "server/front_deadlines.hpp"
#include "server/request_head.hpp"

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace rr::server {

struct FrontConfig {
  std::string bind = "127.0.0.1";
  int port = 8080;  // 0: any free port
  int listen_backlog = 1024;
  size_t workers = 8;      // threads running `answer`
  size_t max_pending = 8;  // complete requests waiting for a worker; beyond: 503
  size_t max_connections = 4096;
  size_t max_idle_connections = 512;
  DeadlinePolicy deadlines;
  uint64_t max_buffered_body_bytes = 512ull << 20;
  size_t max_requests_per_connection = 100;
  HeadLimits head_limits;
};

// A complete request handed to a worker.
struct FrontRequest {
  std::string bytes;  // head and body; with head_only, the head alone
  RequestHead head;   // the front's parse of the head in `bytes`
  // The body was not read: the head already rules the request out (screening refused it, or it is
  // chunked). The answer must come from the head alone, and the connection closes after it.
  bool head_only = false;
  // The connection closes after this answer (the client asked, draining, the request count).
  bool last = false;
  std::string remote_ip, local_ip;
  int remote_port = 0, local_port = 0;
};

struct FrontAnswer {
  std::string bytes;   // a whole HTTP response
  bool close = false;  // close the connection once it is written
  // Runs on the worker after the answer was handed to the front (work that must not delay it).
  std::function<void()> then;
};

// Why the front closed a connection itself (a label of roomrender_connections_closed_total).
enum class CloseReason {
  header_timeout,
  body_timeout,
  idle_timeout,
  idle_evicted,
  head_evicted,
  write_timeout,
  refused,
  count
};
std::string_view close_reason_name(CloseReason reason);

struct FrontStats {
  size_t reading = 0, processing = 0, writing = 0, idle = 0;  // open connections by state
  size_t pending = 0;                                         // requests waiting for a worker
  uint64_t accepted = 0;
  uint64_t closed[size_t(CloseReason::count)] = {};
  uint64_t shed = 0;  // 503s given by the front (pending queue, buffered body bytes, connection cap)
};

class ConnectionFront {
 public:
  // Screening's verdict on a head that announces a body: true when the body is to be read. Runs on
  // the event thread. False: the head goes to `answer` alone and the connection closes after it.
  using Screen = std::function<bool(const RequestHead& head)>;
  using Answer = std::function<FrontAnswer(FrontRequest&)>;
  // The whole response for a refusal the front makes itself; `close` says the connection closes.
  using Refusal = std::function<std::string(int status, std::string_view detail, bool close)>;

  ConnectionFront(FrontConfig config, Screen screen, Answer answer, Refusal refusal);
  ~ConnectionFront();
  ConnectionFront(const ConnectionFront&) = delete;
  ConnectionFront& operator=(const ConnectionFront&) = delete;

  // Binds and listens; returns the port. Throws std::runtime_error when it cannot. Lowers the
  // connection cap to what the process's descriptor limit allows (see max_connections()).
  int bind();
  size_t max_connections() const;
  // Starts the event thread and the workers.
  void start();
  // Closes the listening socket and idle connections; requests already arriving are still read and
  // answered with "Connection: close".
  void stop_accepting();
  // Waits until every connection has closed or `until`, closes the rest, joins every thread.
  void finish(std::chrono::steady_clock::time_point until);
  FrontStats stats() const;

  struct Loop;  // the event loop's state (front_loop.hpp), shared by the front's own files only

 private:
  std::unique_ptr<Loop> loop_;
};

}  // namespace rr::server

// The connection front's event loop, shared by its two files: connection_front.cpp runs the loop
// (accepting, deadlines, stopping, the counts it publishes) and front_exchange.cpp carries one
// connection through a request and its answer (reading, framing, screening, the body, handing the
// request to a worker, writing, keep-alive or linger). Every member is the event thread's, except
// the atomics, the published stats and what WorkerPool guards itself.
#pragma once

#include "server/connection_front.hpp"
#include "server/front_listener.hpp"
#include "server/front_workers.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>

struct epoll_event;

namespace rr::server {
namespace front {

//   head -> body -> processing (a worker has it) -> writing -> idle (keep-alive) or head (pipelined)
// and, when the connection is to close after an answer, writing -> linger (see front_exchange.cpp).
enum class Phase { head, body, processing, writing, idle, linger, count };

struct Connection {
  int fd = -1;
  uint64_t id = 0;
  Phase phase = Phase::head;
  FrontClock::time_point since;  // entered this phase
  FrontClock::time_point deadline = FrontClock::time_point::max();
  uint32_t interest = 0;      // epoll events asked for
  std::string in;             // received and not yet handed on
  size_t in_scanned = 0;      // bytes of `in` already looked at for a newline
  size_t line_start = 0;      // where the unfinished line of `in` begins
  bool head_started = false;  // a byte of the current request arrived
  RequestHead head;
  uint64_t budget = 0;  // counted in buffered_body_bytes
  std::string out;
  size_t out_sent = 0;
  bool close_after_write = false;
  size_t served = 0;
  size_t lingered = 0;
  PeerAddresses peer;
};

}  // namespace front

struct ConnectionFront::Loop {
  using Connection = front::Connection;
  using Phase = front::Phase;

  static constexpr size_t read_chunk = 64 * 1024;

  Loop(FrontConfig config, Screen screen, Answer answer, Refusal refusal);
  ~Loop();

  FrontConfig config;
  Screen screen;
  Refusal refusal;
  Listener listener;
  WorkerPool workers;
  int epoll_fd = -1, wake_fd = -1;
  std::thread thread;

  std::unordered_map<uint64_t, std::unique_ptr<Connection>> connections;
  Deadlines deadlines;
  uint64_t next_id = 2;  // 0 and 1 are the listening socket and the eventfd
  uint64_t buffered_body_bytes = 0;
  size_t in_phase[size_t(Phase::count)] = {};
  FrontClock::time_point accept_resume = FrontClock::time_point::min();
  bool stopping = false;
  char scratch[read_chunk];

  // Shared with the controlling thread.
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> finish_requested{false};
  std::atomic<int64_t> finish_deadline_ns{0};
  mutable std::mutex stats_mutex;
  FrontStats published;
  FrontStats counters;  // accepted, closed, shed: event thread only, copied into `published`

  // connection_front.cpp: the loop.
  void wake();
  void open_loop();
  void run();
  void on_event(const epoll_event& event, FrontClock::time_point now);
  void accept_connections(FrontClock::time_point now);
  void add_connection(int fd, PeerAddresses peer, FrontClock::time_point now);
  bool evict_one();
  Connection* oldest_in(Phase phase);
  void on_deadline(Connection& c, FrontClock::time_point now);
  int wait_ms(FrontClock::time_point now) const;
  void begin_stopping();
  void publish();
  void set_deadline(Connection& c, FrontClock::time_point deadline);
  void set_phase(Connection& c, Phase phase, FrontClock::time_point now);
  void set_interest(Connection& c, uint32_t events);
  void release_budget(Connection& c);
  void close_connection(Connection& c, std::optional<CloseReason> reason = std::nullopt);

  // front_exchange.cpp: one connection's requests and answers.
  void on_readable(Connection& c, FrontClock::time_point now);
  void advance(Connection& c, FrontClock::time_point now);
  bool read_head(Connection& c, FrontClock::time_point now);
  bool body_wanted(const RequestHead& head);
  void dispatch(Connection& c, FrontRequest request, FrontClock::time_point now);
  void collect_answers(FrontClock::time_point now);
  void refuse(Connection& c, int status, std::string_view detail, bool close, FrontClock::time_point now);
  void write_answer(Connection& c, std::string bytes, bool close, FrontClock::time_point now);
  void send_bytes(Connection& c, std::string bytes);
  void flush(Connection& c, FrontClock::time_point now);
  void answered(Connection& c, FrontClock::time_point now);
};

}  // namespace rr::server

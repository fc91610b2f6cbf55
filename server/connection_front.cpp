// The connection front's event loop (see connection_front.hpp and front_loop.hpp). One thread runs
// epoll over the listening socket, an eventfd that workers ring when an answer is ready, and every
// connection; this file is the loop itself: accepting under the connection cap, the deadlines of
// every phase, stopping, and the counts it publishes. One connection's request and answer are
// front_exchange.cpp's.
#include "server/front_loop.hpp"

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>
#include <vector>

namespace rr::server {

std::string_view close_reason_name(CloseReason reason) {
  static constexpr std::string_view names[] = {"header_timeout", "body_timeout",  "idle_timeout", "idle_evicted",
                                               "head_evicted",   "write_timeout", "refused"};
  static_assert(std::size(names) == size_t(CloseReason::count));
  return reason < CloseReason::count ? names[size_t(reason)] : "?";
}

namespace {

using Clock = FrontClock;
using std::chrono::milliseconds;

constexpr uint64_t listen_key = 0;
constexpr uint64_t wake_key = 1;
constexpr size_t max_accepts_per_wakeup = 256;
constexpr milliseconds accept_pause{100};  // after running out of file descriptors

}  // namespace

using Loop = ConnectionFront::Loop;

Loop::Loop(FrontConfig c, Screen s, Answer a, Refusal r)
    : config(std::move(c)),
      screen(std::move(s)),
      refusal(std::move(r)),
      workers(
          config.max_pending, std::move(a),
          [this] {
            return FrontAnswer{refusal(500, "The server failed to answer this request.", true), true, nullptr};
          },
          [this] { wake(); }) {}

Loop::~Loop() {
  for (auto& [id, connection] : connections) ::close(connection->fd);
  for (int fd : {wake_fd, epoll_fd}) {
    if (fd >= 0) ::close(fd);
  }
}

void Loop::wake() {
  uint64_t one = 1;
  [[maybe_unused]] ssize_t n = ::write(wake_fd, &one, sizeof one);
}

void Loop::open_loop() {
  epoll_fd = epoll_create1(EPOLL_CLOEXEC);
  wake_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (epoll_fd < 0 || wake_fd < 0) throw std::runtime_error("cannot create the event loop");
  epoll_event event{};
  event.events = EPOLLIN;
  event.data.u64 = wake_key;
  epoll_ctl(epoll_fd, EPOLL_CTL_ADD, wake_fd, &event);
  listener.watch(epoll_fd, listen_key, true);
}

// ---- accepting: below the cap, else make room by eviction, else 503 ----

void Loop::accept_connections(Clock::time_point now) {
  for (size_t i = 0; i < max_accepts_per_wakeup; ++i) {
    int fd = -1;
    PeerAddresses peer;
    Listener::Accept got = listener.accept_one(fd, peer);
    if (got == Listener::Accept::out_of_descriptors) {
      // Level-triggered, the listener would wake the loop at once again: wait for descriptors.
      listener.watch(epoll_fd, listen_key, false);
      accept_resume = now + accept_pause;
    }
    if (got != Listener::Accept::accepted) return;
    ++counters.accepted;
    if (connections.size() >= config.max_connections && !evict_one()) {
      // Every connection is busy with a request: refuse this one rather than queue it unseen.
      std::string answer = refusal(503, "The server holds as many connections as it takes; retry shortly.", true);
      [[maybe_unused]] ssize_t n = ::send(fd, answer.data(), answer.size(), MSG_NOSIGNAL);
      ::close(fd);
      ++counters.closed[size_t(CloseReason::refused)];
      ++counters.shed;
      continue;
    }
    add_connection(fd, std::move(peer), now);
  }
}

void Loop::add_connection(int fd, PeerAddresses peer, Clock::time_point now) {
  auto connection = std::make_unique<Connection>();
  Connection& c = *connection;
  c.fd = fd;
  c.id = next_id++;
  c.peer = std::move(peer);
  epoll_event event{};
  event.events = EPOLLIN;
  event.data.u64 = c.id;
  if (epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &event) != 0) {
    ::close(fd);
    return;
  }
  c.interest = EPOLLIN;
  connections.emplace(c.id, std::move(connection));
  ++in_phase[size_t(Phase::head)];
  c.since = now;
  // The first request's head must arrive within header_timeout of the accept.
  set_deadline(c, now + config.deadlines.header_timeout);
}

// Makes room for one connection: the oldest idle keep-alive connection, else the oldest one still
// waiting for its request head (a client that takes that long is the likeliest to be an attack).
bool Loop::evict_one() {
  Connection* victim = oldest_in(Phase::idle);
  CloseReason reason = CloseReason::idle_evicted;
  if (!victim) {
    victim = oldest_in(Phase::head);
    reason = CloseReason::head_evicted;
  }
  if (!victim) return false;
  close_connection(*victim, reason);
  return true;
}

Loop::Connection* Loop::oldest_in(Phase phase) {
  Connection* oldest = nullptr;
  if (in_phase[size_t(phase)] == 0) return nullptr;
  for (auto& [id, c] : connections) {
    // Connections accepted in one turn share `since`; the lower id was accepted first.
    if (c->phase == phase && (!oldest || std::pair(c->since, c->id) < std::pair(oldest->since, oldest->id))) {
      oldest = c.get();
    }
  }
  return oldest;
}

// ---- bookkeeping ----

void Loop::set_deadline(Connection& c, Clock::time_point deadline) { deadlines.move(c.id, c.deadline, deadline); }

void Loop::set_phase(Connection& c, Phase phase, Clock::time_point now) {
  --in_phase[size_t(c.phase)];
  ++in_phase[size_t(phase)];
  c.phase = phase;
  c.since = now;
}

void Loop::set_interest(Connection& c, uint32_t events) {
  if (events == c.interest) return;
  epoll_event event{};
  event.events = events;
  event.data.u64 = c.id;
  epoll_ctl(epoll_fd, EPOLL_CTL_MOD, c.fd, &event);
  c.interest = events;
}

void Loop::release_budget(Connection& c) {
  buffered_body_bytes -= c.budget;
  c.budget = 0;
}

void Loop::close_connection(Connection& c, std::optional<CloseReason> reason) {
  if (reason) ++counters.closed[size_t(*reason)];
  release_budget(c);
  set_deadline(c, Clock::time_point::max());
  --in_phase[size_t(c.phase)];
  epoll_ctl(epoll_fd, EPOLL_CTL_DEL, c.fd, nullptr);
  ::close(c.fd);
  connections.erase(c.id);  // destroys c
}

// ---- deadlines ----

void Loop::on_deadline(Connection& c, Clock::time_point now) {
  c.deadline = Clock::time_point::max();  // Deadlines::pop_due took it out of the set
  switch (c.phase) {
    case Phase::idle:
      close_connection(c, CloseReason::idle_timeout);
      break;
    case Phase::head:
      if (!c.head_started) {
        close_connection(c, CloseReason::header_timeout);
      } else {
        ++counters.closed[size_t(CloseReason::header_timeout)];
        refuse(c, 408,
               "The request head did not arrive within " + std::to_string(config.deadlines.header_timeout.count()) +
                   " ms.",
               true, now);
      }
      break;
    case Phase::body:
      ++counters.closed[size_t(CloseReason::body_timeout)];
      refuse(c, 408, late_body_detail(config.deadlines), true, now);
      break;
    case Phase::writing:
      close_connection(c, CloseReason::write_timeout);
      break;
    default:
      close_connection(c);
      break;
  }
}

int Loop::wait_ms(Clock::time_point now) const {
  Clock::time_point next = deadlines.next();
  if (!listener.watched() && !stopping && accept_resume != Clock::time_point::min()) {
    next = std::min(next, accept_resume);
  }
  if (finish_requested) next = std::min(next, Clock::time_point(Clock::duration(finish_deadline_ns.load())));
  if (next == Clock::time_point::max()) return -1;
  if (next <= now) return 0;
  return int(std::min<int64_t>(std::chrono::ceil<milliseconds>(next - now).count(), 60'000));
}

// ---- stopping, counts and the loop ----

void Loop::begin_stopping() {
  stopping = true;
  listener.close();
  std::vector<Connection*> quiet;
  for (auto& [id, c] : connections) {
    if (c->phase == Phase::idle || (c->phase == Phase::head && c->in.empty())) quiet.push_back(c.get());
  }
  for (Connection* c : quiet) close_connection(*c);
}

void Loop::publish() {
  std::lock_guard lock(stats_mutex);
  published = counters;
  published.reading = in_phase[size_t(Phase::head)] + in_phase[size_t(Phase::body)];
  published.processing = in_phase[size_t(Phase::processing)];
  published.writing = in_phase[size_t(Phase::writing)] + in_phase[size_t(Phase::linger)];
  published.idle = in_phase[size_t(Phase::idle)];
  published.pending = workers.pending();
}

void Loop::on_event(const epoll_event& event, Clock::time_point now) {
  const uint64_t key = event.data.u64;
  if (key == listen_key) {
    if (listener.watched()) accept_connections(now);
    return;
  }
  if (key == wake_key) return collect_answers(now);
  auto it = connections.find(key);
  if (it == connections.end()) return;
  Connection& c = *it->second;
  if (event.events & EPOLLERR) return close_connection(c);
  if (event.events & EPOLLOUT) {
    flush(c, now);
    if (!connections.count(key)) return;
  }
  if (event.events & (EPOLLIN | EPOLLHUP)) {
    if (c.interest & EPOLLIN) {
      on_readable(c, now);
    } else if (event.events & EPOLLHUP) {
      close_connection(c);  // gone while its request is processed: drop the answer
    }
  }
}

void Loop::run() {
  epoll_event events[256];
  for (;;) {
    int n = epoll_wait(epoll_fd, events, 256, wait_ms(Clock::now()));
    Clock::time_point now = Clock::now();
    for (int i = 0; i < n; ++i) on_event(events[i], now);
    if (stop_requested && !stopping) begin_stopping();
    if (!listener.watched() && !stopping && now >= accept_resume) listener.watch(epoll_fd, listen_key, true);
    for (uint64_t id = 0; deadlines.pop_due(now, id);) {
      auto it = connections.find(id);
      if (it != connections.end()) on_deadline(*it->second, now);
    }
    publish();
    if (finish_requested) {
      bool past = now >= Clock::time_point(Clock::duration(finish_deadline_ns.load()));
      if (connections.empty() || past) break;
    }
  }
  std::vector<Connection*> rest;
  for (auto& [id, c] : connections) rest.push_back(c.get());
  for (Connection* c : rest) close_connection(*c);
  publish();
}

ConnectionFront::ConnectionFront(FrontConfig config, Screen screen, Answer answer, Refusal refusal)
    : loop_(std::make_unique<Loop>(std::move(config), std::move(screen), std::move(answer), std::move(refusal))) {}

ConnectionFront::~ConnectionFront() { finish(Clock::now()); }

int ConnectionFront::bind() {
  // Past the descriptor limit accept() would fail instead of evicting: the cap follows the limit.
  loop_->config.max_connections = raise_descriptor_limit(loop_->config.max_connections);
  return loop_->listener.bind(loop_->config.bind, loop_->config.port, loop_->config.listen_backlog);
}

void ConnectionFront::start() {
  loop_->open_loop();
  loop_->workers.start(loop_->config.workers);
  loop_->thread = std::thread([this] { loop_->run(); });
}

void ConnectionFront::stop_accepting() {
  loop_->stop_requested = true;
  loop_->wake();
}

void ConnectionFront::finish(std::chrono::steady_clock::time_point until) {
  loop_->stop_requested = true;
  loop_->finish_deadline_ns = until.time_since_epoch().count();
  loop_->finish_requested = true;
  if (loop_->wake_fd >= 0) loop_->wake();
  if (loop_->thread.joinable()) loop_->thread.join();
  loop_->workers.stop();
}

size_t ConnectionFront::max_connections() const { return loop_->config.max_connections; }

FrontStats ConnectionFront::stats() const {
  std::lock_guard lock(loop_->stats_mutex);
  return loop_->published;
}

}  // namespace rr::server

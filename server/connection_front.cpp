// The connection front (see connection_front.hpp). One thread runs an epoll loop over the listening
// socket, an eventfd that workers ring when an answer is ready, and every connection. A connection
// moves through phases:
//   head -> body -> processing (a worker has it) -> writing -> idle (keep-alive) or head (pipelined)
// and, when it is to close after an answer, through linger: the write side is shut and what the
// client still sends is read and dropped for a moment, so closing with unread bytes does not reset
// the connection and destroy the answer before the client has read it.
// Each phase but processing has a deadline, kept in one ordered set; the loop sleeps until the
// nearest. Reading stops while a request is processed or answered, so a client that pipelines gets
// its answers in order and the bytes buffered per connection stay bounded by one head or one body.
#include "server/connection_front.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>
#include <unordered_map>
#include <vector>

namespace rr::server {

std::string_view close_reason_name(CloseReason reason) {
  switch (reason) {
    case CloseReason::header_timeout:
      return "header_timeout";
    case CloseReason::body_timeout:
      return "body_timeout";
    case CloseReason::idle_timeout:
      return "idle_timeout";
    case CloseReason::idle_evicted:
      return "idle_evicted";
    case CloseReason::head_evicted:
      return "head_evicted";
    case CloseReason::write_timeout:
      return "write_timeout";
    case CloseReason::refused:
      return "refused";
    case CloseReason::count:
      break;
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

constexpr uint64_t listen_key = 0;
constexpr uint64_t wake_key = 1;
constexpr size_t read_chunk = 64 * 1024;
constexpr size_t max_accepts_per_wakeup = 256;
constexpr milliseconds linger_time{1000};
constexpr size_t linger_max_bytes = 1u << 20;
constexpr milliseconds accept_pause{100};  // after running out of file descriptors

enum class Phase { head, body, processing, writing, idle, linger, count };

struct Connection {
  int fd = -1;
  uint64_t id = 0;
  Phase phase = Phase::head;
  Clock::time_point since;  // entered this phase
  Clock::time_point deadline = Clock::time_point::max();
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
  std::string remote_ip, local_ip;
  int remote_port = 0, local_port = 0;
};

struct Job {
  uint64_t id;
  FrontRequest request;
};

struct Done {
  uint64_t id;
  FrontAnswer answer;
};

void address_text(const sockaddr_storage& address, std::string& ip, int& port) {
  char text[INET6_ADDRSTRLEN] = {};
  if (address.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(address);
    inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
    port = ntohs(v4.sin_port);
  } else if (address.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(address);
    inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
    port = ntohs(v6.sin6_port);
  }
  ip = text;
}

// Time to move `bytes` at `rate` bytes per second, on top of a base timeout.
milliseconds transfer_allowance(milliseconds base, uint64_t bytes, uint64_t rate) {
  return base + milliseconds(rate ? bytes * 1000 / rate : 0);
}

// Descriptors kept free of client connections: the listening socket, epoll, eventfd, and the files
// workers open (stored scenes, schemas, the web page).
constexpr size_t reserved_descriptors = 128;

// There must be a descriptor for every connection the front may hold; the soft limit is often 1024.
// Raises it as far as the hard limit allows and returns how many connections fit.
size_t raise_descriptor_limit(size_t connections) {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0) return connections;
  rlim_t wanted = rlim_t(connections + reserved_descriptors);
  if (limit.rlim_cur < wanted) {
    limit.rlim_cur = limit.rlim_max == RLIM_INFINITY ? wanted : std::min(wanted, limit.rlim_max);
    setrlimit(RLIMIT_NOFILE, &limit);
    getrlimit(RLIMIT_NOFILE, &limit);
  }
  if (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur >= wanted) return connections;
  return size_t(std::max<rlim_t>(limit.rlim_cur, 2 * reserved_descriptors) - reserved_descriptors);
}

}  // namespace

struct ConnectionFront::Loop {
  FrontConfig config;
  BodyLimit body_limit;
  Answer answer;
  Refusal refusal;

  int epoll_fd = -1, listen_fd = -1, wake_fd = -1;
  std::thread thread;
  std::vector<std::thread> workers;

  // Owned by the loop thread.
  std::unordered_map<uint64_t, std::unique_ptr<Connection>> connections;
  std::set<std::pair<Clock::time_point, uint64_t>> timers;
  uint64_t next_id = 2;  // 0 and 1 are the listening socket and the eventfd
  uint64_t buffered_body_bytes = 0;
  size_t in_phase[size_t(Phase::count)] = {};
  Clock::time_point accept_resume = Clock::time_point::min();
  bool listening = false;
  bool stopping = false;
  char scratch[read_chunk];

  // Shared with workers and the controlling thread.
  std::mutex jobs_mutex;
  std::condition_variable jobs_ready;
  std::deque<Job> jobs;
  bool workers_stop = false;
  std::mutex done_mutex;
  std::vector<Done> done;
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> finish_requested{false};
  std::atomic<int64_t> finish_deadline_ns{0};

  mutable std::mutex stats_mutex;
  FrontStats published;
  FrontStats counters;  // accepted, closed, shed: loop thread only, copied into `published`

  Loop(FrontConfig c, BodyLimit b, Answer a, Refusal r)
      : config(std::move(c)), body_limit(std::move(b)), answer(std::move(a)), refusal(std::move(r)) {}

  ~Loop() {
    for (auto& [id, connection] : connections) ::close(connection->fd);
    for (int fd : {listen_fd, wake_fd, epoll_fd}) {
      if (fd >= 0) ::close(fd);
    }
  }

  void wake() {
    uint64_t one = 1;
    [[maybe_unused]] ssize_t n = ::write(wake_fd, &one, sizeof one);
  }

  // ---- listening ----

  int bind_and_listen() {
    // Past the descriptor limit accept() would fail instead of evicting: the cap follows the limit.
    config.max_connections = raise_descriptor_limit(config.max_connections);
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    addrinfo* found = nullptr;
    std::string port = std::to_string(config.port);
    if (getaddrinfo(config.bind.c_str(), port.c_str(), &hints, &found) != 0 || !found) {
      throw std::runtime_error("cannot resolve the bind address " + config.bind);
    }
    for (addrinfo* a = found; a && listen_fd < 0; a = a->ai_next) {
      int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
      if (fd < 0) continue;
      // SO_REUSEADDR allows a quick restart; SO_REUSEPORT is left off, so a second server cannot
      // bind the same port and take half the connections.
      int yes = 1;
      setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
      if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0 && ::listen(fd, config.listen_backlog) == 0) {
        listen_fd = fd;
      } else {
        ::close(fd);
      }
    }
    freeaddrinfo(found);
    if (listen_fd < 0) throw std::runtime_error("cannot listen on " + config.bind + ":" + port);
    sockaddr_storage local{};
    socklen_t length = sizeof local;
    getsockname(listen_fd, reinterpret_cast<sockaddr*>(&local), &length);
    std::string ip;
    int bound = 0;
    address_text(local, ip, bound);
    return bound;
  }

  void open_loop() {
    epoll_fd = epoll_create1(EPOLL_CLOEXEC);
    wake_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (epoll_fd < 0 || wake_fd < 0) throw std::runtime_error("cannot create the event loop");
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.u64 = wake_key;
    epoll_ctl(epoll_fd, EPOLL_CTL_ADD, wake_fd, &event);
    set_listening(true);
  }

  void set_listening(bool on) {
    if (on == listening || listen_fd < 0) return;
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.u64 = listen_key;
    epoll_ctl(epoll_fd, on ? EPOLL_CTL_ADD : EPOLL_CTL_DEL, listen_fd, &event);
    listening = on;
  }

  void accept_connections(Clock::time_point now) {
    for (size_t i = 0; i < max_accepts_per_wakeup; ++i) {
      sockaddr_storage peer{};
      socklen_t length = sizeof peer;
      int fd = accept4(listen_fd, reinterpret_cast<sockaddr*>(&peer), &length, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno == EINTR || errno == ECONNABORTED) continue;
        if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
          // Level-triggered, the listener would wake the loop at once again: wait for descriptors.
          set_listening(false);
          accept_resume = now + accept_pause;
        }
        return;
      }
      ++counters.accepted;
      if (connections.size() >= config.max_connections && !evict_one()) {
        // Every connection is busy with a request: refuse this one rather than queue it unseen.
        std::string answer_bytes =
            refusal(503, "The server holds as many connections as it takes; retry shortly.", true);
        [[maybe_unused]] ssize_t n = ::send(fd, answer_bytes.data(), answer_bytes.size(), MSG_NOSIGNAL);
        ::close(fd);
        ++counters.closed[size_t(CloseReason::refused)];
        ++counters.shed;
        continue;
      }
      add_connection(fd, peer, now);
    }
  }

  void add_connection(int fd, const sockaddr_storage& peer, Clock::time_point now) {
    int yes = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    auto connection = std::make_unique<Connection>();
    Connection& c = *connection;
    c.fd = fd;
    c.id = next_id++;
    address_text(peer, c.remote_ip, c.remote_port);
    sockaddr_storage local{};
    socklen_t length = sizeof local;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length) == 0)
      address_text(local, c.local_ip, c.local_port);
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
    set_deadline(c, now + config.header_timeout);
  }

  // Makes room for one connection: the oldest idle keep-alive connection, else the oldest one still
  // waiting for its request head (a client that takes that long is the likeliest to be an attack).
  bool evict_one() {
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

  Connection* oldest_in(Phase phase) {
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

  void set_deadline(Connection& c, Clock::time_point deadline) {
    if (c.deadline != Clock::time_point::max()) timers.erase({c.deadline, c.id});
    c.deadline = deadline;
    if (deadline != Clock::time_point::max()) timers.insert({deadline, c.id});
  }

  void set_phase(Connection& c, Phase phase, Clock::time_point now) {
    --in_phase[size_t(c.phase)];
    ++in_phase[size_t(phase)];
    c.phase = phase;
    c.since = now;
  }

  void set_interest(Connection& c, uint32_t events) {
    if (events == c.interest) return;
    epoll_event event{};
    event.events = events;
    event.data.u64 = c.id;
    epoll_ctl(epoll_fd, EPOLL_CTL_MOD, c.fd, &event);
    c.interest = events;
  }

  void release_budget(Connection& c) {
    buffered_body_bytes -= c.budget;
    c.budget = 0;
  }

  void close_connection(Connection& c, std::optional<CloseReason> reason = std::nullopt) {
    if (reason) ++counters.closed[size_t(*reason)];
    release_budget(c);
    set_deadline(c, Clock::time_point::max());
    --in_phase[size_t(c.phase)];
    epoll_ctl(epoll_fd, EPOLL_CTL_DEL, c.fd, nullptr);
    ::close(c.fd);
    connections.erase(c.id);  // destroys c
  }

  // ---- reading ----

  void on_readable(Connection& c, Clock::time_point now) {
    if (c.phase == Phase::processing || c.phase == Phase::writing) return;
    ssize_t n = ::recv(c.fd, scratch, sizeof scratch, 0);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    if (n <= 0) {
      close_connection(c);
      return;
    }
    if (c.phase == Phase::linger) {
      c.lingered += size_t(n);
      if (c.lingered > linger_max_bytes) close_connection(c);
      return;
    }
    c.in.append(scratch, size_t(n));
    advance(c, now);
  }

  void reset_scan(Connection& c) {
    c.in_scanned = 0;
    c.line_start = 0;
  }

  // Frames as much of `in` as has arrived: a head, then its body, then hands the request on.
  void advance(Connection& c, Clock::time_point now) {
    if (c.phase == Phase::idle || c.phase == Phase::head) {
      size_t blank = leading_empty_lines(c.in);
      if (blank) {
        c.in.erase(0, blank);
        reset_scan(c);
      }
      if (c.in.empty()) return;
      if (c.phase == Phase::idle) {
        set_phase(c, Phase::head, now);
        set_deadline(c, now + config.header_timeout);
      }
      c.head_started = true;
      if (!read_head(c, now)) return;
    }
    if (c.phase == Phase::body) {
      const size_t need = c.head.head_bytes + c.head.content_length;
      if (c.in.size() < need) return;
      FrontRequest request;
      request.bytes = c.in.substr(0, need);
      c.in.erase(0, need);
      // A large body's buffer is not kept for the connection's next request.
      if (c.in.capacity() > 2 * read_chunk) c.in.shrink_to_fit();
      reset_scan(c);
      release_budget(c);
      dispatch(c, std::move(request), now);
    }
  }

  // Scans the head when a line has ended (or a cap may be crossed); true once a body phase begins.
  bool read_head(Connection& c, Clock::time_point now) {
    const HeadLimits& limits = config.head_limits;
    size_t newline = c.in.find('\n', c.in_scanned);
    c.in_scanned = c.in.size();
    if (newline == std::string::npos) {
      bool cap_reached =
          c.in.size() - c.line_start > limits.max_request_line_bytes + 1 || c.in.size() > limits.max_header_bytes;
      if (!cap_reached) return false;
    } else {
      c.line_start = c.in.rfind('\n') + 1;
    }
    HeadScan scan = scan_head(c.in, limits);
    if (scan.status == HeadStatus::incomplete) return false;
    if (scan.status != HeadStatus::complete) {
      refuse(c, head_status_code(scan.status), scan.detail, true, now);
      return false;
    }
    c.head = std::move(scan.head);
    const uint64_t length = c.head.content_length;
    if (c.head.has_transfer_encoding || length > body_limit(c.head.method, c.head.target)) {
      // The answer follows from the head alone; the body stays unread and the connection closes.
      FrontRequest request;
      request.bytes = c.in.substr(0, c.head.head_bytes);
      request.head_only = true;
      c.in.clear();
      reset_scan(c);
      dispatch(c, std::move(request), now);
      return false;
    }
    if (length > 0 && buffered_body_bytes + length > config.max_buffered_body_bytes) {
      refuse(c, 503, "The server is receiving as many request bodies as it holds at once; retry shortly.", true, now);
      ++counters.shed;
      return false;
    }
    c.budget = length;
    buffered_body_bytes += length;
    if (c.head.expects_continue) {
      // Answered here, so the worker must not see the Expect line and answer it again.
      c.in.erase(c.head.expect_begin, c.head.expect_end - c.head.expect_begin);
      c.head.head_bytes -= c.head.expect_end - c.head.expect_begin;
      reset_scan(c);
      const uint64_t id = c.id;
      if (c.in.size() < c.head.head_bytes + length) send_bytes(c, "HTTP/1.1 100 Continue\r\n\r\n");
      if (!connections.count(id)) return false;  // the write failed and closed it
    }
    set_phase(c, Phase::body, now);
    set_deadline(c, now + transfer_allowance(config.body_timeout, length, config.min_transfer_rate));
    return true;
  }

  void dispatch(Connection& c, FrontRequest request, Clock::time_point now) {
    request.last = request.last || request.head_only || stopping || c.served + 1 >= config.max_requests_per_connection;
    request.remote_ip = c.remote_ip;
    request.remote_port = c.remote_port;
    request.local_ip = c.local_ip;
    request.local_port = c.local_port;
    {
      std::lock_guard lock(jobs_mutex);
      if (jobs.size() < config.max_pending) {
        jobs.push_back({c.id, std::move(request)});
        jobs_ready.notify_one();
        set_phase(c, Phase::processing, now);
        set_deadline(c, Clock::time_point::max());
        set_interest(c, c.out.empty() ? 0u : uint32_t(EPOLLOUT));
        return;
      }
    }
    ++counters.shed;
    refuse(c, 503, "Every request worker is busy and the queue is full; retry shortly.", request.head_only, now);
  }

  // ---- writing ----

  // Queues a whole answer the front made itself and writes what the socket takes now.
  void refuse(Connection& c, int status, std::string_view detail, bool close, Clock::time_point now) {
    if (close) release_budget(c);
    write_answer(c, refusal(status, detail, close), close, now);
  }

  void write_answer(Connection& c, std::string bytes, bool close, Clock::time_point now) {
    c.close_after_write = c.close_after_write || close;
    set_phase(c, Phase::writing, now);
    // No reading while an answer is written: a client that sends without reading would otherwise
    // grow `in` for as long as it likes.
    set_interest(c, 0);
    set_deadline(c,
                 now + transfer_allowance(config.write_timeout, bytes.size() + c.out.size(), config.min_transfer_rate));
    send_bytes(c, std::move(bytes));
  }

  void send_bytes(Connection& c, std::string bytes) {
    if (c.out.empty()) {
      c.out = std::move(bytes);
      c.out_sent = 0;
    } else {
      c.out += bytes;
    }
    flush(c, Clock::now());
  }

  // Writes what the socket takes; once `out` is empty, an answer is complete.
  void flush(Connection& c, Clock::time_point now) {
    while (c.out_sent < c.out.size()) {
      ssize_t n = ::send(c.fd, c.out.data() + c.out_sent, c.out.size() - c.out_sent, MSG_NOSIGNAL);
      if (n > 0) {
        c.out_sent += size_t(n);
      } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
        set_interest(c, (c.interest & EPOLLIN) | EPOLLOUT);
        return;
      } else {
        close_connection(c);
        return;
      }
    }
    c.out = std::string();  // releases a large answer's buffer
    c.out_sent = 0;
    if (c.phase == Phase::writing) {
      answered(c, now);
    } else {
      set_interest(c, c.interest & ~uint32_t(EPOLLOUT));
    }
  }

  void answered(Connection& c, Clock::time_point now) {
    if (c.close_after_write || stopping) {
      // Shut the write side, then read and drop what the client still sends, briefly.
      ::shutdown(c.fd, SHUT_WR);
      set_phase(c, Phase::linger, now);
      set_deadline(c, now + linger_time);
      c.in.clear();
      set_interest(c, EPOLLIN);
      return;
    }
    c.head_started = false;
    if (c.in.empty()) {
      set_phase(c, Phase::idle, now);
      set_deadline(c, now + config.keep_alive_timeout);
      set_interest(c, EPOLLIN);
      if (in_phase[size_t(Phase::idle)] > config.max_idle_connections) {
        if (Connection* oldest = oldest_in(Phase::idle)) close_connection(*oldest, CloseReason::idle_evicted);
      }
      return;
    }
    // A pipelined request is already here.
    set_phase(c, Phase::head, now);
    set_deadline(c, now + config.header_timeout);
    set_interest(c, EPOLLIN);
    advance(c, now);
  }

  // ---- answers from workers ----

  void collect_answers(Clock::time_point now) {
    uint64_t count = 0;
    [[maybe_unused]] ssize_t n = ::read(wake_fd, &count, sizeof count);
    std::vector<Done> ready;
    {
      std::lock_guard lock(done_mutex);
      ready.swap(done);
    }
    for (Done& d : ready) {
      auto it = connections.find(d.id);
      if (it == connections.end()) continue;  // the client went away meanwhile
      Connection& c = *it->second;
      ++c.served;
      write_answer(c, std::move(d.answer.bytes), d.answer.close, now);
    }
  }

  void run_worker() {
    for (;;) {
      uint64_t id = 0;
      FrontAnswer result;
      {
        std::unique_lock lock(jobs_mutex);
        jobs_ready.wait(lock, [this] { return workers_stop || !jobs.empty(); });
        if (jobs.empty()) return;
        Job job = std::move(jobs.front());
        jobs.pop_front();
        lock.unlock();
        id = job.id;
        try {
          result = answer(job.request);
        } catch (...) {
          result = FrontAnswer{refusal(500, "The server failed to answer this request.", true), true, nullptr};
        }
      }  // the request's bytes are freed before `then`, which may return free memory to the OS
      auto then = std::move(result.then);
      {
        std::lock_guard lock(done_mutex);
        done.push_back({id, std::move(result)});
      }
      wake();
      if (then) then();
    }
  }

  // ---- deadlines and the loop ----

  void on_deadline(Connection& c, Clock::time_point now) {
    c.deadline = Clock::time_point::max();
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
                 "The request head did not arrive within " + std::to_string(config.header_timeout.count()) + " ms.",
                 true, now);
        }
        break;
      case Phase::body:
        ++counters.closed[size_t(CloseReason::body_timeout)];
        refuse(c, 408,
               "The request body did not arrive in time (" + std::to_string(config.body_timeout.count()) +
                   " ms plus 1 s per " + std::to_string(config.min_transfer_rate) + " bytes).",
               true, now);
        break;
      case Phase::writing:
        close_connection(c, CloseReason::write_timeout);
        break;
      default:
        close_connection(c);
        break;
    }
  }

  void expire(Clock::time_point now) {
    while (!timers.empty() && timers.begin()->first <= now) {
      uint64_t id = timers.begin()->second;
      timers.erase(timers.begin());
      auto it = connections.find(id);
      if (it != connections.end()) on_deadline(*it->second, now);
    }
  }

  int wait_ms(Clock::time_point now) const {
    Clock::time_point next = Clock::time_point::max();
    if (!timers.empty()) next = timers.begin()->first;
    if (!listening && !stopping && accept_resume != Clock::time_point::min()) next = std::min(next, accept_resume);
    if (finish_requested) next = std::min(next, Clock::time_point(Clock::duration(finish_deadline_ns.load())));
    if (next == Clock::time_point::max()) return -1;
    if (next <= now) return 0;
    return int(std::min<int64_t>(std::chrono::ceil<milliseconds>(next - now).count(), 60'000));
  }

  void begin_stopping(Clock::time_point now) {
    stopping = true;
    set_listening(false);
    if (listen_fd >= 0) ::close(listen_fd);
    listen_fd = -1;
    std::vector<Connection*> quiet;
    for (auto& [id, c] : connections) {
      if (c->phase == Phase::idle || (c->phase == Phase::head && c->in.empty())) quiet.push_back(c.get());
    }
    for (Connection* c : quiet) close_connection(*c);
    (void)now;
  }

  void publish() {
    std::lock_guard lock(stats_mutex);
    published = counters;
    published.reading = in_phase[size_t(Phase::head)] + in_phase[size_t(Phase::body)];
    published.processing = in_phase[size_t(Phase::processing)];
    published.writing = in_phase[size_t(Phase::writing)] + in_phase[size_t(Phase::linger)];
    published.idle = in_phase[size_t(Phase::idle)];
    std::lock_guard jobs_lock(jobs_mutex);
    published.pending = jobs.size();
  }

  void run() {
    epoll_event events[256];
    for (;;) {
      int n = epoll_wait(epoll_fd, events, 256, wait_ms(Clock::now()));
      Clock::time_point now = Clock::now();
      for (int i = 0; i < n; ++i) {
        const uint64_t key = events[i].data.u64;
        if (key == listen_key) {
          if (listening) accept_connections(now);
          continue;
        }
        if (key == wake_key) {
          collect_answers(now);
          continue;
        }
        auto it = connections.find(key);
        if (it == connections.end()) continue;
        Connection& c = *it->second;
        const uint32_t e = events[i].events;
        if (e & EPOLLERR) {
          close_connection(c);
          continue;
        }
        if (e & EPOLLOUT) {
          flush(c, now);
          if (!connections.count(key)) continue;
        }
        if (e & (EPOLLIN | EPOLLHUP)) {
          if (c.interest & EPOLLIN) {
            on_readable(c, now);
          } else if (e & EPOLLHUP) {
            close_connection(c);  // gone while its request is processed: drop the answer
          }
        }
      }
      if (stop_requested && !stopping) begin_stopping(now);
      if (!listening && !stopping && now >= accept_resume) set_listening(true);
      expire(now);
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
};

ConnectionFront::ConnectionFront(FrontConfig config, BodyLimit body_limit, Answer answer, Refusal refusal)
    : loop_(std::make_unique<Loop>(std::move(config), std::move(body_limit), std::move(answer), std::move(refusal))) {}

ConnectionFront::~ConnectionFront() {
  if (loop_->thread.joinable() || !loop_->workers.empty()) finish(Clock::now());
}

int ConnectionFront::bind() { return loop_->bind_and_listen(); }

void ConnectionFront::start() {
  loop_->open_loop();
  for (size_t i = 0; i < std::max<size_t>(1, loop_->config.workers); ++i) {
    loop_->workers.emplace_back([this] { loop_->run_worker(); });
  }
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
  loop_->wake();
  if (loop_->thread.joinable()) loop_->thread.join();
  {
    std::lock_guard lock(loop_->jobs_mutex);
    loop_->workers_stop = true;
    loop_->jobs.clear();
  }
  loop_->jobs_ready.notify_all();
  for (std::thread& worker : loop_->workers) worker.join();
  loop_->workers.clear();
}

size_t ConnectionFront::max_connections() const { return loop_->config.max_connections; }

FrontStats ConnectionFront::stats() const {
  std::lock_guard lock(loop_->stats_mutex);
  return loop_->published;
}

}  // namespace rr::server

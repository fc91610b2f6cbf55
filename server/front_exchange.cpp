// One connection's requests and answers in the connection front (see front_loop.hpp): bytes are
// read into the connection's buffer and framed into a head; a head that announces a body is
// screened before "100 Continue" is sent or a body byte is taken, and a refused one goes to a worker
// alone, its body never read; a body is read under its deadline (front_deadlines.hpp), which the
// bytes received move on, then the whole request goes to a worker. The answer is written back
// without reading meanwhile; then the connection waits for its next request, or shuts its write
// side and lingers: what the client still sends is read and dropped for a moment, so closing with
// unread bytes does not reset the connection and destroy the answer before the client has read it.
#include "server/front_loop.hpp"

#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

namespace rr::server {
namespace {

using Clock = FrontClock;

constexpr std::chrono::milliseconds linger_time{1000};
constexpr size_t linger_max_bytes = 1u << 20;
constexpr std::string_view continue_line = "HTTP/1.1 100 Continue\r\n\r\n";

void reset_scan(front::Connection& c) {
  c.in_scanned = 0;
  c.line_start = 0;
}

}  // namespace

using Loop = ConnectionFront::Loop;

void Loop::on_readable(Connection& c, Clock::time_point now) {
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

// Frames as much of `in` as has arrived: a head, then its body, then hands the request on.
void Loop::advance(Connection& c, Clock::time_point now) {
  if (c.phase == Phase::idle || c.phase == Phase::head) {
    size_t blank = leading_empty_lines(c.in);
    if (blank) {
      c.in.erase(0, blank);
      reset_scan(c);
    }
    if (c.in.empty()) return;
    if (c.phase == Phase::idle) {
      set_phase(c, Phase::head, now);
      set_deadline(c, now + config.deadlines.header_timeout);
    }
    c.head_started = true;
    if (!read_head(c, now)) return;
  }
  if (c.phase == Phase::body) {
    const size_t need = c.head.head_bytes + c.head.content_length;
    if (c.in.size() < need) {
      // The bytes received so far earn the body more time, up to its total.
      set_deadline(c, body_deadline(config.deadlines, c.since, c.head.content_length, c.in.size() - c.head.head_bytes));
      return;
    }
    FrontRequest request;
    request.bytes = c.in.substr(0, need);
    request.head = std::move(c.head);
    c.in.erase(0, need);
    // A large body's buffer is not kept for the connection's next request.
    if (c.in.capacity() > 2 * read_chunk) c.in.shrink_to_fit();
    reset_scan(c);
    release_budget(c);
    dispatch(c, std::move(request), now);
  }
}

// Parses the head once a line has ended (or a cap may be crossed); true once a body phase begins.
bool Loop::read_head(Connection& c, Clock::time_point now) {
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
  if (c.head.has_transfer_encoding || (length > 0 && !body_wanted(c.head))) {
    // The answer follows from the head alone; the body stays unread and the connection closes.
    FrontRequest request;
    request.bytes = c.in.substr(0, c.head.head_bytes);
    request.head = std::move(c.head);
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
    erase_expect_line(c.in, c.head);
    reset_scan(c);
    const uint64_t id = c.id;
    if (c.in.size() < c.head.head_bytes + length) send_bytes(c, std::string(continue_line));
    if (!connections.count(id)) return false;  // the write failed and closed it
  }
  set_phase(c, Phase::body, now);
  set_deadline(c, body_deadline(config.deadlines, now, length, c.in.size() - c.head.head_bytes));
  return true;
}

// Screening's verdict from the head alone; a verdict that throws reads nothing.
bool Loop::body_wanted(const RequestHead& head) {
  try {
    return screen(head);
  } catch (...) {
    return false;
  }
}

void Loop::dispatch(Connection& c, FrontRequest request, Clock::time_point now) {
  request.last = request.last || request.head_only || !request.head.keep_alive || stopping ||
                 c.served + 1 >= config.max_requests_per_connection;
  request.remote_ip = c.peer.remote_ip;
  request.remote_port = c.peer.remote_port;
  request.local_ip = c.peer.local_ip;
  request.local_port = c.peer.local_port;
  const bool head_only = request.head_only;
  if (workers.submit(c.id, request)) {
    set_phase(c, Phase::processing, now);
    set_deadline(c, Clock::time_point::max());
    set_interest(c, c.out.empty() ? 0u : uint32_t(EPOLLOUT));
    return;
  }
  ++counters.shed;
  refuse(c, 503, "Every request worker is busy and the queue is full; retry shortly.", head_only, now);
}

void Loop::collect_answers(Clock::time_point now) {
  uint64_t count = 0;
  [[maybe_unused]] ssize_t n = ::read(wake_fd, &count, sizeof count);
  for (WorkerPool::Done& d : workers.take_done()) {
    auto it = connections.find(d.id);
    if (it == connections.end()) continue;  // the client went away meanwhile
    Connection& c = *it->second;
    ++c.served;
    write_answer(c, std::move(d.answer.bytes), d.answer.close, now);
  }
}

// Queues a whole answer the front made itself and writes what the socket takes now.
void Loop::refuse(Connection& c, int status, std::string_view detail, bool close, Clock::time_point now) {
  if (close) release_budget(c);
  write_answer(c, refusal(status, detail, close), close, now);
}

void Loop::write_answer(Connection& c, std::string bytes, bool close, Clock::time_point now) {
  c.close_after_write = c.close_after_write || close;
  set_phase(c, Phase::writing, now);
  // No reading while an answer is written: a client that sends without reading would otherwise
  // grow `in` for as long as it likes.
  set_interest(c, 0);
  set_deadline(c, write_deadline(config.deadlines, now, bytes.size() + c.out.size()));
  send_bytes(c, std::move(bytes));
}

void Loop::send_bytes(Connection& c, std::string bytes) {
  if (c.out.empty()) {
    c.out = std::move(bytes);
    c.out_sent = 0;
  } else {
    c.out += bytes;
  }
  flush(c, Clock::now());
}

// Writes what the socket takes; once `out` is empty, an answer is complete.
void Loop::flush(Connection& c, Clock::time_point now) {
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

void Loop::answered(Connection& c, Clock::time_point now) {
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
    set_deadline(c, now + config.deadlines.keep_alive_timeout);
    set_interest(c, EPOLLIN);
    if (in_phase[size_t(Phase::idle)] > config.max_idle_connections) {
      if (Connection* oldest = oldest_in(Phase::idle)) close_connection(*oldest, CloseReason::idle_evicted);
    }
    return;
  }
  // A pipelined request is already here.
  set_phase(c, Phase::head, now);
  set_deadline(c, now + config.deadlines.header_timeout);
  set_interest(c, EPOLLIN);
  advance(c, now);
}

}  // namespace rr::server

// The connection front's listening socket: binding, the descriptor limit the connection cap must fit
// in, accepting, and pausing while the process is out of descriptors. What to do with an accepted
// connection (the cap, eviction, the 503) is the event loop's (connection_front.cpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace rr::server {

// A socket's addresses as text ("127.0.0.1", port).
struct PeerAddresses {
  std::string remote_ip, local_ip;
  int remote_port = 0, local_port = 0;
};

// There must be a descriptor for every connection the front may hold; the soft limit is often 1024.
// Raises it as far as the hard limit allows and returns how many connections fit (at most `connections`).
size_t raise_descriptor_limit(size_t connections);

class Listener {
 public:
  Listener() = default;
  ~Listener();
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;

  // Binds and listens; returns the port. Throws std::runtime_error when it cannot.
  int bind(const std::string& address, int port, int backlog);
  // Adds the socket to (or takes it out of) the epoll set under `key`; a closed listener is never added.
  void watch(int epoll_fd, uint64_t key, bool on);
  bool watched() const { return watched_; }
  enum class Accept { accepted, none_pending, out_of_descriptors };
  // Accepts one pending connection (non-blocking, TCP_NODELAY) into `fd` and `peer`.
  Accept accept_one(int& fd, PeerAddresses& peer);
  void close();

 private:
  int fd_ = -1;
  int epoll_fd_ = -1;
  bool watched_ = false;
};

}  // namespace rr::server

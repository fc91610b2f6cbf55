// The listening socket (see front_listener.hpp).
#include "server/front_listener.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <stdexcept>

namespace rr::server {
namespace {

// Descriptors kept free of client connections: the listening socket, epoll, eventfd, and the files
// workers open (stored scenes, schemas, the web page).
constexpr size_t reserved_descriptors = 128;

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

}  // namespace

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

Listener::~Listener() { close(); }

int Listener::bind(const std::string& address, int port, int backlog) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  if (getaddrinfo(address.c_str(), service.c_str(), &hints, &found) != 0 || !found) {
    throw std::runtime_error("cannot resolve the bind address " + address);
  }
  for (addrinfo* a = found; a && fd_ < 0; a = a->ai_next) {
    int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    // SO_REUSEADDR allows a quick restart; SO_REUSEPORT is left off, so a second server cannot
    // bind the same port and take half the connections.
    int yes = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0 && ::listen(fd, backlog) == 0) {
      fd_ = fd;
    } else {
      ::close(fd);
    }
  }
  freeaddrinfo(found);
  if (fd_ < 0) throw std::runtime_error("cannot listen on " + address + ":" + service);
  sockaddr_storage local{};
  socklen_t length = sizeof local;
  getsockname(fd_, reinterpret_cast<sockaddr*>(&local), &length);
  std::string ip;
  int bound = 0;
  address_text(local, ip, bound);
  return bound;
}

void Listener::watch(int epoll_fd, uint64_t key, bool on) {
  if (on == watched_ || fd_ < 0) return;
  epoll_event event{};
  event.events = EPOLLIN;
  event.data.u64 = key;
  epoll_ctl(epoll_fd, on ? EPOLL_CTL_ADD : EPOLL_CTL_DEL, fd_, &event);
  epoll_fd_ = epoll_fd;
  watched_ = on;
}

Listener::Accept Listener::accept_one(int& fd, PeerAddresses& peer) {
  for (;;) {
    sockaddr_storage remote{};
    socklen_t length = sizeof remote;
    fd = accept4(fd_, reinterpret_cast<sockaddr*>(&remote), &length, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd >= 0) {
      int yes = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
      address_text(remote, peer.remote_ip, peer.remote_port);
      sockaddr_storage local{};
      length = sizeof local;
      if (getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length) == 0) {
        address_text(local, peer.local_ip, peer.local_port);
      }
      return Accept::accepted;
    }
    if (errno == EINTR || errno == ECONNABORTED) continue;
    if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) return Accept::out_of_descriptors;
    return Accept::none_pending;
  }
}

void Listener::close() {
  if (fd_ < 0) return;
  if (watched_) epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd_, nullptr);
  watched_ = false;
  ::close(fd_);
  fd_ = -1;
}

}  // namespace rr::server

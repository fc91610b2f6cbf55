// The seam between the connection front and cpp-httplib 0.11. The front parses each request head
// (request_head.hpp) and decides from that parse: framing, the body limit, Expect, keep-alive and,
// through screening, whether the body is read at all. httplib then parses the same bytes again, on
// an in-memory stream, for its router and the handlers. Its server takes bytes only through
// Server::process_request (protected, so reached through RequestProcessor), and it writes the
// answers (status line, Keep-Alive, HEAD, compression), so that second parse stays; these functions
// hold the two together. request_from_head builds the httplib::Request that httplib's parse gives
// from the front's parse, with httplib's own helpers; parse_difference compares the two, in the
// differential test and fuzz target (tests/unit/test_http_seam.cpp, fuzz/fuzz_http_seam.cpp) and on
// every request the service answers.
#pragma once

#include "server/request_head.hpp"

#include <httplib.h>

#include <functional>
#include <string>
#include <string_view>
#include <type_traits>

namespace rr::server {

// httplib's request processing, reachable: it parses one request from the stream, runs the pre-routing
// handler, the route's handler and the logger, and writes the answer to the stream. `setup` sees
// httplib's parse first (before Expect, routing and the body).
class RequestProcessor : public httplib::Server {
 public:
  using Setup = std::function<void(httplib::Request&)>;
  bool process(httplib::Stream& stream, bool close_connection, bool& connection_closed, const Setup& setup) {
    return process_request(stream, close_connection, connection_closed, setup);
  }

 private:
  // Newer cpp-httplib releases changed this protected member; a changed one must stop the build
  // here, not fail at run time.
  static_assert(std::is_same_v<decltype(&RequestProcessor::process_request),
                               bool (httplib::Server::*)(httplib::Stream&, bool, bool&, const Setup&)>,
                "cpp-httplib's Server::process_request is not the 0.11 one the connection front's bridge "
                "calls (server/httplib_bridge.hpp): port the bridge and rerun the seam's differential test");
};

// One complete request as httplib's input, its answer collected as bytes. Reading past the request
// gives 0 (end of stream), so a handler never waits for a client.
class MemoryStream final : public httplib::Stream {
 public:
  struct Peer {
    std::string remote_ip, local_ip;
    int remote_port = 0, local_port = 0;
  };
  MemoryStream(std::string_view request, std::string& answer, const Peer& peer)
      : request_(request), answer_(answer), peer_(peer) {}
  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return INVALID_SOCKET; }

 private:
  std::string_view request_;
  std::string& answer_;
  const Peer& peer_;
  size_t offset_ = 0;
};

// The httplib::Request that httplib 0.11 parses from a head the front parsed: method, target,
// version, path (percent-decoded), query parameters and headers (values percent-decoded, fields
// with an empty value dropped, as httplib does). No body and no socket addresses.
httplib::Request request_from_head(const RequestHead& head);

// "" when httplib's parse `parsed` of a request agrees with the front's `head`, else the first
// difference in words. Compares method, target, version, path, parameters and headers (less the
// REMOTE_ADDR, REMOTE_PORT, LOCAL_ADDR and LOCAL_PORT that httplib appends to every request).
std::string parse_difference(const RequestHead& head, const httplib::Request& parsed);

// True when an answer's head says "Connection: close".
bool answer_closes(std::string_view answer);

}  // namespace rr::server

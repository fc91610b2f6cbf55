// The connection front's parse of one HTTP/1.1 request head, as bytes arrive: where the head ends,
// its request line and header fields, how long the body is, whether the connection stays open, and
// whether the head breaks a cap. It is the parse the seam's decisions come from (framing, body
// limit, Expect, keep-alive, screening); cpp-httplib parses the same bytes again for the handlers,
// and server/httplib_bridge.hpp holds the two to each other. So the language accepted here is a
// subset of what httplib 0.11 reads the same way: CR LF line ends, its methods, a target without
// white space or control bytes and at most one '?', and no percent sign in the framing fields
// (httplib percent-decodes every header value). Pure functions on byte strings, no sockets.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rr::server {

// httplib 0.11 answers 414 to a request line, and 400 to a header line, longer than 8192 bytes with
// its CR LF (CPPHTTPLIB_REQUEST_URI_MAX_LENGTH, CPPHTTPLIB_HEADER_MAX_LENGTH, compiled into Debian's
// library): the longest line both parsers read is this many bytes before the CR LF.
constexpr size_t httplib_max_line_bytes = 8190;

struct HeadLimits {
  size_t max_request_line_bytes = httplib_max_line_bytes;  // also the cap on one header line
  size_t max_header_bytes = 65536;                         // request line + header lines + the empty line
  size_t max_header_count = 100;
};

struct HeaderField {
  std::string name;   // as sent
  std::string value;  // as sent, without the white space around it (may be empty)
};

struct RequestHead {
  size_t head_bytes = 0;  // up to and including the empty line that ends the head
  std::string method;
  std::string target;   // as sent: path and query
  std::string version;  // "HTTP/1.1" or "HTTP/1.0"
  std::vector<HeaderField> fields;
  uint64_t content_length = 0;
  bool has_content_length = false;
  bool has_transfer_encoding = false;
  bool expects_continue = false;  // "Expect: 100-continue"
  // Byte range [begin, end) of the Expect line inside the head, so it can be cut once answered.
  size_t expect_begin = 0, expect_end = 0;
  // The connection may carry another request after this one's answer: HTTP/1.1 without a "close"
  // option in Connection, or HTTP/1.0 whose first Connection field is "Keep-Alive" as 1.0 clients
  // send it (httplib matches that value exactly, so the front does too).
  bool keep_alive = true;
};

enum class HeadStatus {
  incomplete,  // more bytes needed, no cap broken yet
  complete,
  bad,                    // 400: unparsable request line, header line or framing field
  request_line_too_long,  // 414
  header_too_large,       // 431: a header line, the header count or the head size
  unknown_method,         // 501: a method neither this server nor httplib implements
};

struct HeadScan {
  HeadStatus status = HeadStatus::incomplete;
  RequestHead head;    // filled when complete
  std::string detail;  // for errors: what broke, in words for the client
};

// Empty lines before a request line are allowed (RFC 9112 section 2.2); this is how many bytes of
// them `bytes` starts with (CR LF or a bare LF each: they are dropped before anything parses).
size_t leading_empty_lines(std::string_view bytes);

// Scans `bytes`, which starts at a request line. Every line ends in CR LF.
HeadScan scan_head(std::string_view bytes, const HeadLimits& limits);

// The 3-digit status of a HeadStatus that refuses the request (400, 414, 431, 501); 0 otherwise.
int head_status_code(HeadStatus status);

// The methods httplib 0.11 routes (it answers 400 to CONNECT, TRACE and PRI, and to any other).
bool is_known_method(std::string_view method);

// Cuts the Expect line out of `request` (which starts with `head`'s bytes) and out of `head`, once
// the front has answered "100 Continue" itself, so httplib does not answer it a second time.
void erase_expect_line(std::string& request, RequestHead& head);

}  // namespace rr::server

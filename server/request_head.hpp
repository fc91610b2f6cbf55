// Framing of one HTTP/1.1 request head as bytes arrive: where the head ends, how long the body is,
// and whether the head breaks a cap (request line, header line, header count, head size). Only the
// fields the connection front needs to frame and screen a request are read here; cpp-httplib parses
// the complete request again. Pure functions on byte strings, no sockets.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace rr::server {

struct HeadLimits {
  size_t max_request_line_bytes = 8192;  // also the cap on one header line
  size_t max_header_bytes = 65536;       // request line + header lines + the empty line
  size_t max_header_count = 100;
};

struct RequestHead {
  size_t head_bytes = 0;  // up to and including the empty line that ends the head
  std::string method;
  std::string target;  // as sent: path and query
  uint64_t content_length = 0;
  bool has_content_length = false;
  bool has_transfer_encoding = false;
  bool expects_continue = false;  // "Expect: 100-continue"
  // Byte range [begin, end) of the Expect line inside the head, so it can be cut once answered.
  size_t expect_begin = 0, expect_end = 0;
};

enum class HeadStatus {
  incomplete,  // more bytes needed, no cap broken yet
  complete,
  bad,                    // 400: unparsable request line, header line or Content-Length
  request_line_too_long,  // 414
  header_too_large,       // 431: a header line, the header count or the head size
};

struct HeadScan {
  HeadStatus status = HeadStatus::incomplete;
  RequestHead head;    // filled when complete
  std::string detail;  // for errors: what broke, in words for the client
};

// Empty lines before a request line are allowed (RFC 9112 section 2.2); this is how many bytes of
// them `bytes` starts with.
size_t leading_empty_lines(std::string_view bytes);

// Scans `bytes`, which starts at a request line. Lines end in LF, optionally preceded by CR.
HeadScan scan_head(std::string_view bytes, const HeadLimits& limits);

// The 3-digit status of a HeadStatus that refuses the request (400, 414, 431); 0 otherwise.
int head_status_code(HeadStatus status);

}  // namespace rr::server

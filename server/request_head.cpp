// Request head framing (see request_head.hpp). The caps are checked on bytes, before a line is
// complete, so a request line or header line that never ends is refused once it passes its cap,
// not when the client stops sending.
#include "server/request_head.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace rr::server {
namespace {

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

// RFC 9110 section 5.6.2: the characters of a header name or a method.
bool is_token(std::string_view text) {
  if (text.empty()) return false;
  return std::all_of(text.begin(), text.end(), [](char c) {
    unsigned char u = static_cast<unsigned char>(c);
    return std::isalnum(u) || std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
  });
}

std::string_view trim_whitespace(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

std::string_view without_cr(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

HeadScan refuse(HeadStatus status, std::string detail) {
  HeadScan scan;
  scan.status = status;
  scan.detail = std::move(detail);
  return scan;
}

// "METHOD SP target SP HTTP/1.x"
bool parse_request_line(std::string_view line, RequestHead& head) {
  size_t first = line.find(' ');
  size_t last = line.rfind(' ');
  if (first == std::string_view::npos || first == last) return false;
  std::string_view method = line.substr(0, first);
  std::string_view target = line.substr(first + 1, last - first - 1);
  std::string_view version = line.substr(last + 1);
  if (!is_token(method) || target.empty() || target.find(' ') != std::string_view::npos) return false;
  if (version != "HTTP/1.1" && version != "HTTP/1.0") return false;
  head.method = std::string(method);
  head.target = std::string(target);
  return true;
}

// One header field; false when the line is not a field or its framing value is unusable.
bool read_field(std::string_view line, size_t line_begin, size_t line_end, RequestHead& head, std::string& detail) {
  size_t colon = line.find(':');
  std::string_view name = colon == std::string_view::npos ? std::string_view() : line.substr(0, colon);
  if (!is_token(name)) {
    detail = "A header line is not of the form 'Name: value'.";
    return false;
  }
  std::string_view value = trim_whitespace(line.substr(colon + 1));
  if (equals_ignoring_case(name, "Content-Length")) {
    uint64_t length = 0;
    auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), length);
    if (value.empty() || ec != std::errc() || end != value.data() + value.size()) {
      detail = "The Content-Length header is not a number.";
      return false;
    }
    if (head.has_content_length && head.content_length != length) {
      detail = "The request has more than one Content-Length header.";
      return false;
    }
    head.has_content_length = true;
    head.content_length = length;
  } else if (equals_ignoring_case(name, "Transfer-Encoding")) {
    head.has_transfer_encoding = true;
  } else if (equals_ignoring_case(name, "Expect") && equals_ignoring_case(value, "100-continue")) {
    head.expects_continue = true;
    head.expect_begin = line_begin;
    head.expect_end = line_end;
  }
  return true;
}

}  // namespace

size_t leading_empty_lines(std::string_view bytes) {
  size_t n = 0;
  while (n < bytes.size() && (bytes[n] == '\n' || (bytes[n] == '\r' && n + 1 < bytes.size() && bytes[n + 1] == '\n'))) {
    n += bytes[n] == '\r' ? 2 : 1;
  }
  return n;
}

HeadScan scan_head(std::string_view bytes, const HeadLimits& limits) {
  const size_t max_line = limits.max_request_line_bytes;
  size_t newline = bytes.find('\n');
  // A line's length counts its bytes before CR LF.
  if ((newline == std::string_view::npos && bytes.size() > max_line + 1) ||
      (newline != std::string_view::npos && without_cr(bytes.substr(0, newline)).size() > max_line)) {
    return refuse(HeadStatus::request_line_too_long,
                  "The request line is longer than " + std::to_string(max_line) + " bytes.");
  }
  if (newline == std::string_view::npos) return {};
  HeadScan scan;
  if (!parse_request_line(without_cr(bytes.substr(0, newline)), scan.head)) {
    return refuse(HeadStatus::bad, "The request line is not 'METHOD target HTTP/1.1'.");
  }
  size_t count = 0;
  for (size_t begin = newline + 1;;) {
    newline = bytes.find('\n', begin);
    size_t end = newline == std::string_view::npos ? bytes.size() : newline + 1;
    if (end > limits.max_header_bytes) {
      return refuse(HeadStatus::header_too_large,
                    "The request head is larger than " + std::to_string(limits.max_header_bytes) + " bytes.");
    }
    std::string_view line = bytes.substr(begin, end - begin);
    if (newline != std::string_view::npos) line = without_cr(line.substr(0, line.size() - 1));
    if (line.size() > max_line + (newline == std::string_view::npos ? 1 : 0)) {
      return refuse(HeadStatus::header_too_large,
                    "A header line is longer than " + std::to_string(max_line) + " bytes.");
    }
    if (newline == std::string_view::npos) return {};
    if (line.empty()) {
      scan.status = HeadStatus::complete;
      scan.head.head_bytes = end;
      return scan;
    }
    if (line.front() == ' ' || line.front() == '\t') {
      return refuse(HeadStatus::bad, "Folded header lines (starting with white space) are not accepted.");
    }
    if (++count > limits.max_header_count) {
      return refuse(HeadStatus::header_too_large,
                    "The request has more than " + std::to_string(limits.max_header_count) + " header fields.");
    }
    std::string detail;
    if (!read_field(line, begin, end, scan.head, detail)) return refuse(HeadStatus::bad, std::move(detail));
    begin = end;
  }
}

int head_status_code(HeadStatus status) {
  switch (status) {
    case HeadStatus::bad:
      return 400;
    case HeadStatus::request_line_too_long:
      return 414;
    case HeadStatus::header_too_large:
      return 431;
    default:
      return 0;
  }
}

}  // namespace rr::server

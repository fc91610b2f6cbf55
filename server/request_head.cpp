// Request head parsing (see request_head.hpp). The caps are checked on bytes, before a line is
// complete, so a request line or header line that never ends is refused once it passes its cap,
// not when the client stops sending. Where httplib 0.11 would read a head differently (a bare LF,
// a header line it skips, a value it percent-decodes into a framing word), the head is refused here
// instead, so the bytes httplib gets always mean to it what they meant to the front.
#include "server/request_head.hpp"

#include <algorithm>
#include <array>
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

bool is_control(char c) {
  unsigned char u = static_cast<unsigned char>(c);
  return u < 0x20 || u == 0x7f;
}

std::string_view trim_whitespace(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

HeadScan refuse(HeadStatus status, std::string detail) {
  HeadScan scan;
  scan.status = status;
  scan.detail = std::move(detail);
  return scan;
}

// "METHOD SP target SP HTTP/1.x" with single spaces; the target in origin form ("/path?query") with
// no white space or control byte (httplib would trim or cut at them), no '#' (a fragment is never
// sent; httplib cuts the target there) and at most one '?' (httplib refuses some targets with more
// and reads others differently).
HeadStatus parse_request_line(std::string_view line, RequestHead& head, std::string& detail) {
  size_t first = line.find(' ');
  size_t last = line.rfind(' ');
  detail = "The request line is not 'METHOD /target HTTP/1.1'.";
  if (first == std::string_view::npos || first == last) return HeadStatus::bad;
  std::string_view method = line.substr(0, first);
  std::string_view target = line.substr(first + 1, last - first - 1);
  std::string_view version = line.substr(last + 1);
  if (!is_token(method) || target.empty() || target.front() != '/') return HeadStatus::bad;
  if (std::any_of(target.begin(), target.end(), [](char c) { return c == ' ' || c == '#' || is_control(c); })) {
    return HeadStatus::bad;
  }
  if (std::count(target.begin(), target.end(), '?') > 1) {
    detail = "The request target has more than one '?'; percent-encode the others as %3F.";
    return HeadStatus::bad;
  }
  if (version != "HTTP/1.1" && version != "HTTP/1.0") return HeadStatus::bad;
  if (!is_known_method(method)) {
    detail = "The method " + std::string(method) + " is not implemented here.";
    return HeadStatus::unknown_method;
  }
  head.method = std::string(method);
  head.target = std::string(target);
  head.version = std::string(version);
  return HeadStatus::complete;
}

// True when the comma-separated list `value` holds `option` (case-insensitive, RFC 9110 section 7.6.1).
bool has_option(std::string_view value, std::string_view option) {
  for (size_t begin = 0; begin <= value.size();) {
    size_t end = std::min(value.find(',', begin), value.size());
    if (equals_ignoring_case(trim_whitespace(value.substr(begin, end - begin)), option)) return true;
    begin = end + 1;
  }
  return false;
}

// One header field; false (with `detail`) when the line is not a field or a framing value is unusable.
bool read_field(std::string_view line, size_t line_begin, size_t line_end, RequestHead& head, std::string& detail) {
  size_t colon = line.find(':');
  std::string_view name = colon == std::string_view::npos ? std::string_view() : line.substr(0, colon);
  if (!is_token(name)) {
    detail = "A header line is not of the form 'Name: value'.";
    return false;
  }
  std::string_view value = trim_whitespace(line.substr(colon + 1));
  if (std::any_of(value.begin(), value.end(), [](char c) { return c != '\t' && is_control(c); })) {
    detail = "The value of " + std::string(name) + " holds a control character.";
    return false;
  }
  const bool connection = equals_ignoring_case(name, "Connection");
  const bool expect = equals_ignoring_case(name, "Expect");
  if ((connection || expect) && value.find('%') != std::string_view::npos) {
    detail = "The value of " + std::string(name) + " is percent-encoded.";
    return false;
  }
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
  } else if (expect) {
    if (head.expect_end != 0) {
      detail = "The request has more than one Expect header.";
      return false;
    }
    head.expects_continue = equals_ignoring_case(value, "100-continue");
    head.expect_begin = line_begin;
    head.expect_end = line_end;
  } else if (connection && has_option(value, "close")) {
    head.keep_alive = false;
  }
  head.fields.push_back({std::string(name), std::string(value)});
  return true;
}

// An HTTP/1.0 connection persists only when its first Connection field is "Keep-Alive", the value
// 1.0 clients send; httplib 0.11 compares it exactly.
bool http10_keep_alive(const RequestHead& head) {
  for (const HeaderField& f : head.fields) {
    if (equals_ignoring_case(f.name, "Connection")) return f.value == "Keep-Alive";
  }
  return false;
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
  HeadScan scan;
  size_t count = 0;
  for (size_t begin = 0;;) {
    const size_t newline = bytes.find('\n', begin);
    const size_t end = newline == std::string_view::npos ? bytes.size() : newline + 1;
    // A line's length counts its bytes before CR LF; an unfinished one may end in the CR of its CR LF.
    std::string_view line = bytes.substr(begin, end - begin);
    const bool finished = newline != std::string_view::npos;
    if (finished) line.remove_suffix(1);
    const size_t length = !line.empty() && line.back() == '\r' ? line.size() - 1 : line.size();
    if (length > max_line) {
      if (begin == 0) {
        return refuse(HeadStatus::request_line_too_long,
                      "The request line is longer than " + std::to_string(max_line) + " bytes.");
      }
      return refuse(HeadStatus::header_too_large,
                    "A header line is longer than " + std::to_string(max_line) + " bytes.");
    }
    if (begin > 0 && end > limits.max_header_bytes) {
      return refuse(HeadStatus::header_too_large,
                    "The request head is larger than " + std::to_string(limits.max_header_bytes) + " bytes.");
    }
    if (!finished) return scan;  // incomplete
    if (line.empty() || line.back() != '\r') return refuse(HeadStatus::bad, "Lines must end in CR LF.");
    line.remove_suffix(1);
    if (begin == 0) {
      std::string detail;
      HeadStatus status = parse_request_line(line, scan.head, detail);
      if (status != HeadStatus::complete) return refuse(status, std::move(detail));
    } else if (line.empty()) {
      scan.status = HeadStatus::complete;
      scan.head.head_bytes = end;
      if (scan.head.version == "HTTP/1.0") scan.head.keep_alive = scan.head.keep_alive && http10_keep_alive(scan.head);
      return scan;
    } else if (line.front() == ' ' || line.front() == '\t') {
      return refuse(HeadStatus::bad, "Folded header lines (starting with white space) are not accepted.");
    } else if (++count > limits.max_header_count) {
      return refuse(HeadStatus::header_too_large,
                    "The request has more than " + std::to_string(limits.max_header_count) + " header fields.");
    } else {
      std::string detail;
      if (!read_field(line, begin, end, scan.head, detail)) return refuse(HeadStatus::bad, std::move(detail));
    }
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
    case HeadStatus::unknown_method:
      return 501;
    default:
      return 0;
  }
}

bool is_known_method(std::string_view method) {
  static constexpr std::array<std::string_view, 7> methods = {"GET",   "HEAD",   "POST",   "PUT",
                                                              "PATCH", "DELETE", "OPTIONS"};
  return std::find(methods.begin(), methods.end(), method) != methods.end();
}

void erase_expect_line(std::string& request, RequestHead& head) {
  if (head.expect_end == 0) return;
  request.erase(head.expect_begin, head.expect_end - head.expect_begin);
  head.head_bytes -= head.expect_end - head.expect_begin;
  std::erase_if(head.fields, [](const HeaderField& f) { return equals_ignoring_case(f.name, "Expect"); });
  head.expects_continue = false;
  head.expect_begin = head.expect_end = 0;
}

}  // namespace rr::server

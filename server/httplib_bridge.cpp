// The front/httplib seam (see httplib_bridge.hpp). request_from_head follows httplib 0.11's
// Server::parse_request_line and detail::read_headers step by step, with the helpers the library
// exports (detail::split, decode_url, parse_query_text), so the front's screening sees exactly the
// request the handlers will see.
#include "server/httplib_bridge.hpp"

#include <algorithm>
#include <cstring>

namespace rr::server {

ssize_t MemoryStream::read(char* ptr, size_t size) {
  size_t n = std::min(size, request_.size() - offset_);
  std::memcpy(ptr, request_.data() + offset_, n);
  offset_ += n;
  return ssize_t(n);
}

ssize_t MemoryStream::write(const char* ptr, size_t size) {
  answer_.append(ptr, size);
  return ssize_t(size);
}

void MemoryStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  ip = peer_.remote_ip;
  port = peer_.remote_port;
}

void MemoryStream::get_local_ip_and_port(std::string& ip, int& port) const {
  ip = peer_.local_ip;
  port = peer_.local_port;
}

httplib::Request request_from_head(const RequestHead& head) {
  httplib::Request req;
  req.method = head.method;
  req.target = head.target;
  req.version = head.version;
  // httplib splits the target at '?' into non-empty pieces; the front allows at most one '?'.
  size_t piece = 0;
  httplib::detail::split(req.target.data(), req.target.data() + req.target.size(), '?',
                         [&](const char* b, const char* e) {
                           if (piece == 0) req.path = httplib::detail::decode_url(std::string(b, e), false);
                           if (piece == 1 && e > b) httplib::detail::parse_query_text(std::string(b, e), req.params);
                           ++piece;
                         });
  for (const HeaderField& field : head.fields) {
    if (field.value.empty()) continue;  // httplib keeps no field without a value
    req.headers.emplace(field.name, httplib::detail::decode_url(field.value, false));
  }
  return req;
}

namespace {

std::string in_quotes(std::string_view text) {
  std::string out = "'";
  out.append(text.substr(0, 80));
  out += '\'';
  return out;
}

std::string headers_text(const httplib::Headers& headers) {
  std::string text;
  for (const auto& [name, value] : headers) text += (text.empty() ? "" : ", ") + name + ": " + value;
  return in_quotes(text);
}

}  // namespace

std::string parse_difference(const RequestHead& head, const httplib::Request& parsed) {
  const httplib::Request front = request_from_head(head);
  auto differs = [](const char* what, const std::string& a, const std::string& b) {
    return std::string(what) + ": the front read " + in_quotes(a) + ", httplib " + in_quotes(b);
  };
  if (front.method != parsed.method) return differs("method", front.method, parsed.method);
  if (front.target != parsed.target) return differs("target", front.target, parsed.target);
  if (front.version != parsed.version) return differs("version", front.version, parsed.version);
  if (front.path != parsed.path) return differs("path", front.path, parsed.path);
  if (front.params != parsed.params) return "query parameters differ";
  httplib::Headers headers = parsed.headers;
  for (const char* added : {"REMOTE_ADDR", "REMOTE_PORT", "LOCAL_ADDR", "LOCAL_PORT"}) {
    auto [first, last] = headers.equal_range(added);
    if (first != last) headers.erase(std::prev(last));  // httplib's own, after any the client sent
  }
  if (front.headers != headers)
    return "headers: the front read " + headers_text(front.headers) + ", httplib " + headers_text(headers);
  return "";
}

bool answer_closes(std::string_view answer) {
  std::string_view head = answer.substr(0, answer.find("\r\n\r\n"));
  return head.find("\r\nConnection: close\r\n") != std::string_view::npos || head.ends_with("\r\nConnection: close");
}

}  // namespace rr::server

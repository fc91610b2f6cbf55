// The seam's differential check (see http_seam_harness.hpp). httplib runs with handlers on every
// method that answer 200 and note the body they got, and with the front's keep-alive decision passed
// in as the seam passes it. Bodies are compared for the methods httplib reads one for (POST, PUT,
// PATCH, DELETE); the seam reads no other: every route that takes a body is a POST or a PUT
// (tests/unit/test_http_seam.cpp checks the route table), and screening refuses a body elsewhere
// from the head. Where screening would refuse the head for what it says about the body (an encoding,
// form data) httplib's own answer is not compared either.
#include "fuzz/http_seam_harness.hpp"

#include "server/httplib_bridge.hpp"
#include "server/request_head.hpp"

#include <algorithm>
#include <optional>

namespace rr::fuzz {

using server::RequestHead;

namespace {

// Bodies httplib does not hand over as bytes: it inflates a Content-Encoding and parses form data,
// and refuses what it cannot. Screening refuses every one of them from the head (415: no route takes
// them, tests/unit/test_http_seam.cpp), so the seam never hands httplib such a body.
bool body_decoded_by_httplib(const RequestHead& head) {
  const httplib::Request req = server::request_from_head(head);
  const std::string type = req.get_header_value("Content-Type");
  return req.has_header("Content-Encoding") || type.starts_with("multipart/form-data") ||
         type == "application/x-www-form-urlencoded";
}

// Where the handlers note the body they got, for the call in progress on this thread.
thread_local std::optional<size_t>* body_seen = nullptr;

// httplib with handlers on every method and path (also one that decodes to a line break, which ".*"
// does not match) that answer 200; made once, as compiling its patterns costs more than a check.
server::RequestProcessor& processor() {
  static server::RequestProcessor* httplib = [] {
    auto* p = new server::RequestProcessor;
    auto answer = [](const httplib::Request& req, httplib::Response& res) {
      if (body_seen) *body_seen = req.body.size();
      res.set_content("ok", "text/plain");
    };
    const std::string any = "[\\s\\S]*";
    p->Get(any, answer).Post(any, answer).Put(any, answer).Patch(any, answer).Delete(any, answer);
    p->Options(any, answer);
    // Only a head that goes on alone keeps its Expect line, and screening refuses those (411).
    p->set_expect_100_continue_handler([](const httplib::Request&, httplib::Response& res) {
      res.status = 411;
      return 411;
    });
    return p;
  }();
  return *httplib;
}

}  // namespace

std::string seam_disagreement(std::string_view bytes) {
  server::HeadScan scan = server::scan_head(bytes, server::HeadLimits{});
  if (scan.status != server::HeadStatus::complete) return "";
  RequestHead head = scan.head;
  std::string request(bytes.substr(0, head.head_bytes));
  const uint64_t available = bytes.size() - head.head_bytes;
  // A chunked head goes on alone, its body unread, and its connection closes after the answer.
  const bool body_read = !head.has_transfer_encoding;
  const bool close_connection = !body_read || !head.keep_alive;
  bool body_whole = true;
  if (body_read) {
    if (head.expects_continue) server::erase_expect_line(request, head);
    body_whole = available >= head.content_length;
    request.append(bytes.substr(scan.head.head_bytes, std::min<uint64_t>(available, head.content_length)));
  }

  std::optional<std::string> parse;  // httplib's parse against the front's, once httplib has one
  std::optional<size_t> body_size;   // the body httplib handed the handler, once it did
  body_seen = &body_size;
  std::string out;
  const server::MemoryStream::Peer peer{"127.0.0.1", "127.0.0.1", 40000, 8080};
  server::MemoryStream stream(request, out, peer);
  bool closed = false;
  processor().process(stream, close_connection, closed,
                      [&](httplib::Request& parsed) { parse = server::parse_difference(head, parsed); });
  body_seen = nullptr;

  const std::string status_line = out.substr(0, out.find("\r\n"));
  // httplib answers an unparsable Range with its own 416 before anything else sees the request;
  // the front does not read Range, so that answer is httplib's alone to give.
  const bool range_refused =
      status_line.starts_with("HTTP/1.1 416 ") && server::request_from_head(head).has_header("Range");
  if (!parse && !range_refused) return "httplib refused a head the front accepted: " + status_line;
  if (parse && !parse->empty()) return *parse;
  const bool reads_body =
      head.method == "POST" || head.method == "PUT" || head.method == "PATCH" || head.method == "DELETE";
  if (!range_refused && body_read && body_whole && reads_body && !body_decoded_by_httplib(head)) {
    if (!body_size) return "httplib answered without its handler: " + status_line;
    if (*body_size != head.content_length) {
      return "body length: the front read " + std::to_string(head.content_length) + " bytes, httplib " +
             std::to_string(*body_size);
    }
  }
  if (closed && !close_connection) return "keep-alive: httplib closes a connection the front keeps open";
  if (server::answer_closes(out) != close_connection) {
    return std::string("keep-alive: the answer ") + (close_connection ? "does not say" : "says") +
           " 'Connection: close' and the front " + (close_connection ? "closes the connection" : "keeps it open");
  }
  return "";
}

}  // namespace rr::fuzz

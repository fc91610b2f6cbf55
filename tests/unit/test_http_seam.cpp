// The two HTTP parsers of the seam held together (server/httplib_bridge.hpp, fuzz/http_seam_harness):
// every head the connection front accepts, cpp-httplib 0.11 reads to the same method, target, path,
// query, headers, body length and keep-alive. Hand-picked heads where the two could part, the
// longest lines either reads, seeded random heads built from the pieces that matter, and the fuzz
// target's seeds and findings (fuzz/http_seeds, fuzz/http_regressions). Plus what keeps the rest of
// the seam honest: the bodies the service reads are ones both parsers frame, and the runtime
// comparison the service makes on every request does notice a difference.
#include "fuzz/http_seam_harness.hpp"
#include "server/httplib_bridge.hpp"
#include "server/routes.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace rr {
namespace {

using fuzz::seam_disagreement;

TEST(HttpSeam, HeadsWhereTheParsersCouldPartAgree) {
  const char* requests[] = {
      "GET /a%20b?x=%41&y=%u0041&z HTTP/1.1\r\nX-Dec: a%20b%0d%0a\r\nX-Empty:\r\nX-Sp:   v  \r\n\r\n",
      "GET /livez HTTP/1.1\r\nHost: a\r\nhost: b\r\nHOST: c\r\n\r\n",
      "GET / HTTP/1.1\r\nREMOTE_ADDR: 10.0.0.1\r\nLOCAL_PORT: 1\r\n\r\n",
      "GET /x? HTTP/1.1\r\n\r\n",
      "GET /x?a=1&a=2&b HTTP/1.1\r\n\r\n",
      "POST /p HTTP/1.1\r\nContent-Length: 3\r\n\r\nabcXYZ",
      "POST /p HTTP/1.1\r\nContent-Length: 3\r\ncontent-length: 3\r\n\r\nabc",
      "POST /p HTTP/1.1\r\n\r\nabc",
      "PUT /p HTTP/1.1\r\nContent-Length: 00002\r\n\r\n{}",
      "PATCH /p HTTP/1.1\r\nContent-Length: 1\r\n\r\nx",
      "DELETE /p HTTP/1.1\r\nContent-Length: 2\r\n\r\nxy",
      "DELETE /p HTTP/1.1\r\n\r\nxy",
      "GET /p HTTP/1.1\r\nContent-Length: 2\r\n\r\nxy",
      "POST /p HTTP/1.1\r\nExpect: 100-continue\r\nContent-Length: 2\r\n\r\n{}",
      "POST /p HTTP/1.1\r\nExpect: 100-Continue\r\nContent-Length: 2\r\n\r\n{}",
      "POST /p HTTP/1.1\r\nExpect: 100-continue\r\nContent-Length: 0\r\n\r\n",
      "POST /p HTTP/1.1\r\nTransfer-Encoding: chunked\r\nExpect: 100-continue\r\n\r\n2\r\n{}\r\n0\r\n\r\n",
      "POST /p HTTP/1.1\r\nTransfer-Encoding:\r\nContent-Length: 1\r\n\r\nx",
      "GET / HTTP/1.1\r\nConnection: close\r\n\r\n",
      "GET / HTTP/1.1\r\nConnection: Close\r\n\r\n",
      "GET / HTTP/1.1\r\nConnection:\r\nConnection: close\r\n\r\n",
      "GET / HTTP/1.1\r\nConnection: keep-alive, close\r\n\r\n",
      "GET / HTTP/1.1\r\nConnection: keep-alive\r\n\r\n",
      "GET / HTTP/1.0\r\n\r\n",
      "GET / HTTP/1.0\r\nConnection: Keep-Alive\r\n\r\n",
      "GET / HTTP/1.0\r\nConnection: keep-alive\r\n\r\n",
      "GET / HTTP/1.0\r\nConnection:\r\nConnection: Keep-Alive\r\n\r\n",
      "HEAD / HTTP/1.1\r\n\r\n",
      "OPTIONS /v1/render HTTP/1.1\r\nOrigin: https://a.example\r\nAccess-Control-Request-Method: POST\r\n\r\n",
      "GET /\xc3\xa9 HTTP/1.1\r\nX: \xff\xfe\r\n\r\n",
  };
  for (const char* request : requests) EXPECT_EQ(seam_disagreement(request), "") << request;
}

// httplib reads a line of at most 8192 bytes with its CR LF (414 or 400 beyond); the front's
// default cap is that line.
TEST(HttpSeam, TheLongestLinesAgree) {
  for (size_t length = 8186; length <= 8194; ++length) {
    const std::string request_line = "GET /" + std::string(length - 14, 'a') + " HTTP/1.1";
    ASSERT_EQ(request_line.size(), length);
    EXPECT_EQ(seam_disagreement(request_line + "\r\n\r\n"), "") << "a request line of " << length << " bytes";
    const std::string header_line = "X: " + std::string(length - 3, 'v');
    EXPECT_EQ(seam_disagreement("GET / HTTP/1.1\r\n" + header_line + "\r\n\r\n"), "")
        << "a header line of " << length << " bytes";
  }
}

// One random request from the pieces the two parsers treat differently: methods, percent signs and
// question marks in targets, framing and connection fields with odd values and white space, names
// in any case, bare LFs and control bytes.
std::string random_request(std::mt19937& random) {
  auto pick = [&](const std::vector<std::string>& list) { return list[random() % list.size()]; };
  static const std::vector<std::string> methods = {"GET", "POST", "PUT", "PATCH", "DELETE", "OPTIONS", "HEAD", "get"};
  static const std::vector<std::string> target_pieces = {"a", "/", "%20", "%2F", "%u0041", "%",   "%4", "?",
                                                         "=", "&", "+",   "#",   ";",      "%3F", "~",  "\xc3\xa9"};
  static const std::vector<std::string> names = {"Host",       "Content-Length", "content-length", "Transfer-Encoding",
                                                 "Connection", "connection",     "Expect",         "Content-Type",
                                                 "Accept",     "Origin",         "Authorization",  "X-A",
                                                 "x-a",        "REMOTE_ADDR",    "Range"};
  static const std::vector<std::string> values = {"",
                                                  "0",
                                                  "3",
                                                  "03",
                                                  "close",
                                                  "Close",
                                                  "keep-alive",
                                                  "Keep-Alive",
                                                  "x, close",
                                                  "100-continue",
                                                  "100-Continue",
                                                  "chunked",
                                                  "a%20b",
                                                  "%41%0d%0a",
                                                  "application/json",
                                                  "a\tb",
                                                  "Bearer abc",
                                                  "\xff",
                                                  "bytes=0-1",
                                                  "bytes=5-1"};
  static const std::vector<std::string> gaps = {"", " ", "  ", "\t", " \t"};
  std::string target = "/";
  for (size_t n = random() % 6; n > 0; --n) target += pick(target_pieces);
  std::string request = pick(methods) + " " + target + " " + (random() % 5 == 0 ? "HTTP/1.0" : "HTTP/1.1") + "\r\n";
  for (size_t n = random() % 6; n > 0; --n) {
    const std::string end = random() % 40 == 0 ? "\n" : "\r\n";
    request += pick(names) + ":" + pick(gaps) + pick(values) + pick(gaps) + end;
  }
  request += "\r\n";
  for (size_t n = random() % 8; n > 0; --n) request += char('a' + random() % 26);
  return request;
}

TEST(HttpSeam, SeededRandomHeadsAgree) {
  const unsigned seed = 20261205;
  std::mt19937 random(seed);
  size_t accepted = 0;
  for (int i = 0; i < 20000; ++i) {
    const std::string request = random_request(random);
    const std::string difference = seam_disagreement(request);
    ASSERT_EQ(difference, "") << "seed " << seed << ", request " << i << ":\n" << request;
    accepted += server::scan_head(request, server::HeadLimits{}).status == server::HeadStatus::complete ? 1 : 0;
  }
  // The pieces must leave most heads to the comparison, or the test compares nothing.
  EXPECT_GT(accepted, 5000u);
}

TEST(HttpSeam, FuzzSeedsAndFindingsAgree) {
  size_t files = 0;
  for (const char* dir : {"http_seeds", "http_regressions"}) {
    for (const auto& entry : std::filesystem::directory_iterator(testing::source_dir() / "fuzz" / dir)) {
      if (!entry.is_regular_file() || entry.path().filename().string()[0] == '.') continue;
      ++files;
      EXPECT_EQ(seam_disagreement(testing::read_file(entry.path())), "") << entry.path();
    }
  }
  EXPECT_GT(files, 10u);
}

// The seam reads a body only for a route that takes one; both parsers frame those methods' bodies
// the same way (httplib reads none for GET, HEAD or OPTIONS).
TEST(HttpSeam, EveryRouteThatTakesABodyIsAPostOrAPut) {
  for (const server::Route& route : server::service_routes(server::default_server_config())) {
    if (route.consumes.empty()) continue;
    EXPECT_TRUE(route.method == "POST" || route.method == "PUT") << route.method << " " << route.path_template;
  }
}

// httplib inflates encoded bodies and parses form data itself; screening refuses both (415), so no
// route may take them.
TEST(HttpSeam, NoRouteTakesABodyHttplibWouldDecode) {
  for (const server::Route& route : server::service_routes(server::default_server_config())) {
    for (const std::string& type : route.consumes) {
      EXPECT_FALSE(type.starts_with("multipart/") || type == "application/x-www-form-urlencoded")
          << route.method << " " << route.path_template << " takes " << type;
    }
  }
}

// The comparison the service makes on every request (http_server.cpp) tells a difference.
TEST(HttpSeam, ParseDifferenceNamesWhatDiffers) {
  const std::string head_bytes = "GET /a?x=1 HTTP/1.1\r\nX-A: 1\r\n\r\n";
  server::HeadScan scan = server::scan_head(head_bytes, server::HeadLimits{});
  ASSERT_EQ(scan.status, server::HeadStatus::complete);
  httplib::Request same = server::request_from_head(scan.head);
  same.headers.emplace("REMOTE_ADDR", "127.0.0.1");
  EXPECT_EQ(server::parse_difference(scan.head, same), "");
  httplib::Request other = same;
  other.path = "/b";
  EXPECT_NE(server::parse_difference(scan.head, other).find("path"), std::string::npos);
  other = same;
  other.headers.emplace("Content-Length", "5");
  EXPECT_NE(server::parse_difference(scan.head, other).find("headers"), std::string::npos);
  other = same;
  other.params.emplace("y", "2");
  EXPECT_NE(server::parse_difference(scan.head, other), "");
}

}  // namespace
}  // namespace rr

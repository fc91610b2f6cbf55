// The connection front's parse of a request head (server/request_head.hpp): where a head ends, its
// fields, the body length it announces, whether the connection stays open, each cap refused as soon
// as the bytes prove it broken, and every head refused that httplib 0.11 would read another way
// (tests/unit/test_http_seam.cpp holds the accepted ones to httplib's own parse).
#include "server/request_head.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using rr::server::HeadLimits;
using rr::server::HeadStatus;
using rr::server::scan_head;

const HeadLimits small{64, 256, 4};

TEST(RequestHead, CompleteHeadGivesItsLengthFieldsAndBodyFraming) {
  std::string head = "POST /v1/render?x=1 HTTP/1.1\r\nHost: a\r\nContent-Length: 12\r\nX-Empty:\r\n\r\n";
  auto scan = scan_head(head + "{\"camera\":1}", small);
  ASSERT_EQ(scan.status, HeadStatus::complete) << scan.detail;
  EXPECT_EQ(scan.head.head_bytes, head.size());
  EXPECT_EQ(scan.head.method, "POST");
  EXPECT_EQ(scan.head.target, "/v1/render?x=1");
  EXPECT_EQ(scan.head.version, "HTTP/1.1");
  ASSERT_EQ(scan.head.fields.size(), 3u);
  EXPECT_EQ(scan.head.fields[1].name, "Content-Length");
  EXPECT_EQ(scan.head.fields[1].value, "12");
  EXPECT_EQ(scan.head.fields[2].value, "");
  EXPECT_TRUE(scan.head.has_content_length);
  EXPECT_EQ(scan.head.content_length, 12u);
  EXPECT_FALSE(scan.head.has_transfer_encoding);
  EXPECT_TRUE(scan.head.keep_alive);
}

// httplib 0.11 refuses a request line ending in a bare LF and skips a header line ending in one, so
// a Content-Length on such a line would frame a body httplib does not see.
TEST(RequestHead, LinesEndInCrLf) {
  EXPECT_EQ(scan_head("GET / HTTP/1.1\nHost: a\r\n\r\n", small).status, HeadStatus::bad);
  EXPECT_EQ(scan_head("GET / HTTP/1.1\r\nContent-Length: 5\n\r\n", small).status, HeadStatus::bad);
  EXPECT_EQ(scan_head("GET / HTTP/1.1\r\nHost: a\r\n\n", small).status, HeadStatus::bad);
}

TEST(RequestHead, EveryPrefixOfAHeadIsIncomplete) {
  std::string head = "GET /livez HTTP/1.1\r\nHost: a\r\nAccept: */*\r\n\r\n";
  for (size_t n = 0; n < head.size(); ++n) {
    EXPECT_EQ(scan_head(head.substr(0, n), small).status, HeadStatus::incomplete) << "prefix of " << n << " bytes";
  }
}

TEST(RequestHead, RequestLinePastItsCapIs414BeforeItEnds) {
  // 64 bytes and a CR may still be a request line of 64 bytes; a 65th byte that is not a CR is not.
  EXPECT_EQ(scan_head(std::string(64, 'A') + "\r", small).status, HeadStatus::incomplete);
  EXPECT_EQ(scan_head(std::string(65, 'A'), small).status, HeadStatus::request_line_too_long);
  std::string line = "GET /" + std::string(60, 'a') + " HTTP/1.1\r\n";
  EXPECT_EQ(scan_head(line, small).status, HeadStatus::request_line_too_long);
  EXPECT_EQ(rr::server::head_status_code(HeadStatus::request_line_too_long), 414);
}

TEST(RequestHead, DefaultLineCapIsTheLongestLineHttplibReads) {
  EXPECT_EQ(HeadLimits{}.max_request_line_bytes, 8190u);
  const std::string start = "GET /" + std::string(8190 - 14, 'a') + " HTTP/1.1";
  ASSERT_EQ(start.size(), 8190u);
  EXPECT_EQ(scan_head(start + "\r\n\r\n", HeadLimits{}).status, HeadStatus::complete);
  EXPECT_EQ(scan_head("GET /a" + start.substr(5) + "\r\n\r\n", HeadLimits{}).status, HeadStatus::request_line_too_long);
}

TEST(RequestHead, LongHeaderLineManyFieldsOrALargeHeadAre431) {
  const std::string start = "GET / HTTP/1.1\r\n";
  EXPECT_EQ(scan_head(start + "X: " + std::string(70, 'v'), small).status, HeadStatus::header_too_large);
  std::string four = start + "A: 1\r\nB: 1\r\nC: 1\r\nD: 1\r\n";
  EXPECT_EQ(scan_head(four + "\r\n", small).status, HeadStatus::complete);
  EXPECT_EQ(scan_head(four + "E: 1\r\n", small).status, HeadStatus::header_too_large);
  HeadLimits many_fields{64, 256, 100};
  std::string big = start;
  while (big.size() < 300) big += "X-Long: " + std::string(40, 'v') + "\r\n";
  EXPECT_EQ(scan_head(big, many_fields).status, HeadStatus::header_too_large);
  EXPECT_EQ(rr::server::head_status_code(HeadStatus::header_too_large), 431);
}

TEST(RequestHead, BrokenLinesAndLengthsAre400) {
  for (const char* head :
       {"GET /\r\n\r\n", "GET / HTTP/2.0\r\n\r\n", "GET / HTTP/1.1\r\nno colon\r\n\r\n",
        "GET / HTTP/1.1\r\nA: 1\r\n folded\r\n\r\n", "GET / HTTP/1.1\r\nBad Name: 1\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length: 1x\r\n\r\n", "POST / HTTP/1.1\r\nContent-Length: +1\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length:\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length: 99999999999999999999999\r\n\r\n",
        "POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n"}) {
    EXPECT_EQ(scan_head(head, small).status, HeadStatus::bad) << head;
  }
  // The same length twice is one length (RFC 9110 section 8.6).
  EXPECT_EQ(scan_head("POST / HTTP/1.1\r\nContent-Length: 2\r\ncontent-length: 2\r\n\r\n", small).status,
            HeadStatus::complete);
}

// Targets httplib trims, cuts or splits differently, control bytes in values, and framing words
// httplib would percent-decode into something else.
TEST(RequestHead, HeadsHttplibReadsAnotherWayAre400) {
  for (const char* head :
       {"GET  / HTTP/1.1\r\n\r\n", "GET /\t HTTP/1.1\r\n\r\n", "GET /a?b?c HTTP/1.1\r\n\r\n",
        "GET /a??b HTTP/1.1\r\n\r\n", "GET ?x HTTP/1.1\r\n\r\n", "GET * HTTP/1.1\r\n\r\n",
        "GET /a\x01 HTTP/1.1\r\n\r\n", "GET /a#b HTTP/1.1\r\n\r\n", "GET / HTTP/1.1\r\nX: a\rb\r\n\r\n",
        "GET / HTTP/1.1\r\nX: a\x7f\r\n\r\n", "GET / HTTP/1.1\r\nConnection: %63lose\r\n\r\n",
        "POST / HTTP/1.1\r\nExpect: 100%2Dcontinue\r\n\r\n",
        "POST / HTTP/1.1\r\nExpect: 100-continue\r\nExpect: 100-continue\r\n\r\n"}) {
    EXPECT_EQ(scan_head(head, small).status, HeadStatus::bad) << head;
  }
  EXPECT_EQ(scan_head("GET /a%20b?q=%3F HTTP/1.1\r\nX: tab\there\r\n\r\n", small).status, HeadStatus::complete);
}

TEST(RequestHead, MethodsHttplibDoesNotRouteAre501) {
  for (const char* head : {"BREW / HTTP/1.1\r\n\r\n", "TRACE / HTTP/1.1\r\n\r\n", "CONNECT / HTTP/1.1\r\n\r\n"}) {
    EXPECT_EQ(scan_head(head, small).status, HeadStatus::unknown_method) << head;
  }
  EXPECT_EQ(rr::server::head_status_code(HeadStatus::unknown_method), 501);
  EXPECT_EQ(scan_head("PATCH / HTTP/1.1\r\n\r\n", small).status, HeadStatus::complete);
}

TEST(RequestHead, KeepAliveFollowsVersionAndConnection) {
  auto keep = [](const std::string& head) { return scan_head(head + "\r\n", small).head.keep_alive; };
  EXPECT_TRUE(keep("GET / HTTP/1.1\r\n"));
  EXPECT_FALSE(keep("GET / HTTP/1.1\r\nConnection: close\r\n"));
  EXPECT_FALSE(keep("GET / HTTP/1.1\r\nConnection: Close\r\n"));
  EXPECT_FALSE(keep("GET / HTTP/1.1\r\nConnection: keep-alive, close\r\n"));
  EXPECT_TRUE(keep("GET / HTTP/1.1\r\nConnection: keep-alive\r\n"));
  EXPECT_FALSE(keep("GET / HTTP/1.0\r\n"));
  EXPECT_TRUE(keep("GET / HTTP/1.0\r\nConnection: Keep-Alive\r\n"));
  EXPECT_FALSE(keep("GET / HTTP/1.0\r\nConnection: keep-alive\r\n"));  // httplib 0.11 closes it
}

TEST(RequestHead, ExpectContinueIsFoundWithItsLineAndCut) {
  std::string request = "POST / HTTP/1.1\r\nExpect: 100-Continue\r\nContent-Length: 2\r\n\r\n{}";
  auto scan = scan_head(request, small);
  ASSERT_EQ(scan.status, HeadStatus::complete);
  EXPECT_TRUE(scan.head.expects_continue);
  EXPECT_EQ(request.substr(scan.head.expect_begin, scan.head.expect_end - scan.head.expect_begin),
            "Expect: 100-Continue\r\n");
  rr::server::erase_expect_line(request, scan.head);
  EXPECT_EQ(request, "POST / HTTP/1.1\r\nContent-Length: 2\r\n\r\n{}");
  EXPECT_EQ(scan.head.head_bytes, request.size() - 2);
  ASSERT_EQ(scan.head.fields.size(), 1u);
  EXPECT_EQ(scan.head.fields[0].name, "Content-Length");
  EXPECT_FALSE(scan.head.expects_continue);
}

TEST(RequestHead, EmptyLinesBeforeARequestAreSkipped) {
  EXPECT_EQ(rr::server::leading_empty_lines("\r\n\nGET"), 3u);
  EXPECT_EQ(rr::server::leading_empty_lines("\r"), 0u);  // a CR alone may be half of a CR LF
  EXPECT_EQ(rr::server::leading_empty_lines("GET"), 0u);
}

}  // namespace

// Request head framing (server/request_head.hpp): where a head ends, the body length it announces,
// and each cap refused as soon as the bytes prove it broken, before a line or the head is complete.
#include "server/request_head.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using rr::server::HeadLimits;
using rr::server::HeadStatus;
using rr::server::scan_head;

const HeadLimits small{64, 256, 4};

TEST(RequestHead, CompleteHeadGivesItsLengthAndBodyFraming) {
  std::string head = "POST /v1/render?x=1 HTTP/1.1\r\nHost: a\r\nContent-Length: 12\r\n\r\n";
  auto scan = scan_head(head + "{\"camera\":1}", small);
  ASSERT_EQ(scan.status, HeadStatus::complete) << scan.detail;
  EXPECT_EQ(scan.head.head_bytes, head.size());
  EXPECT_EQ(scan.head.method, "POST");
  EXPECT_EQ(scan.head.target, "/v1/render?x=1");
  EXPECT_TRUE(scan.head.has_content_length);
  EXPECT_EQ(scan.head.content_length, 12u);
  EXPECT_FALSE(scan.head.has_transfer_encoding);
}

TEST(RequestHead, BareLineFeedsEndLinesToo) {
  auto scan = scan_head("GET / HTTP/1.0\nHost: a\n\n", small);
  ASSERT_EQ(scan.status, HeadStatus::complete);
  EXPECT_EQ(scan.head.head_bytes, 24u);
}

TEST(RequestHead, EveryPrefixOfAHeadIsIncomplete) {
  std::string head = "GET /livez HTTP/1.1\r\nHost: a\r\nAccept: */*\r\n\r\n";
  for (size_t n = 0; n < head.size(); ++n) {
    EXPECT_EQ(scan_head(head.substr(0, n), small).status, HeadStatus::incomplete) << "prefix of " << n << " bytes";
  }
}

TEST(RequestHead, RequestLinePastItsCapIs414BeforeItEnds) {
  // 65 bytes without a newline cannot be a request line of at most 64 bytes plus CR.
  EXPECT_EQ(scan_head(std::string(65, 'A'), small).status, HeadStatus::incomplete);
  EXPECT_EQ(scan_head(std::string(66, 'A'), small).status, HeadStatus::request_line_too_long);
  std::string line = "GET /" + std::string(60, 'a') + " HTTP/1.1\r\n";
  EXPECT_EQ(scan_head(line, small).status, HeadStatus::request_line_too_long);
  EXPECT_EQ(rr::server::head_status_code(HeadStatus::request_line_too_long), 414);
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
  for (const char* head : {"GET /\r\n\r\n", "GET / HTTP/2.0\r\n\r\n", "GET / HTTP/1.1\r\nno colon\r\n\r\n",
                           "GET / HTTP/1.1\r\nA: 1\r\n folded\r\n\r\n", "GET / HTTP/1.1\r\nBad Name: 1\r\n\r\n",
                           "POST / HTTP/1.1\r\nContent-Length: 1x\r\n\r\n",
                           "POST / HTTP/1.1\r\nContent-Length: 99999999999999999999999\r\n\r\n",
                           "POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n"}) {
    EXPECT_EQ(scan_head(head, small).status, HeadStatus::bad) << head;
  }
  // The same length twice is one length (RFC 9110 section 8.6).
  EXPECT_EQ(scan_head("POST / HTTP/1.1\r\nContent-Length: 2\r\ncontent-length: 2\r\n\r\n", small).status,
            HeadStatus::complete);
}

TEST(RequestHead, ExpectContinueIsFoundWithItsLine) {
  std::string head = "POST / HTTP/1.1\r\nExpect: 100-continue\r\nTransfer-Encoding: chunked\r\n\r\n";
  auto scan = scan_head(head, small);
  ASSERT_EQ(scan.status, HeadStatus::complete);
  EXPECT_TRUE(scan.head.expects_continue);
  EXPECT_TRUE(scan.head.has_transfer_encoding);
  EXPECT_EQ(head.substr(scan.head.expect_begin, scan.head.expect_end - scan.head.expect_begin),
            "Expect: 100-continue\r\n");
}

TEST(RequestHead, EmptyLinesBeforeARequestAreSkipped) {
  EXPECT_EQ(rr::server::leading_empty_lines("\r\n\nGET"), 3u);
  EXPECT_EQ(rr::server::leading_empty_lines("\r"), 0u);  // a CR alone may be half of a CR LF
  EXPECT_EQ(rr::server::leading_empty_lines("GET"), 0u);
}

}  // namespace

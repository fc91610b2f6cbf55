// server/http_util.hpp on exact fixtures: Accept negotiation and If-None-Match matching (RFC 9110),
// base64 against RFC 4648's test vectors, and ids as FNV-1a 64 in hex.
#include "server/http_util.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace {

using namespace rr::server;

TEST(Negotiate, PicksTheBestOfferedTypeByQValueThenServerOrder) {
  const std::vector<std::string> offered = {"image/png", "application/json"};
  EXPECT_EQ(negotiate("", offered), "image/png");
  EXPECT_EQ(negotiate("*/*", offered), "image/png");
  EXPECT_EQ(negotiate("application/json", offered), "application/json");
  EXPECT_EQ(negotiate("application/*", offered), "application/json");
  EXPECT_EQ(negotiate("image/png;q=0.4, application/json;q=0.5", offered), "application/json");
  EXPECT_EQ(negotiate("*/*;q=0.1, image/png;q=0", offered), "application/json") << "the specific range wins";
  EXPECT_EQ(negotiate("APPLICATION/JSON", offered), "application/json");
  EXPECT_EQ(negotiate("text/html", offered), std::nullopt);
  EXPECT_EQ(negotiate("image/png;q=0", offered), std::nullopt);
  EXPECT_EQ(negotiate("image/png;q=abc", offered), "image/png") << "an unreadable q counts as 1";
}

TEST(IfNoneMatch, WeakComparisonOverAList) {
  EXPECT_TRUE(if_none_match_matches("\"abc\"", "\"abc\""));
  EXPECT_TRUE(if_none_match_matches("W/\"abc\"", "\"abc\""));
  EXPECT_TRUE(if_none_match_matches("\"x\", \"abc\"", "\"abc\""));
  EXPECT_TRUE(if_none_match_matches("*", "\"abc\""));
  EXPECT_FALSE(if_none_match_matches("\"abd\"", "\"abc\""));
  EXPECT_FALSE(if_none_match_matches("abc", "\"abc\"")) << "quotes are part of the tag";
  EXPECT_FALSE(if_none_match_matches("", "\"abc\""));
}

TEST(Base64, Rfc4648TestVectors) {
  EXPECT_EQ(base64_encode(""), "");
  EXPECT_EQ(base64_encode("f"), "Zg==");
  EXPECT_EQ(base64_encode("fo"), "Zm8=");
  EXPECT_EQ(base64_encode("foo"), "Zm9v");
  EXPECT_EQ(base64_encode("foob"), "Zm9vYg==");
  EXPECT_EQ(base64_encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64_encode(std::string("\xff\xfe\x00", 3)), "//4A");
}

TEST(HashHex, IsFnv1a64) {
  EXPECT_EQ(hash_hex(""), "cbf29ce484222325");   // the offset basis
  EXPECT_EQ(hash_hex("a"), "af63dc4c8601ec8c");  // published FNV-1a test vector
}

}  // namespace

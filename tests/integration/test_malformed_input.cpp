// Malformed and hostile request bodies over real HTTP: integers spelled as floats are rendered, bytes
// after the JSON text (a NUL included) are refused with 400, and error answers quote at most 64 bytes
// of the client's input however large it was. After each refusal a normal render on a new
// connection is answered.
#include "server_fixture.hpp"

#include <string>

namespace {

using nlohmann::json;
using namespace rr::testing;

class MalformedInputTest : public SharedServerTest<MalformedInputTest> {
 protected:
  static httplib::Result post_render(const std::string& body) {
    return client().Post("/v1/render", body, "application/json");
  }
  // A normal render from a fresh client, hence on a new connection.
  static void expect_render_answered() {
    auto res = post_render(small_request);
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200) << res->body.substr(0, 300);
    PngSize size = png_size(res->body);
    EXPECT_EQ(size.width, 64u);
    EXPECT_EQ(size.height, 48u);
  }
};

// A key of `bytes` bytes: 'a' and then two-byte characters, so a cut at byte 64 would split one.
std::string long_utf8_text(size_t bytes) {
  std::string text = "a";
  while (text.size() + 2 <= bytes) text += "\u00e9";
  return text;
}

TEST_F(MalformedInputTest, IntegersWrittenAsFloatsAreRendered) {
  auto res = post_render(R"({
    "scene": {"floor": {"cells": [4.0, 4.0]},
              "solids": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                          "faces": [[0.0, 1.0, 2.0]]},
                         {"type": "cylinder", "center": [1, 1], "radius": 0.3, "height": 1,
                          "segments": 16.0}]},
    "camera": {"position": [3, 2.5, 4], "target": [0, 0.5, 0]},
    "options": {"width": 64.0, "height": 48.0, "shadows": true,
                "shadow": {"size": 256.0, "pcf": 3.0}, "bsp": {"max_candidates": 8.0}}})");
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200) << res->body.substr(0, 300);
  PngSize size = png_size(res->body);
  EXPECT_EQ(size.width, 64u);
  EXPECT_EQ(size.height, 48u);
  json problem = expect_problem(post_render(R"({"scene":{"floor":{"cells":[4.5,4]}}})"), 422);
  EXPECT_EQ(problem["errors"][0].value("pointer", ""), "/scene/floor/cells/0");
  EXPECT_NE(problem.value("detail", "").find("must be an integer (got 4.5)"), std::string::npos) << problem;
}

TEST_F(MalformedInputTest, NulAfterTheJsonTextIsRefused) {
  const std::string head = R"({"options":{"width":64,"height":48}})";
  const std::string body = head + std::string(1, '\0') + R"({"options":{"width":100000}})";
  ASSERT_EQ(body.size(), head.size() + 29);
  json problem = expect_problem(post_render(body), 400);
  EXPECT_NE(problem.value("detail", "").find("byte " + std::to_string(head.size() + 1) + ": a NUL byte"),
            std::string::npos)
      << problem;
  // Any other trailing byte is refused the same way; trailing whitespace is not.
  expect_problem(post_render(head + "x"), 400);
  auto spaced = post_render(std::string(small_request) + " \r\n\t");
  ASSERT_TRUE(spaced);
  EXPECT_EQ(spaced->status, 200) << spaced->body.substr(0, 300);
  expect_render_answered();
}

TEST_F(MalformedInputTest, HugeUnknownKeyIsNotEchoed) {
  const std::string key = long_utf8_text(4u << 20);
  auto res = post_render(R"({"scene":{")" + key + R"(":1}})");
  json problem = expect_problem(res, 422);
  ASSERT_TRUE(res);
  EXPECT_LT(res->body.size(), 2048u) << res->body.substr(0, 300);
  std::string expected_token = "a";
  for (int i = 0; i < 31; ++i) expected_token += "\u00e9";
  EXPECT_EQ(problem["errors"][0].value("pointer", ""),
            "/scene/" + expected_token + "\u2026(" + std::to_string(key.size()) + " bytes)");
  expect_render_answered();
}

TEST_F(MalformedInputTest, HugeEnumValueIsNotEchoed) {
  auto res = post_render(R"({"options":{"pipeline":")" + long_utf8_text(4u << 20) + R"("}})");
  json problem = expect_problem(res, 422);
  ASSERT_TRUE(res);
  EXPECT_LT(res->body.size(), 2048u) << res->body.substr(0, 300);
  EXPECT_EQ(problem["errors"][0].value("pointer", ""), "/options/pipeline");
  expect_render_answered();
}

TEST_F(MalformedInputTest, HugeUnterminatedStringIsNotEchoed) {
  auto res = post_render(R"({"scene":{")" + long_utf8_text(4u << 20));
  expect_problem(res, 400);
  ASSERT_TRUE(res);
  EXPECT_LT(res->body.size(), 2048u) << res->body.substr(0, 300);
  expect_render_answered();
}

TEST_F(MalformedInputTest, LongQueryParameterIsNotEchoed) {
  auto stored = server_->client().Post("/v1/scenes", json::parse(small_request)["scene"].dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_TRUE(stored->status == 200 || stored->status == 201) << stored->body;
  const std::string location = json::parse(stored->body).at("location");
  auto res = server_->client().Get(location + "/render.png?" + std::string(2000, 'q') + "=1");
  json problem = expect_problem(res, 400);
  ASSERT_TRUE(res);
  EXPECT_LT(res->body.size(), 1024u) << res->body.substr(0, 300);
  EXPECT_EQ(problem["errors"][0].value("parameter", ""), std::string(64, 'q') + "\u2026(2000 bytes)");
}

}  // namespace

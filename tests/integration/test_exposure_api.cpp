// options.exposure over real HTTP: render.png?exposure=2 is another image under another ETag, the
// same exposure twice gives the same bytes (and a 304 to its ETag), exposure=1 the bytes of no
// exposure; "auto" answers with the multiplier it chose in X-Exposure and the JSON answer; bad
// values are problems that name the parameter and /options/exposure.
#include "server_fixture.hpp"

#include <string>

namespace {

using nlohmann::json;
using namespace rr::testing;

class ExposureApiTest : public SharedServerTest<ExposureApiTest> {};

TEST_F(ExposureApiTest, TwoExposuresAreTwoImagesAndOneIsTheSameBytes) {
  auto stored = client().Post("/v1/scenes", scene_with_box_at(1.3).dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string base =
      "/v1/scenes/" + json::parse(stored->body)["id"].get<std::string>() + "/render.png?width=64&height=48";
  auto get = [&](const std::string& query) {
    auto res = client().Get((base + query).c_str());
    EXPECT_TRUE(res);
    EXPECT_EQ(res ? res->status : 0, 200) << query << ": " << (res ? res->body : "");
    return res;
  };
  auto plain = get("");
  auto one = get("&exposure=1");
  auto two = get("&exposure=2");
  auto two_again = get("&exposure=2");
  auto half = get("&exposure=0.5");
  ASSERT_TRUE(plain && one && two && two_again && half);
  EXPECT_EQ(one->body, plain->body);
  EXPECT_EQ(plain->get_header_value("X-Exposure"), "1.0");
  EXPECT_NE(two->body, plain->body);
  EXPECT_NE(half->body, plain->body);
  EXPECT_NE(half->body, two->body);
  EXPECT_EQ(two_again->body, two->body);
  EXPECT_EQ(two->get_header_value("X-Exposure"), "2.0");
  EXPECT_NE(two->get_header_value("ETag"), plain->get_header_value("ETag"));
  EXPECT_EQ(two_again->get_header_value("ETag"), two->get_header_value("ETag"));
  auto cached = client().Get((base + "&exposure=2").c_str(), {{"If-None-Match", two->get_header_value("ETag")}});
  ASSERT_TRUE(cached);
  EXPECT_EQ(cached->status, 304);
  auto other = client().Get((base + "&exposure=0.5").c_str(), {{"If-None-Match", two->get_header_value("ETag")}});
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 200) << "another exposure is not the cached image";

  auto automatic = get("&exposure=auto");
  ASSERT_TRUE(automatic);
  const double chosen = std::stod(automatic->get_header_value("X-Exposure"));
  EXPECT_GE(chosen, 1.0 / 16.0);
  EXPECT_LE(chosen, 16.0);
  EXPECT_EQ(get("&exposure=auto")->body, automatic->body);
}

TEST_F(ExposureApiTest, BadValuesNameTheParameter) {
  auto stored = client().Post("/v1/scenes", scene_with_box_at(1.4).dump(), "application/json");
  ASSERT_TRUE(stored);
  const std::string base = "/v1/scenes/" + json::parse(stored->body)["id"].get<std::string>() + "/render.png?";
  auto check = [&](const std::string& query, int status) {
    json problem = expect_problem(client().Get((base + query).c_str()), status);
    ASSERT_TRUE(problem.contains("errors")) << query << ": " << problem;
    EXPECT_EQ(problem["errors"][0]["parameter"], "exposure") << query;
    EXPECT_EQ(problem["errors"][0]["pointer"], "/options/exposure") << query;
  };
  check("exposure=bright", 400);  // neither a number nor auto: the query is malformed
  check("exposure=nan", 400);
  check("exposure=-1", 422);  // a number out of range: invalid, as width=16.5 is
  check("exposure=0", 422);
  check("exposure=65", 422);
  json body =
      expect_problem(client().Post("/v1/render", R"({"options": {"exposure": "brighter"}})", "application/json"), 422);
  EXPECT_EQ(body["errors"][0]["pointer"], "/options/exposure");
}

TEST_F(ExposureApiTest, TheJsonAnswerSaysTheExposureUsed) {
  json request = json::parse(small_request);
  request["options"]["exposure"] = 3;
  auto res = client().Post("/v1/render", {{"Accept", "application/json"}}, request.dump(), "application/json");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(json::parse(res->body)["exposure"], 3.0);
  EXPECT_EQ(res->get_header_value("X-Exposure"), "3.0");
}

}  // namespace

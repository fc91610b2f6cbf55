// Error answers over real HTTP: a request with several invalid fields gets every one back, with its
// pointer, in reading order; the list stops at 100 and says so; the top-level detail names the first
// pointer; the title is the status line's reason phrase; malformed JSON and limits stay one error.
#include "server_fixture.hpp"

#include <string>
#include <vector>

namespace {

using nlohmann::json;
using namespace rr::testing;

class ErrorAnswersTest : public SharedServerTest<ErrorAnswersTest> {
 protected:
  static httplib::Result post(const std::string& path, const std::string& body) {
    return client().Post(path, body, "application/json");
  }
};

std::vector<std::string> pointers_of(const json& problem) {
  std::vector<std::string> out;
  for (const json& e : problem.value("errors", json::array())) out.push_back(e.value("pointer", "?"));
  return out;
}

json wall(double height) { return {{"start", {0, 0}}, {"end", {4, 0}}, {"height", height}}; }

// Six independent mistakes spread over walls, solids, camera and options.
json request_with_six_errors() {
  json bad_wall = {{"start", {0, 3}}, {"end", {4, 3}}, {"colour", "red"}, {"thickness", 0}};
  return {
      {"scene",
       {{"walls", {wall(-1), wall(2.5), bad_wall}}, {"solids", json::array({{{"type", "box"}, {"center", {1, 1}}}})}}},
      {"camera", {{"fov_y", 200}}},
      {"options", {{"width", 64}, {"height", 48}, {"shading", "glossy"}}}};
}

TEST_F(ErrorAnswersTest, EveryInvalidFieldIsAnsweredInReadingOrder) {
  auto res = post("/v1/render", request_with_six_errors().dump());
  json problem = expect_problem(res, 422);
  ASSERT_TRUE(res);
  EXPECT_EQ(pointers_of(problem),
            (std::vector<std::string>{"/scene/walls/0/height", "/scene/walls/2/colour", "/scene/walls/2/thickness",
                                      "/scene/solids/0", "/camera/fov_y", "/options/shading"}))
      << res->body;
  for (const json& e : problem["errors"]) EXPECT_FALSE(e.value("detail", "").empty()) << e;
  EXPECT_EQ(problem["errors"][3]["detail"], "missing required key \"size\"");
  EXPECT_EQ(problem.value("detail", ""), "/scene/walls/0/height: must be greater than 0 (and 5 more errors)");
  EXPECT_FALSE(problem.contains("errors_truncated"));
  EXPECT_EQ(problem.value("title", ""), "Unprocessable Entity");
  EXPECT_EQ(problem.value("title", ""), res->reason);
}

TEST_F(ErrorAnswersTest, StoredScenesListEveryErrorAtDocumentPointers) {
  json scene = request_with_six_errors()["scene"];
  auto res = post("/v1/scenes", scene.dump());
  json problem = expect_problem(res, 422);
  EXPECT_EQ(pointers_of(problem),
            (std::vector<std::string>{"/walls/0/height", "/walls/2/colour", "/walls/2/thickness", "/solids/0"}));
  EXPECT_EQ(problem.value("detail", ""), "/walls/0/height: must be greater than 0 (and 3 more errors)");
}

// 500 boxes, each with a 1000-byte unknown key: reading stops at the 101st error; every pointer quotes
// at most 64 bytes of the key, so the answer stays small.
TEST_F(ErrorAnswersTest, TheListStopsAtTheCapAndSaysSo) {
  const std::string long_key(1000, 'k');
  json solids = json::array();
  for (int i = 0; i < 500; ++i) {
    solids.push_back({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {long_key, i}});
  }
  auto res = post("/v1/render", json{{"scene", {{"solids", solids}}}}.dump());
  json problem = expect_problem(res, 422);
  ASSERT_TRUE(res);
  EXPECT_LT(res->body.size(), 64u * 1024u);
  ASSERT_EQ(problem.value("errors", json::array()).size(), 100u) << res->body.substr(0, 500);
  EXPECT_EQ(problem.value("errors_truncated", false), true);
  const std::vector<std::string> pointers = pointers_of(problem);
  for (size_t i = 0; i < pointers.size(); ++i) {
    const std::string prefix = "/scene/solids/" + std::to_string(i) + "/" + std::string(64, 'k');
    EXPECT_EQ(pointers[i], prefix + "\u2026(1000 bytes)");
  }
  EXPECT_EQ(problem.value("detail", "").find(pointers[0] + ": unknown key"), 0u) << problem["detail"];
  EXPECT_NE(problem.value("detail", "").find("(and 99 more listed; the list stops at 100)"), std::string::npos)
      << problem["detail"];
}

TEST_F(ErrorAnswersTest, ExactlyTheCapIsNotTruncated) {
  json solids = json::array();
  for (int i = 0; i < 100; ++i) solids.push_back({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 0, 1}}});
  json problem = expect_problem(post("/v1/render", json{{"scene", {{"solids", solids}}}}.dump()), 422);
  EXPECT_EQ(problem.value("errors", json::array()).size(), 100u);
  EXPECT_FALSE(problem.contains("errors_truncated"));
  EXPECT_EQ(problem.value("detail", ""), "/scene/solids/0/size/1: must be greater than 0 (and 99 more errors)");
}

// A door has no sill: its message speaks of its height alone; a window's of sill + height.
TEST_F(ErrorAnswersTest, OpeningsTooTallAreToldInTheirOwnTerms) {
  json openings = {{{"type", "door"}, {"offset", 0.5}, {"width", 0.9}, {"height", 2.6}},
                   {{"type", "window"}, {"offset", 2}, {"width", 1}, {"sill", 1.5}, {"height", 1.2}}};
  json host = {{"start", {0, 0}}, {"end", {4, 0}}, {"height", 2.5}, {"openings", openings}};
  json request = {{"scene", {{"walls", json::array({host})}}}};
  json problem = expect_problem(post("/v1/render", request.dump()), 422);
  ASSERT_EQ(pointers_of(problem), (std::vector<std::string>{"/scene/walls/0/openings/0", "/scene/walls/0/openings/1"}));
  EXPECT_EQ(problem["errors"][0]["detail"], "door is taller than its wall (height 2.6 m > wall height 2.5 m)");
  EXPECT_EQ(problem["errors"][1]["detail"],
            "window extends above its wall (sill + height = 2.7 m > wall height 2.5 m)");
}

// Malformed JSON and a limit stop reading: one error each, even when invalid fields came first.
TEST_F(ErrorAnswersTest, MalformedAndTooLargeStayOneErrorWithTheirReasonPhrase) {
  auto malformed = post("/v1/render", R"({"scene": {"walls": [)");
  json bad_json = expect_problem(malformed, 400);
  ASSERT_TRUE(malformed);
  EXPECT_EQ(bad_json.value("title", ""), "Bad Request");
  EXPECT_EQ(bad_json.value("title", ""), malformed->reason);
  EXPECT_EQ(bad_json.value("errors", json::array()).size(), 1u);

  json request = request_with_six_errors();
  request["options"] = {{"width", 5000}};
  auto too_large = post("/v1/render", request.dump());
  json limit = expect_problem(too_large, 413);
  ASSERT_TRUE(too_large);
  EXPECT_EQ(limit.value("title", ""), "Payload Too Large");
  EXPECT_EQ(limit.value("title", ""), too_large->reason);
  EXPECT_EQ(pointers_of(limit), std::vector<std::string>{"/options/width"});
  EXPECT_EQ(limit.value("detail", ""), "/options/width: must be at most 4096");
}

}  // namespace

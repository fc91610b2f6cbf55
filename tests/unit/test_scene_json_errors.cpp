// scene_json's error list: independent problems are all reported, in reading order, with their
// pointers; a rule over several members is not judged when one of them was refused (no echo of one
// mistake); the list stops at max_listed_errors; InputError's summary names the first pointer.
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace rr {
namespace {

// The error parse_request raises for `text` (a test failure when it accepts the text).
InputError error_of(const std::string& text) {
  try {
    parse_request(text);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << text.substr(0, 200);
  return InputError(InputError::Kind::malformed, "<accepted>", "");
}

std::vector<std::string> pointers(const InputError& e) {
  std::vector<std::string> out;
  for (const FieldProblem& p : e.errors()) out.push_back(p.pointer);
  return out;
}

TEST(SceneJsonErrorList, EveryBadElementOfAMeshIsListed) {
  InputError e = error_of(R"({"scene":{"solids":[{"type":"mesh","vertices":[[0,0,0],[1,"x",0],[0,1,0],[1,1]],
                                "faces":[[0,1,2],[0,2,7],[0,0]]}]}})");
  EXPECT_EQ(e.kind(), InputError::Kind::invalid);
  EXPECT_EQ(pointers(e), (std::vector<std::string>{"/scene/solids/0/vertices/1/1", "/scene/solids/0/vertices/3",
                                                   "/scene/solids/0/faces/1/2", "/scene/solids/0/faces/2"}));
  EXPECT_FALSE(e.truncated());
  EXPECT_EQ(e.pointer(), "/scene/solids/0/vertices/1/1");
  EXPECT_EQ(std::string(e.what()), "must be a number");
}

TEST(SceneJsonErrorList, UnknownKeysAndBadMembersOfOneObjectAreAllListed) {
  InputError e = error_of(R"({"options":{"widht":10,"hieght":10,"shading":"glossy","shadows":1}})");
  EXPECT_EQ(pointers(e),
            (std::vector<std::string>{"/options/hieght", "/options/widht", "/options/shading", "/options/shadows"}));
}

// A rule combining members is judged only on members that were read: one mistake, one error.
TEST(SceneJsonErrorList, CombinedRulesWaitForTheirMembers) {
  // A refused start is not also "end too close to start".
  EXPECT_EQ(pointers(error_of(R"({"scene":{"walls":[{"start":[0,"a"],"end":[0,0]}]}})")),
            std::vector<std::string>{"/scene/walls/0/start/1"});
  // A refused wall height is not also "window above its wall".
  EXPECT_EQ(pointers(error_of(R"({"scene":{"walls":[{"start":[0,0],"end":[5,0],"height":-1,
            "openings":[{"type":"window","offset":1,"width":1,"sill":2.4}]}]}})")),
            std::vector<std::string>{"/scene/walls/0/height"});
  // A refused near is not also "far must be greater than near".
  EXPECT_EQ(pointers(error_of(R"({"camera":{"near":-1,"far":0.05}})")), std::vector<std::string>{"/camera/near"});
  // A refused footprint point is not also "not a simple polygon".
  EXPECT_EQ(pointers(error_of(R"({"scene":{"solids":[{"type":"prism","points":[[0,0],[1,1],[1,"x"],[0,1]],
            "height":1}]}})")),
            std::vector<std::string>{"/scene/solids/0/points/2/1"});
}

TEST(SceneJsonErrorList, StopsAtTheCap) {
  std::string walls;
  for (int i = 0; i < 250; ++i) walls += std::string(i ? "," : "") + R"({"start":[0,0],"end":[1,0],"height":0})";
  InputError e = error_of(R"({"scene":{"walls":[)" + walls + "]}}");
  ASSERT_EQ(e.errors().size(), max_listed_errors);
  EXPECT_TRUE(e.truncated());
  EXPECT_EQ(e.errors().back().pointer, "/scene/walls/99/height");
  EXPECT_EQ(e.summary(), "/scene/walls/0/height: must be greater than 0 (and 99 more listed; the list stops at 100)");
}

TEST(SceneJsonErrorList, LimitsAndSyntaxStayOneError) {
  InputError syntax = error_of(R"({"scene":{"walls":[{"height":-1}], )");
  EXPECT_EQ(syntax.kind(), InputError::Kind::malformed);
  EXPECT_EQ(syntax.errors().size(), 1u);
  InputError limit = error_of(R"({"scene":{"walls":[{"height":-1}]},"options":{"height":100000}})");
  EXPECT_EQ(limit.kind(), InputError::Kind::too_large);
  EXPECT_EQ(pointers(limit), std::vector<std::string>{"/options/height"});
}

TEST(InputErrorSummary, NamesTheFirstPointerAndCountsTheRest) {
  EXPECT_EQ(InputError(InputError::Kind::invalid, "/camera/fov_y", "must be less than 170").summary(),
            "/camera/fov_y: must be less than 170");
  EXPECT_EQ(InputError(InputError::Kind::malformed, "", "syntax error at byte 3").summary(), "syntax error at byte 3");
  InputError two(InputError::Kind::invalid, {{"/a", "bad"}, {"/b", "worse"}}, false);
  EXPECT_EQ(two.summary(), "/a: bad (and 1 more error)");
  EXPECT_EQ(two.with_pointers([](const std::string& p) { return "/scene" + p; }).summary(),
            "/scene/a: bad (and 1 more error)");
}

}  // namespace
}  // namespace rr

// Levels and ceilings over real HTTP: an unknown level, in the scene or in a view of a stored scene,
// is a 422 naming its pointer; a view's level selection gets its own BSP tree in the shared cache
// (a miss, then a hit when repeated) and never changes the scene id.
#include "server_fixture.hpp"

namespace {

using nlohmann::json;
using namespace rr::testing;

const json two_level_scene = json::parse(R"({
  "levels": [{"id": "ground"}, {"id": "upper", "elevation": 3.0, "viewable": false}],
  "rooms": [{"points": [[0, 0], [4, 0], [4, 4], [0, 4]], "level": "ground"},
            {"points": [[0, 0], [4, 0], [4, 4], [0, 4]], "level": "upper"}],
  "walls": [{"start": [0, 0], "end": [4, 0], "level": "ground"}],
  "solids": [{"type": "box", "center": [2, 2], "base": 3.0, "size": [1, 1, 1], "level": "upper"}]
})");

const json above_camera = {{"position", {2.0, 9.0, 8.0}}, {"target", {2.0, 0.0, 2.0}}};

TEST(LevelsApi, UnknownLevelsAre422AtTheirPointer) {
  TestServer server;
  json bad = two_level_scene;
  bad["rooms"][1]["level"] = "attic";
  json problem =
      expect_problem(server.client().Post("/v1/render", json({{"scene", bad}}).dump(), "application/json"), 422);
  EXPECT_EQ(problem["errors"][0]["pointer"], "/scene/rooms/1/level") << problem;
  json view = {{"scene", two_level_scene}, {"options", {{"levels", {"ground", "attic"}}}}};
  problem = expect_problem(server.client().Post("/v1/render", view.dump(), "application/json"), 422);
  EXPECT_EQ(problem["errors"][0]["pointer"], "/options/levels/1") << problem;
  auto stored = server.client().Post("/v1/scenes", two_level_scene.dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string path = "/v1/scenes/" + json::parse(stored->body)["id"].get<std::string>() + "/render";
  problem = expect_problem(
      server.client().Post(path.c_str(), json({{"options", {{"levels", {"attic"}}}}}).dump(), "application/json"), 422);
  EXPECT_EQ(problem["errors"][0]["pointer"], "/options/levels/0") << problem;
  auto ok = server.client().Post(
      path.c_str(), json({{"camera", above_camera}, {"options", {{"levels", {"upper"}}}}}).dump(), "application/json");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200) << ok->body;
}

TEST(LevelsApi, EachSelectionHasItsOwnCachedTreeAndTheSceneIdStays) {
  TestServer server;
  auto draw = [&](const json& levels) {
    json request = {{"scene", two_level_scene},
                    {"camera", above_camera},
                    {"options", {{"width", 32}, {"height", 24}, {"pipeline", "bsp"}, {"levels", levels}}}};
    auto res = server.client().Post("/v1/render", request.dump(), "application/json");
    EXPECT_TRUE(res);
    EXPECT_EQ(res->status, 200) << res->body;
    return std::pair{res->get_header_value("X-Cache"), res->get_header_value("X-Scene-Id")};
  };
  const auto ground = draw({"ground"});
  const auto both = draw({"ground", "upper"});
  const auto ground_again = draw({"ground"});
  EXPECT_EQ(ground.first, "miss");
  EXPECT_EQ(both.first, "miss");  // another selection: another tree
  EXPECT_EQ(ground_again.first, "hit");
  EXPECT_EQ(ground.second, both.second);
}

}  // namespace

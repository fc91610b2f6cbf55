// Picking and framing over real HTTP. Pick: for every element the apartment shows, one of its pixels
// (taken from the id buffer `roomrender render --ids` writes, mapped to elements through the
// library's tessellation) is picked inline and from the stored scene, and must name that element;
// the picked point must project back into the pixel; bad pixels answer 422 at /x or /y. Frame:
// `"camera": {"frame": "all"}` answers the camera it chose, and that camera sent explicitly draws
// the same bytes; without it the answer carries no camera.
#include "integration/server_fixture.hpp"
#include "render/core/camera.hpp"
#include "render/core/image.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "render/scene_io/scene_json.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

namespace {

using nlohmann::json;
using rr::testing::TestServer;
namespace fs = std::filesystem;

json apartment() { return json::parse(rr::testing::read_file(rr::testing::examples_dir() / "apartment.json")); }

// The id buffer of `request` as the CLI writes it.
rr::IdBuffer cli_ids(const json& request) {
  const fs::path dir = rr::testing::output_dir("integration") / "pick";
  fs::create_directories(dir);
  rr::testing::write_file(dir / "request.json", request.dump());
  const std::string command = "cd '" + dir.string() +
                              "' && '" ROOMRENDER_BINARY_DIR
                              "/roomrender' render request.json -o out.png --ids out.ids >/dev/null 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return rr::decode_id_buffer(rr::testing::read_file(dir / "out.ids"));
}

struct Pixel {
  int x = 0, y = 0;
};

// For each element the id buffer shows, its first pixel in row order that is not on an edge (so the
// pick does not hinge on which side of a boundary a pixel centre falls).
std::map<std::string, Pixel> pixel_per_element(const rr::IdBuffer& ids, const rr::PolygonSoup& soup) {
  std::map<std::string, Pixel> out;
  for (int y = 1; y + 1 < ids.height; ++y) {
    for (int x = 1; x + 1 < ids.width; ++x) {
      const uint32_t id = ids.at(x, y);
      if (id == rr::background_id || rr::is_edge_pixel(ids, x, y)) continue;
      out.emplace(rr::element_pointer(soup.objects[soup.polygons[id].object].element), Pixel{x, y});
    }
  }
  return out;
}

json post(TestServer& server, const std::string& path, const json& body, int status = 200) {
  auto res = server.client().Post(path.c_str(), body.dump(), "application/json");
  EXPECT_TRUE(res) << path;
  if (!res) return json();
  EXPECT_EQ(res->status, status) << path << ": " << res->body;
  return json::parse(res->body);
}

TEST(Pick, NamesTheElementTheIdBufferShowsInlineAndStored) {
  TestServer server;
  const json request = apartment();
  const rr::PreparedScene scene = rr::prepare_scene(rr::request_from_json(request).scene);
  const auto pixels = pixel_per_element(cli_ids(request), scene.soup);
  ASSERT_GE(pixels.size(), 10u) << "the apartment's default view shows most of its elements";
  EXPECT_TRUE(pixels.count("/scene/solids/4")) << "chair_west is in view";

  const json stored = post(server, "/v1/scenes", request["scene"], 201);
  const std::string stored_pick = "/v1/scenes/" + stored["id"].get<std::string>() + "/pick";
  const rr::Camera camera = rr::request_from_json(request).camera;
  const rr::ViewTransform view = rr::make_view(camera, 640, 480);
  for (const auto& [pointer, pixel] : pixels) {
    json body = request;
    body["x"] = pixel.x;
    body["y"] = pixel.y;
    const json inline_pick = post(server, "/v1/pick", body);
    EXPECT_EQ(inline_pick["pointer"], pointer) << "pixel " << pixel.x << "," << pixel.y;
    body.erase("scene");
    EXPECT_EQ(post(server, stored_pick, body)["pointer"], pointer.substr(std::string("/scene").size()));

    // The point lies on the picked surface under the pixel's centre, in front of the eye.
    const json& p = inline_pick["point"];
    const rr::Vec2 screen = rr::project_to_screen(view, rr::Vec3(p[0], p[1], p[2]));
    EXPECT_NEAR(screen.x, pixel.x + 0.5, 1e-3) << pointer;
    EXPECT_NEAR(screen.y, pixel.y + 0.5, 1e-3) << pointer;
    EXPECT_GT(inline_pick["depth"].get<double>(), camera.near) << pointer;
  }
}

TEST(Pick, BackgroundHasNoElement) {
  TestServer server;
  json body = apartment();
  body["x"] = 0;
  body["y"] = 0;
  ASSERT_EQ(cli_ids(apartment()).at(0, 0), rr::background_id) << "the corner shows no geometry";
  const json answer = post(server, "/v1/pick", body);
  EXPECT_TRUE(answer["pointer"].is_null());
  EXPECT_TRUE(answer["point"].is_null());
}

TEST(Pick, PixelsOutsideTheImageAnswer422AtTheField) {
  TestServer server;
  const json base = apartment();
  const std::vector<std::tuple<json, json, std::string>> cases = {
      {640, 10, "/x"}, {10, 480, "/y"}, {-1, 10, "/x"},      {10, -1, "/y"},
      {1.5, 10, "/x"}, {10, "3", "/y"}, {nullptr, 10, "/x"}, {10, nullptr, "/y"},
  };
  for (const auto& [x, y, pointer] : cases) {
    json body = base;
    if (!x.is_null()) body["x"] = x;
    if (!y.is_null()) body["y"] = y;
    auto res = server.client().Post("/v1/pick", body.dump(), "application/json");
    const json problem = rr::testing::expect_problem(res, 422);
    EXPECT_EQ(problem["errors"][0]["pointer"], pointer) << body["x"] << "," << body["y"];
  }
  json stored_with_scene = base;
  stored_with_scene["x"] = stored_with_scene["y"] = 1;
  const json stored = post(server, "/v1/scenes", base["scene"], 201);
  const std::string path = "/v1/scenes/" + stored["id"].get<std::string>() + "/pick";
  EXPECT_EQ(
      rr::testing::expect_problem(server.client().Post(path.c_str(), stored_with_scene.dump(), "application/json"),
                                  422)["errors"][0]["pointer"],
      "/scene");
  rr::testing::expect_problem(
      server.client().Post("/v1/scenes/0123456789abcdef/pick", "{\"x\":1,\"y\":1}", "application/json"), 404);
}

json render_json(TestServer& server, const json& body) {
  httplib::Headers headers = {{"Accept", "application/json"}};
  auto res = server.client().Post("/v1/render", headers, body.dump(), "application/json");
  EXPECT_TRUE(res && res->status == 200) << (res ? res->body : "no answer");
  return res ? json::parse(res->body) : json();
}

TEST(Frame, AllAnswersItsCameraWhichDrawsTheSameBytes) {
  TestServer server;
  json request = apartment();
  EXPECT_FALSE(render_json(server, request).contains("camera")) << "a given camera is not echoed";
  request["camera"] = {{"frame", "all"}, {"fov_y", 50}};
  const json framed = render_json(server, request);
  ASSERT_TRUE(framed.contains("camera"));
  EXPECT_EQ(framed["camera"]["fov_y"], 50);
  request["camera"] = framed["camera"];
  EXPECT_EQ(render_json(server, request)["png_base64"], framed["png_base64"]);

  json placed = apartment();
  placed["camera"]["frame"] = "all";
  const json problem =
      rr::testing::expect_problem(server.client().Post("/v1/render", placed.dump(), "application/json"), 422);
  EXPECT_EQ(problem["errors"][0]["pointer"], "/camera/frame");
  placed["camera"] = {{"frame", "some"}};
  EXPECT_EQ(rr::testing::expect_problem(server.client().Post("/v1/render", placed.dump(), "application/json"),
                                        422)["errors"][0]["pointer"],
            "/camera/frame");
}

TEST(Frame, RenderPngQueryParameter) {
  TestServer server;
  const json stored = post(server, "/v1/scenes", apartment()["scene"], 201);
  const std::string base = "/v1/scenes/" + stored["id"].get<std::string>() + "/render.png?width=64&height=48";
  auto framed = server.client().Get((base + "&frame=all").c_str());
  auto plain = server.client().Get(base.c_str());
  ASSERT_TRUE(framed && plain);
  EXPECT_EQ(framed->status, 200);
  EXPECT_NE(framed->body, plain->body) << "framing moves the camera away from the default";
}

}  // namespace

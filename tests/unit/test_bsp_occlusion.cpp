// The BSP pipeline's front-to-back walk with a coverage buffer (render/pipelines/bsp_occlusion.cpp) against
// the classic back-to-front walk it replaces: identical ids and identical pixels (translucent panes
// included) on every example and on seeded random scenes and views, with less work where rooms hide
// each other, and a walk that stops once every pixel is written.
#include "render/pipelines/bsp.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <random>

namespace rr {
namespace {

using json = nlohmann::json;

json bsp_example(const std::string& stem, int width = 320, int height = 240) {
  json r = testing::example_request(stem, width, height);
  r["options"]["pipeline"] = "bsp";
  return r;
}

struct Pair {
  RenderResult back_to_front, front_to_back;
};

Pair render_both(const json& request) {
  RenderRequest r = request_from_json(request);
  PolygonSoup soup = tessellate(r.scene.geometry);
  Pair out;
  r.options.bsp.traversal = BspTraversal::back_to_front;
  out.back_to_front = render_frame(r.scene, soup, r.camera, r.options);
  r.options.bsp.traversal = BspTraversal::front_to_back;
  out.front_to_back = render_frame(r.scene, soup, r.camera, r.options);
  return out;
}

// Exact equality: both walks draw the same polygons with the same rasterizer and shader, and the
// pixel's final writer in one is its first writer in the other.
void expect_identical(const Pair& p) {
  EXPECT_EQ(p.front_to_back.frame.ids.ids, p.back_to_front.frame.ids.ids);
  EXPECT_EQ(p.front_to_back.frame.image.rgb, p.back_to_front.frame.image.rgb);
  EXPECT_LE(p.front_to_back.stats.polygons_drawn, p.back_to_front.stats.polygons_drawn);
}

TEST(BspOcclusion, EveryExampleEqualsTheBackToFrontWalk) {
  for (const auto& file : testing::example_files()) {
    for (const char* shading : {"flat", "phong"}) {
      SCOPED_TRACE(file.stem().string() + " " + shading);
      json request = bsp_example(file.stem().string());
      request["options"]["shading"] = shading;
      request["options"]["shadows"] = std::string(shading) == "phong";
      expect_identical(render_both(request));
    }
  }
}

// Seeded random views inside the apartment (eye level, any direction): walls, doors and translucent
// window panes hide each other in every order.
TEST(BspOcclusion, SeededRandomViewsInsideTheApartmentEqualTheBackToFrontWalk) {
  const json base = bsp_example("apartment", 160, 120);
  for (uint32_t seed = 1; seed <= 30; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(0.3, 11.7), z(0.3, 7.7), y(0.4, 2.4);
    json request = base;
    request["camera"]["position"] = {x(rng), y(rng), z(rng)};
    request["camera"]["target"] = {x(rng), y(rng), z(rng)};
    expect_identical(render_both(request));
  }
}

TEST(BspOcclusion, SeededRandomTrianglesEqualTheBackToFrontWalk) {
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    json vertices = json::array(), faces = json::array();
    for (int t = 0; t < 24; ++t) {
      for (int k = 0; k < 3; ++k) vertices.push_back({u(rng), u(rng) + 1.0, u(rng)});
      faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    }
    json solids = json::array({{{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}}});
    solids.push_back({{"type", "box"}, {"center", {u(rng), u(rng)}}, {"size", {0.5, 0.8, 0.4}}});
    json request = {{"scene", {{"floor", {{"cells", {3, 3}}}}, {"solids", solids}}},
                    {"camera", {{"position", {2.5 * u(rng), 1.0 + u(rng), 3.0}}, {"target", {0.0, 1.0, 0.0}}}},
                    {"options", {{"width", 96}, {"height", 72}, {"pipeline", "bsp"}}}};
    expect_identical(render_both(request));
  }
}

// Standing in a room looking through a door: the rooms beyond are mostly hidden by walls.
TEST(BspOcclusion, EyeLevelApartmentDrawsFewerPolygonsAndFragments) {
  json request = bsp_example("apartment", 640, 360);
  request["camera"]["position"] = {0.5, 1.6, 1.2};
  request["camera"]["target"] = {8.5, 1.1, 3.4};
  Pair p = render_both(request);
  expect_identical(p);
  EXPECT_GT(p.front_to_back.stats.bsp_subtrees_occluded, 0u);
  EXPECT_GT(p.front_to_back.stats.bsp_polygons_occluded, 0u);
  EXPECT_LT(p.front_to_back.stats.polygons_drawn, p.back_to_front.stats.polygons_drawn);
  EXPECT_LT(p.front_to_back.stats.fragments, p.back_to_front.stats.fragments);
  std::printf(
      "eye level 640x360: polygons drawn %zu -> %zu, fragments %zu -> %zu, subtrees occluded %zu, "
      "polygons occluded %zu\n",
      p.back_to_front.stats.polygons_drawn, p.front_to_back.stats.polygons_drawn, p.back_to_front.stats.fragments,
      p.front_to_back.stats.fragments, p.front_to_back.stats.bsp_subtrees_occluded,
      p.front_to_back.stats.bsp_polygons_occluded);
}

// A camera close to a wall sees nothing else: the first polygons fill the screen and the walk ends.
TEST(BspOcclusion, AFullScreenEndsTheWalk) {
  json request = {{"scene",
                   {{"walls", json::array({{{"start", {-5, 0}}, {"end", {5, 0}}, {"height", 3}}})},
                    {"solids", json::array({{{"type", "box"}, {"center", {0, -3}}, {"size", {1, 1, 1}}}})}}},
                  {"camera", {{"position", {0, 1.5, 1.0}}, {"target", {0, 1.5, 0}}}},
                  // Without occlusion culling, which would skip the box in both walks.
                  {"options", {{"width", 64}, {"height", 48}, {"pipeline", "bsp"}, {"culling", "off"}}}};
  Pair p = render_both(request);
  expect_identical(p);
  EXPECT_TRUE(p.front_to_back.stats.bsp_screen_full);
  EXPECT_FALSE(p.back_to_front.stats.bsp_screen_full);
  EXPECT_EQ(p.front_to_back.stats.polygons_drawn, 1u) << "the wall's near face fills the screen";
  EXPECT_GT(p.back_to_front.stats.polygons_drawn, 1u) << "the box behind the wall is drawn, then covered";
  for (uint32_t id : p.front_to_back.frame.ids.ids) ASSERT_EQ(id, p.front_to_back.frame.ids.ids[0]);
}

}  // namespace
}  // namespace rr

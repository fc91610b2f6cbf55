// Whole-object frustum culling (render/core/frustum.hpp): objects wholly outside the view are found, and
// skipping their polygons changes nothing in the zbuffer and painter images (the same pipeline run
// with and without the per-object test, on seeded random rooms of boxes seen from random cameras).
#include "render/core/frustum.hpp"
#include "render/pipelines/painter.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/zbuffer.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <random>

namespace rr {
namespace {

using json = nlohmann::json;

TEST(Frustum, BoxesOnEitherSideOfEachPlane) {
  Camera camera;  // at (0, 1.6, 5) looking at (0, 1, 0), near 0.1, far 100
  const Frustum f(make_view(camera, 64, 48));
  EXPECT_FALSE(f.outside(Vec3(-0.5, 0.5, -0.5), Vec3(0.5, 1.5, 0.5)));             // in front of the eye
  EXPECT_TRUE(f.outside(Vec3(-0.5, 0.5, 6.0), Vec3(0.5, 1.5, 7.0)));               // behind the eye
  EXPECT_TRUE(f.outside(Vec3(20.0, 0.5, -0.5), Vec3(21.0, 1.5, 0.5)));             // far to the right
  EXPECT_TRUE(f.outside(Vec3(-21.0, 0.5, -0.5), Vec3(-20.0, 1.5, 0.5)));           // far to the left
  EXPECT_TRUE(f.outside(Vec3(-0.5, 0.5, -200.0), Vec3(0.5, 1.5, -199.0)));         // beyond the far plane
  EXPECT_TRUE(f.outside(Vec3(-0.01, 1.59, 4.95), Vec3(0.01, 1.61, 4.97)));         // between eye and near
  EXPECT_FALSE(f.outside(Vec3(-100.0, -100.0, -50.0), Vec3(100.0, 100.0, 50.0)));  // around it all
}

json random_room(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-6.0, 6.0), size(0.2, 1.5);
  json solids = json::array();
  for (int k = 0; k < 30; ++k) {
    json center = {u(rng), u(rng)};
    if (k % 3) {
      solids.push_back({{"type", "box"}, {"center", center}, {"size", {size(rng), size(rng), size(rng)}}});
    } else {
      solids.push_back({{"type", "cylinder"}, {"center", center}, {"radius", 0.4}, {"height", size(rng)}});
    }
  }
  return {{"scene",
           {{"floor", {{"cells", {6, 6}}}},
            {"solids", solids},
            {"lights", json::array({{{"type", "directional"}, {"direction", {-0.3, -1, -0.2}}}})}}},
          {"camera", {{"position", {u(rng), 1.6, u(rng)}}, {"target", {u(rng), 0.8, u(rng)}}, {"fov_y", 50}}},
          {"options", {{"width", 120}, {"height", 90}, {"shading", "phong"}, {"shadows", true}}}};
}

TEST(Frustum, SkippingObjectsOutsideTheViewChangesNoPixel) {
  size_t culled_total = 0;
  for (uint32_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    RenderRequest r = request_from_json(random_room(rng));
    PolygonSoup soup = tessellate(r.scene.geometry);
    const ViewTransform view = make_view(r.camera, r.options.width, r.options.height);
    const ObjectsInView objects = objects_in_view(soup, view);
    culled_total += objects.culled;
    for (auto draw : {&draw_zbuffer, &draw_painter}) {
      Frame with{Image(r.options.width, r.options.height, r.scene.background),
                 IdBuffer(r.options.width, r.options.height)};
      Frame without = with;
      RenderStats s1, s2;
      StageTimings t1, t2;
      FrameInput culled{r.scene, soup, view, r.options, {}};
      culled.objects_in_view = &objects.visible;
      FrameInput all{r.scene, soup, view, r.options, {}};
      draw(culled, with, s1, t1);
      draw(all, without, s2, t2);
      EXPECT_EQ(with.ids.ids, without.ids.ids);
      EXPECT_EQ(with.image.rgb, without.image.rgb);
      // A culled object's polygons are clipped away or land in the guard band off the image: they
      // may reach the rasterizer without the test, but never cover a pixel.
      EXPECT_EQ(s1.fragments, s2.fragments);
      EXPECT_LE(s1.polygons_drawn, s2.polygons_drawn);
    }
  }
  EXPECT_GT(culled_total, 20u) << "random cameras in a room of 30 solids must leave some outside the view";
}

TEST(Frustum, EyeLevelApartmentReportsCulledObjects) {
  json request = json::parse(testing::read_file(testing::examples_dir() / "apartment.json"));
  request["camera"]["position"] = {0.5, 1.6, 1.2};
  request["camera"]["target"] = {8.5, 1.1, 3.4};
  RenderRequest r = request_from_json(request);
  PolygonSoup soup = tessellate(r.scene.geometry);
  RenderResult result = render_frame(r.scene, soup, r.camera, r.options);
  EXPECT_GT(result.stats.objects_culled, 0u);
  EXPECT_LT(result.stats.objects_culled, soup.objects.size());
  r.options.pipeline = pipeline_id("bsp");
  EXPECT_EQ(render_frame(r.scene, soup, r.camera, r.options).stats.objects_culled, 0u) << "bsp culls subtrees";
}

}  // namespace
}  // namespace rr

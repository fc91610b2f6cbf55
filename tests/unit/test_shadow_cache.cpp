// The shadow cache (render/pipelines/shadow_cache.hpp): which frames reuse maps (same scene, light set and map
// options; any camera for fit "scene", the same view for fit "view"), that a reused map gives the
// bytes a frame's own pass gives, that a dark or recoloured light does not change the key while a
// moved one does, and that simultaneous first requests run one pass.
#include "render/core/shadow.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/shadow_cache.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/render_helpers.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <thread>

namespace rr {
namespace {

using json = nlohmann::json;

json shadowed(const std::string& stem, const std::string& fit) {
  json r = json::parse(testing::read_file(testing::examples_dir() / (stem + ".json")));
  r["options"]["width"] = 240;
  r["options"]["height"] = 180;
  r["options"]["shading"] = "phong";
  r["options"]["shadows"] = true;
  r["options"]["shadow"] = {{"fit", fit}, {"size", 1024}, {"pcf", 3}};
  return r;
}

// The same frame rendered with no cache at all: its own shadow pass.
rr::testing::TextRender uncached(const json& request) { return rr::testing::render_text(request.dump()); }

void expect_same_frame(const rr::testing::TextRender& a, const rr::testing::TextRender& b) {
  EXPECT_EQ(a.result.frame.image.rgb, b.result.frame.image.rgb);
  EXPECT_EQ(a.result.frame.ids.ids, b.result.frame.ids.ids);
  EXPECT_EQ(a.png, b.png);
}

TEST(ShadowCache, SceneFitServesASecondCameraWithNoShadowPass) {
  for (const char* stem : {"studio", "studio_lamp", "apartment"}) {  // directional; + point; 6 rooms
    SCOPED_TRACE(stem);
    ShadowCache cache(256u << 20);
    const RenderContext context{nullptr, nullptr, "", &cache};
    json first = shadowed(stem, "scene");
    json second = first;
    second["camera"]["position"] = {1.0, 1.7, 1.0};
    rr::testing::TextRender a = rr::testing::render_text(first.dump(), context);
    rr::testing::TextRender b = rr::testing::render_text(second.dump(), context);
    EXPECT_EQ(a.result.stats.shadow_cache, "miss");
    EXPECT_EQ(a.result.stats.shadow_passes, 1u);
    EXPECT_FALSE(a.result.stats.shadow_skipped);
    EXPECT_EQ(b.result.stats.shadow_cache, "hit");
    EXPECT_EQ(b.result.stats.shadow_passes, 0u);
    EXPECT_FALSE(b.result.stats.shadow_skipped) << "the reused maps are looked up";
    EXPECT_EQ(cache.stats().builds, 1u);
    EXPECT_GT(cache.stats().bytes, 0u);
    // A hit is byte for byte the frame that runs its own pass.
    expect_same_frame(b, uncached(second));
    expect_same_frame(a, uncached(first));
    EXPECT_NE(a.png, b.png);
  }
}

TEST(ShadowCache, ViewFitIsReusedOnlyForTheSameView) {
  ShadowCache cache(256u << 20);
  const RenderContext context{nullptr, nullptr, "", &cache};
  json request = shadowed("studio", "view");
  EXPECT_EQ(rr::testing::render_text(request.dump(), context).result.stats.shadow_cache, "miss");
  // Another shading mode and image size of the same aspect: the same maps.
  json same_view = request;
  same_view["options"]["shading"] = "gouraud";
  same_view["options"]["width"] = 480;
  same_view["options"]["height"] = 360;
  rr::testing::TextRender hit = rr::testing::render_text(same_view.dump(), context);
  EXPECT_EQ(hit.result.stats.shadow_cache, "hit");
  expect_same_frame(hit, uncached(same_view));
  json moved = request;
  moved["camera"]["position"] = {1.0, 1.7, 1.0};
  EXPECT_EQ(rr::testing::render_text(moved.dump(), context).result.stats.shadow_cache, "miss");
  EXPECT_EQ(cache.stats().builds, 2u);
}

TEST(ShadowCache, AMovedLightMissesARecolouredOneHits) {
  ShadowCache cache(256u << 20);
  const RenderContext context{nullptr, nullptr, "", &cache};
  json request = shadowed("studio", "scene");
  EXPECT_EQ(rr::testing::render_text(request.dump(), context).result.stats.shadow_cache, "miss");
  // The pass reads a light's direction, not its colour or (non-zero) intensity.
  json recoloured = request;
  recoloured["scene"]["lights"][0]["color"] = "#ff8040";
  recoloured["scene"]["lights"][0]["intensity"] = 0.5;
  rr::testing::TextRender hit = rr::testing::render_text(recoloured.dump(), context);
  EXPECT_EQ(hit.result.stats.shadow_cache, "hit");
  expect_same_frame(hit, uncached(recoloured));
  json moved = request;
  moved["scene"]["lights"][0]["direction"] = {0.4, -1.0, -0.6};
  rr::testing::TextRender miss = rr::testing::render_text(moved.dump(), context);
  EXPECT_EQ(miss.result.stats.shadow_cache, "miss");
  expect_same_frame(miss, uncached(moved));
  // Map options enter the key too.
  json sharper = request;
  sharper["options"]["shadow"]["size"] = 2048;
  EXPECT_EQ(rr::testing::render_text(sharper.dump(), context).result.stats.shadow_cache, "miss");
  EXPECT_EQ(cache.stats().builds, 3u);
}

TEST(ShadowCache, NoMapsWantedMeansNoLookup) {
  ShadowCache cache(256u << 20);
  const RenderContext context{nullptr, nullptr, "", &cache};
  json request = shadowed("studio", "scene");
  request["options"]["shadows"] = false;
  rr::testing::TextRender off = rr::testing::render_text(request.dump(), context);
  EXPECT_EQ(off.result.stats.shadow_cache, "none");
  EXPECT_EQ(off.result.stats.shadow_passes, 0u);
  EXPECT_EQ(cache.stats().hits + cache.stats().misses, 0u);
}

TEST(ShadowCache, EightSimultaneousFirstRequestsRunOnePass) {
  ShadowCache cache(256u << 20);
  const std::string text = shadowed("apartment", "scene").dump();
  std::vector<rr::testing::TextRender> renders(8);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < renders.size(); ++t) {
    threads.emplace_back([&, t] {
      renders[t] = rr::testing::render_text(text, RenderContext{nullptr, nullptr, "", &cache});
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(cache.stats().builds, 1u);
  size_t passes = 0;
  for (const rr::testing::TextRender& r : renders) {
    passes += r.result.stats.shadow_passes;
    EXPECT_EQ(r.png, renders[0].png);
  }
  EXPECT_EQ(passes, 1u);
}

// Fitting to the whole scene costs resolution, not correctness: against the view-fitted map the
// image differs only along shadow edges. Tolerance: a channel off by more than 24 (a PCF tap's
// worth of a shadow edge moving by a texel) on at most 1.5 % of the pixels.
TEST(ShadowCache, SceneFitShadowsAgreeWithViewFitShadows) {
  for (const char* stem : {"studio", "studio_lamp", "apartment"}) {
    SCOPED_TRACE(stem);
    const Image view = uncached(shadowed(stem, "view")).result.frame.image;
    const Image scene = uncached(shadowed(stem, "scene")).result.frame.image;
    const Image none = [&] {
      json r = shadowed(stem, "view");
      r["options"]["shadows"] = false;
      return uncached(r).result.frame.image;
    }();
    size_t differ = 0, shadowed_pixels = 0;
    for (size_t i = 0; i < view.rgb.size(); i += 3) {
      bool far = false, dark = false;
      for (size_t c = 0; c < 3; ++c) {
        far |= std::abs(int(view.rgb[i + c]) - int(scene.rgb[i + c])) > 24;
        dark |= view.rgb[i + c] + 24 < none.rgb[i + c];
      }
      differ += far;
      shadowed_pixels += dark;
    }
    const size_t pixels = view.rgb.size() / 3;
    EXPECT_GT(shadowed_pixels, pixels / 100) << "the scene must show shadows for this test to mean anything";
    EXPECT_LE(differ, pixels * 15 / 1000) << differ << " of " << pixels;
  }
}

}  // namespace
}  // namespace rr

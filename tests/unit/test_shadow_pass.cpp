// The tiled shadow rasterizer against the per-fragment one it replaced: on seeded random soups and
// on every example, under a directional and a point light, the same maps drawn both ways agree in
// every texel and in which pages were written; the pass gives the same maps and block summaries on
// 1, 2 and 8 threads; each block summary is its texels' range. Map sides that are not a multiple
// of the 64-texel tile or the 32-texel page put partial tiles and pages in the comparison.
#include "render/core/draw.hpp"
#include "render/core/shadow.hpp"
#include "render/core/shadow_raster.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/soup_builder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <numeric>
#include <random>
#include <string>

namespace rr {
namespace {

// The per-fragment path: every caster clipped to the map's exact frustum, projected, and its fan
// rasterized by rasterize_convex, each fragment writing max(texel, float(inv_w)) through
// TexelStore::write. Returns whether some caster survived clipping.
bool draw_per_fragment(const ShadowMapJob& job, int side, const PolygonSoup& soup, TexelStore& texels) {
  ViewTransform view;
  view.clip_from_world = job.clip;
  view.width = view.height = side;
  texels = TexelStore(side);
  shadow_detail::ClipBuffers buf;
  bool any = false;
  for (uint32_t c : job.casters) {
    if (!shadow_detail::clip_points(shadow_detail::exact_frustum(job.clip), soup.points(soup.polygons[c]), buf))
      continue;
    any = true;
    buf.screen.resize(buf.out.size());
    for (size_t i = 0; i < buf.out.size(); ++i) {
      const ClipVertex& v = buf.out[i];
      const Vec4 p_clip(v.p_clip.x / clip_guard_band, v.p_clip.y / clip_guard_band, v.p_clip.z, v.p_clip.w);
      const Vec2 s = screen_from_clip(view, p_clip);
      const double value = job.directional ? job.far_depth - glm::dot(v.p_world, job.forward) : 1.0 / v.p_clip.w;
      buf.screen[i] = {s.x, s.y, value};
    }
    rasterize_convex(buf.screen, {0, 0, side, side}, [&](const Fragment& f, size_t) {
      float& t = texels.write(f.x, f.y);
      t = std::max(t, float(f.inv_w));
    });
  }
  return any;
}

// Every texel of the pages' area (past the side too) as bits, and which pages exist.
size_t count_differences(const TexelStore& a, const TexelStore& b, std::string& first) {
  size_t differ = 0;
  const size_t pages = a.pages_per_row(), n = pages * TexelStore::page_side;
  for (size_t row = 0; row < pages; ++row) {
    for (size_t column = 0; column < pages; ++column) {
      if ((a.page(row, column) == nullptr) != (b.page(row, column) == nullptr) && differ++ == 0) {
        first = "page (" + std::to_string(row) + ", " + std::to_string(column) + ") written in one only";
      }
    }
  }
  for (size_t v = 0; v < n; ++v) {
    for (size_t u = 0; u < n; ++u) {
      const float x = a.at(int(u), int(v)), y = b.at(int(u), int(v));
      if (std::bit_cast<uint32_t>(x) != std::bit_cast<uint32_t>(y) && differ++ == 0) {
        first = "texel (" + std::to_string(u) + ", " + std::to_string(v) + "): " + std::to_string(x) + " vs " +
                std::to_string(y);
      }
    }
  }
  return differ;
}

// Draws each map of `maps` again from all of the soup's polygons (any caster list will do: the
// rasterizers are compared, not the planning), tiled on `threads` threads and per fragment.
void expect_rasterizers_agree(const ShadowMaps& maps, const PolygonSoup& soup, unsigned threads) {
  std::vector<uint32_t> all(soup.polygons.size());
  std::iota(all.begin(), all.end(), 0u);
  std::vector<ShadowMapJob> jobs;
  for (const ShadowLight& light : maps.lights) {
    for (int32_t m : light.map) {
      if (m < 0) continue;
      ShadowMapJob job;
      job.clip = maps.maps[size_t(m)].view.clip_from_world;
      job.directional = light.directional, job.forward = light.forward, job.far_depth = light.far_depth;
      job.casters = all;
      jobs.push_back(std::move(job));
    }
  }
  ASSERT_FALSE(jobs.empty()) << "no map to compare";
  draw_shadow_jobs(jobs, maps.side, soup, threads, nullptr);
  for (size_t j = 0; j < jobs.size(); ++j) {
    TexelStore oracle;
    EXPECT_EQ(draw_per_fragment(jobs[j], maps.side, soup, oracle), jobs[j].any_caster) << "map " << j;
    std::string first;
    EXPECT_EQ(count_differences(jobs[j].texels, oracle, first), 0u) << "map " << j << ", first: " << first;
  }
}

// Each block summary is the range of its shadow_block^2 texels (0 where no page was written).
void expect_blocks_summarize(const ShadowMap& map) {
  for (int by = 0; by < map.blocks_per_row; ++by) {
    for (int bx = 0; bx < map.blocks_per_row; ++bx) {
      float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
      for (int v = by * shadow_block; v < (by + 1) * shadow_block; ++v) {
        for (int u = bx * shadow_block; u < (bx + 1) * shadow_block; ++u) {
          lo = std::min(lo, map.nearness.at(u, v)), hi = std::max(hi, map.nearness.at(u, v));
        }
      }
      const size_t b = size_t(by * map.blocks_per_row + bx);
      ASSERT_EQ(map.block_min[b], lo) << "block " << bx << ", " << by;
      ASSERT_EQ(map.block_max[b], hi) << "block " << bx << ", " << by;
    }
  }
}

void expect_same_maps(const ShadowMaps& a, const ShadowMaps& b) {
  ASSERT_EQ(a.side, b.side);
  ASSERT_EQ(a.maps.size(), b.maps.size());
  ASSERT_EQ(a.lights.size(), b.lights.size());
  EXPECT_EQ(a.slot_of_light, b.slot_of_light);
  for (size_t l = 0; l < a.lights.size(); ++l) {
    EXPECT_EQ(a.lights[l].map, b.lights[l].map);
    EXPECT_EQ(a.lights[l].left, b.lights[l].left);
    EXPECT_EQ(a.lights[l].top, b.lights[l].top);
    EXPECT_EQ(a.lights[l].far_depth, b.lights[l].far_depth);
  }
  for (size_t m = 0; m < a.maps.size(); ++m) {
    EXPECT_TRUE(a.maps[m].view.clip_from_world == b.maps[m].view.clip_from_world) << "map " << m;
    std::string first;
    EXPECT_EQ(count_differences(a.maps[m].nearness, b.maps[m].nearness, first), 0u) << "map " << m << ": " << first;
    EXPECT_EQ(a.maps[m].block_min, b.maps[m].block_min) << "map " << m;
    EXPECT_EQ(a.maps[m].block_max, b.maps[m].block_max) << "map " << m;
  }
}

// The pass on 1 thread, its maps' summaries, the same maps on 2 and 8 threads, and both rasterizers.
void check_scene(const Scene& scene, const PolygonSoup& soup, const ViewTransform& view, const RenderOptions& options) {
  const ShadowMaps one = build_shadow_maps(scene, soup, view, options, nullptr, 1);
  ASSERT_FALSE(one.empty()) << "no light cast a shadow";
  for (const ShadowMap& map : one.maps) expect_blocks_summarize(map);
  for (unsigned threads : {2u, 8u}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    expect_same_maps(one, build_shadow_maps(scene, soup, view, options, nullptr, threads));
  }
  expect_rasterizers_agree(one, soup, 2);
}

Light directional_light(Vec3 direction) {
  Light light;
  light.type = LightType::directional;
  light.direction = glm::normalize(direction);
  return light;
}

Light point_light(Vec3 position) {
  Light light;
  light.type = LightType::point;
  light.position = position;
  return light;
}

TEST(ShadowPass, TiledMapsMatchPerFragmentMapsOnRandomSoups) {
  const auto seeds = testing::test_seeds(1500, 6);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " (ROOMRENDER_TEST_SEED replays it)");
    std::mt19937 rng(seed);
    const PolygonSoup soup = testing::random_triangle_soup(rng, 400, 3.0);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Scene scene;
    scene.lights = {directional_light({unit(rng), -1.0, unit(rng)}), point_light({unit(rng), unit(rng), unit(rng)})};
    Camera camera;
    camera.position = {6.0 * unit(rng), 4.0, 7.0};
    camera.target = {0.0, 0.0, 0.0};
    RenderOptions options;
    const int sides[] = {64, 100, 517, 2048, 1000, 333};
    options.shadow.size = sides[seed % 6];
    options.shadow.pcf = seed % 2 ? 3 : 1;
    options.shadow.fit = seed % 3 == 2 ? ShadowFit::scene : ShadowFit::view;
    check_scene(scene, soup, make_view(camera, 320, 200), options);
  }
}

TEST(ShadowPass, TiledMapsMatchPerFragmentMapsOnTheExamples) {
  size_t checked = 0;
  for (const auto& file : testing::example_files()) {
    const RenderRequest request = request_from_json(nlohmann::json::parse(testing::read_file(file)));
    const PolygonSoup soup = tessellate(request.scene.geometry);
    if (soup.polygons.empty()) continue;
    SCOPED_TRACE(file.filename().string());
    Scene scene = request.scene;
    // The example's own lights, and a sun and a lamp near the camera's target on top.
    scene.lights.push_back(directional_light({0.45, -1.0, 0.3}));
    scene.lights.push_back(point_light(request.camera.target + Vec3(0.3, 1.2, 0.2)));
    RenderOptions options = request.options;
    options.shadow.size = 1000;
    check_scene(scene, soup, make_view(request.camera, 400, 300), options);
    ++checked;
  }
  EXPECT_GT(checked, 5u) << "examples not found";
}

}  // namespace
}  // namespace rr

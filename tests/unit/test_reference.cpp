// The reference renderer: its pixel-centre coverage equals the rasterizer's exactly for vertices on
// the sub-pixel grid (top-left rule on shared edges included); whole frames agree with the
// z-buffer away from id edges (near-plane crossing, back faces, translucency); its colour is
// shade_point's at the pixel's exact hit point; its shadow rays shadow exactly the analytic
// footprint; and the shadow mask of the rasterizing pipelines agrees with it away from shadow edges.
#include "render/core/error_metrics.hpp"
#include "render/core/shading.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/pipelines/reference.hpp"
#include "support/render_helpers.hpp"
#include "support/soup_builder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <random>

namespace rr {
namespace {

using nlohmann::json;

RenderContext with_shadow_mask() {
  RenderContext context;
  context.shadow_mask = true;
  return context;
}

// Pixel centres covered by the rasterizer's fan of `screen` (each counted), on a w x h grid.
std::vector<int> raster_coverage(const std::vector<RasterVertex>& screen, int w, int h) {
  std::vector<int> count(size_t(w * h), 0);
  rasterize_convex(screen, PixelRect{0, 0, w, h}, [&](const Fragment& f, size_t) { ++count[size_t(f.y * w + f.x)]; });
  return count;
}

TEST(Reference, CoverageEqualsTheRasterizersOnTheSubpixelGrid) {
  // Random convex quads and triangles with vertices on the sub-pixel grid, a third of them on pixel
  // centres (so edges run through centres and the top-left rule decides), plus the two halves of
  // a square split along its diagonal: every pixel centre is covered by exactly the same test.
  const auto seeds = testing::test_seeds(4242, 300);
  const int w = 16, h = 12;
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    const int64_t one = subpixel_one;
    std::uniform_int_distribution<int64_t> grid(-2 * one, 18 * one);
    std::uniform_int_distribution<int> centre(0, 15);
    std::vector<RasterVertex> tri(3);
    for (RasterVertex& v : tri) {
      const bool on_centre = rng() % 3 == 0;
      v.x = on_centre ? centre(rng) + 0.5 : double(grid(rng)) / double(one);
      v.y = on_centre ? centre(rng) % h + 0.5 : double(grid(rng)) / double(one);
    }
    std::vector<Vec2> xy;
    for (const RasterVertex& v : tri) xy.push_back({v.x, v.y});
    const std::vector<int> raster = raster_coverage(tri, w, h);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        ASSERT_EQ(covers_screen_point(xy, x + 0.5, y + 0.5), raster[size_t(y * w + x)] == 1)
            << "seed " << seed << " (replay with ROOMRENDER_TEST_SEED=" << seed << "), pixel " << x << "," << y;
      }
    }
  }
  // A square on pixel centres and its diagonal halves: the halves tile the square exactly once.
  const std::vector<Vec2> a = {{2.5, 2.5}, {9.5, 2.5}, {9.5, 8.5}}, b = {{2.5, 2.5}, {9.5, 8.5}, {2.5, 8.5}};
  const std::vector<Vec2> square = {{2.5, 2.5}, {9.5, 2.5}, {9.5, 8.5}, {2.5, 8.5}};
  std::vector<RasterVertex> quad;
  for (const Vec2& p : square) quad.push_back({p.x, p.y, 1.0});
  const std::vector<int> raster = raster_coverage(quad, w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      EXPECT_EQ(covers_screen_point(square, px, py), raster[size_t(y * w + x)] == 1) << x << "," << y;
      EXPECT_EQ(int(covers_screen_point(a, px, py)) + int(covers_screen_point(b, px, py)),
                int(covers_screen_point(square, px, py)))
          << x << "," << y;
    }
  }
  EXPECT_FALSE(covers_screen_point(std::vector<Vec2>{{1, 1}, {3, 3}, {5, 5}}, 3.0, 3.0));  // no area
}

json room_request(const std::string& pipeline) {
  json request = json::parse(testing::read_file(testing::examples_dir() / "studio.json"));
  request["options"] = {{"width", 96}, {"height", 72}, {"pipeline", pipeline}};
  request["scene"]["lights"] = json::array();  // ambient only: every pipeline's colour is exact
  return request;
}

TEST(Reference, AmbientOnlyRoomEqualsTheZbufferAwayFromEdges) {
  // With ambient light only, a polygon's colour is one constant in every mode, so the reference
  // and the z-buffer must give the same id and the same bytes at every non-edge pixel.
  auto truth = testing::render_json(room_request("reference"));
  auto z = testing::render_json(room_request("zbuffer"));
  const Frame& r = truth.result.frame;
  size_t compared = 0;
  for (int y = 0; y < r.ids.height; ++y) {
    for (int x = 0; x < r.ids.width; ++x) {
      if (is_edge_pixel(r.ids, x, y)) continue;
      ++compared;
      ASSERT_EQ(r.ids.at(x, y), z.result.frame.ids.at(x, y)) << x << "," << y;
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(testing::channel(r.image, x, y, c), testing::channel(z.result.frame.image, x, y, c));
    }
  }
  EXPECT_GT(compared, size_t(96 * 72 / 2));
  EXPECT_EQ(truth.result.stats.polygons_drawn + truth.result.stats.polygons_culled, truth.soup.polygons.size());
}

// A floor quad (open), an optional closed box above it and one light; camera above looking down.
json shadow_request(const std::string& pipeline, json light, bool shadows) {
  return {{"scene",
           {{"ambient", {{"intensity", 0.2}}},
            {"floor", {{"origin", {-4, -4}}, {"cells", {1, 1}}, {"cell_size", 8}, {"colors", {"#808080", "#808080"}}}},
            {"solids", {{{"type", "box"}, {"center", {0.5, -0.5}}, {"base", 1.0}, {"size", {1.0, 0.5, 2.0}}}}},
            {"lights", {std::move(light)}}}},
          {"camera", {{"position", {0, 9, 6}}, {"target", {0, 0, 0}}}},
          {"options",
           {{"width", 120}, {"height", 90}, {"pipeline", pipeline}, {"shading", "phong"}, {"shadows", shadows}}}};
}

TEST(Reference, ColourIsShadePointAtTheExactHitPoint) {
  json light = {{"type", "point"}, {"position", {1.0, 3.0, 2.0}}, {"intensity", 0.9}, {"attenuation", {1, 0.1, 0.02}}};
  auto r = testing::render_json(shadow_request("reference", light, false));
  const Frame& f = r.result.frame;
  const Material& floor_material = r.soup.materials[r.soup.polygons[0].material];
  size_t checked = 0;
  for (int y = 0; y < f.ids.height; y += 3) {
    for (int x = 0; x < f.ids.width; x += 3) {
      if (f.ids.at(x, y) != 0) continue;  // polygon 0 is the floor cell
      const Vec3 p = *testing::pixel_on_plane(r.view, x, y, Vec3(0, 1, 0), 0.0);
      const Color expected = shade_point(r.request.scene, floor_material, p, Vec3(0, 1, 0), r.view.eye);
      // The ray here is normalised, the reference's is not: the hit points differ by rounding, so
      // the exact colour may sit on the other side of a rounding boundary (1 level).
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(testing::channel(f.image, x, y, c), int(to_byte(expected[c])), 1) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200u);
}

TEST(Reference, ShadowRaysShadowExactlyTheBoxFootprint) {
  // Light straight down: a floor point is shadowed iff it lies under the box (x in [0, 1],
  // z in [-1.5, 0.5]); a point light at (0.5, 5, -0.5), above the box's centre, casts the outline
  // of the box's top (y = 1.5, 3.5 m below it) grown by 5/3.5 about the light's foot.
  struct Case {
    json light;
    double scale;
  };
  for (const Case& c : {Case{{{"type", "directional"}, {"direction", {0, -1, 0}}}, 1.0},
                        Case{{{"type", "point"}, {"position", {0.5, 5.0, -0.5}}}, 5.0 / 3.5}}) {
    SCOPED_TRACE(c.light.dump());
    testing::SceneRender r;
    r.request = request_from_json(shadow_request("reference", c.light, true));
    r.soup = tessellate(r.request.scene.geometry);
    r.result = render_frame(r.request.scene, r.soup, r.request.camera, r.request.options, with_shadow_mask());
    r.view = make_view(r.request.camera, 120, 90);
    const Frame& f = r.result.frame;
    ASSERT_EQ(f.shadow_mask.size(), size_t(120 * 90));
    size_t shadowed = 0, lit = 0;
    for (int y = 0; y < 90; ++y) {
      for (int x = 0; x < 120; ++x) {
        if (f.ids.at(x, y) != 0) continue;
        const Vec3 p = *testing::pixel_on_plane(r.view, x, y, Vec3(0, 1, 0), 0.0);
        const double u = (p.x - 0.5) / c.scale, v = (p.z + 0.5) / c.scale;  // relative to the light's foot
        const double margin = std::min(0.5 - std::abs(u), 1.0 - std::abs(v));
        if (std::abs(margin) < 1e-6) continue;  // on the shadow's edge: either answer is exact enough
        const bool in_shadow = margin > 0.0;
        ASSERT_EQ(f.shadow_mask[size_t(y * 120 + x)], in_shadow ? 0 : 1) << x << "," << y;
        (in_shadow ? shadowed : lit)++;
        if (in_shadow) {
          EXPECT_EQ(testing::channel(f.image, x, y), to_byte(0.2f * 128.0f / 255.0f));  // ambient only
        }
      }
    }
    EXPECT_GT(shadowed, 20u);  // the box hides most of its own shadow from this camera
    EXPECT_GT(lit, 1000u);
  }
}

TEST(Reference, RasterShadowMaskAgreesWithShadowRaysAwayFromShadowEdges) {
  json light = {{"type", "directional"}, {"direction", {0.3, -1, 0.2}}};
  const RenderContext want_mask = with_shadow_mask();
  auto render = [&](const std::string& pipeline, const RenderContext& context) {
    RenderRequest q = request_from_json(shadow_request(pipeline, light, true));
    PolygonSoup soup = tessellate(q.scene.geometry);
    return render_frame(q.scene, soup, q.camera, q.options, context).frame;
  };
  const Frame truth = render("reference", want_mask);
  EXPECT_TRUE(render("zbuffer", {}).shadow_mask.empty());  // not asked for: not computed
  for (const PipelineInfo& pipeline : pipeline_table()) {
    if (!pipeline.shadow_maps) continue;  // the reference itself, and any pipeline without maps
    SCOPED_TRACE(pipeline.name);
    const Frame test = render(pipeline.name, want_mask);
    size_t differing = 0, compared = 0;
    for (int y = 1; y + 1 < 90; ++y) {
      for (int x = 1; x + 1 < 120; ++x) {
        const size_t i = size_t(y * 120 + x);
        // Skip id edges and shadow edges (a pixel whose 4-neighbours' lit state differs in the truth).
        if (is_edge_pixel(truth.ids, x, y) || truth.ids.ids[i] != test.ids.ids[i]) continue;
        const uint8_t m = truth.shadow_mask[i];
        if (truth.shadow_mask[i - 1] != m || truth.shadow_mask[i + 1] != m || truth.shadow_mask[i - 120] != m ||
            truth.shadow_mask[i + 120] != m)
          continue;
        ++compared;
        differing += test.shadow_mask[i] != m;
      }
    }
    EXPECT_GT(compared, 5000u);
    EXPECT_EQ(differing, 0u);
  }
}

TEST(Reference, LightMaskHoldsSeventeenLights) {
  // Seventeen directional lights around the box, each casting its shadow another way: the mask has
  // three bytes a pixel, and light l's bit (bit l % 8 of byte l / 8) is, in the reference, exactly
  // the one bit of the mask of a frame lit by light l alone; the shadow-map pipelines agree with it
  // away from id and shadow edges, for every light.
  constexpr size_t lights = 17;
  auto light_at = [](size_t l) {
    const double a = 2.0 * 3.14159265358979 * double(l) / double(lights);
    return json{
        {"type", "directional"}, {"direction", {0.6 * std::cos(a), -1.0, 0.6 * std::sin(a)}}, {"intensity", 0.05}};
  };
  json all = shadow_request("reference", light_at(0), true);
  for (size_t l = 1; l < lights; ++l) all["scene"]["lights"].push_back(light_at(l));
  auto render = [](const json& request) {
    RenderRequest q = request_from_json(request);
    PolygonSoup soup = tessellate(q.scene.geometry);
    return render_frame(q.scene, soup, q.camera, q.options, with_shadow_mask()).frame;
  };
  const Frame truth = render(all);
  ASSERT_EQ(truth.shadow_mask_bytes, 3u);
  ASSERT_EQ(truth.shadow_mask.size(), size_t(120 * 90 * 3));
  auto bit = [](const Frame& f, size_t pixel, size_t l) {
    return (f.shadow_mask[pixel * f.shadow_mask_bytes + l / 8] >> (l % 8)) & 1u;
  };
  size_t casting = 0;  // lights whose shadow on the floor shows (the box hides some of them)
  for (size_t l = 0; l < lights; ++l) {
    SCOPED_TRACE("light " + std::to_string(l));
    const Frame alone = render(shadow_request("reference", light_at(l), true));
    ASSERT_EQ(alone.shadow_mask_bytes, 1u);
    size_t shadowed = 0;
    for (size_t i = 0; i < size_t(120 * 90); ++i) {
      ASSERT_EQ(bit(truth, i, l), alone.shadow_mask[i] & 1u) << "pixel " << i;
      shadowed += truth.ids.ids[i] == 0 && bit(truth, i, l) == 0;  // floor pixels in this light's shadow
    }
    casting += shadowed > 50;
    if (l == lights - 1) {
      EXPECT_GT(shadowed, 50u);  // the last light, alone in the third byte
    }
  }
  EXPECT_GE(casting, 12u);
  for (size_t i = 0; i < size_t(120 * 90); ++i) EXPECT_EQ(truth.shadow_mask[i * 3 + 2] & 0xFEu, 0) << "pixel " << i;
  for (const PipelineInfo& pipeline : pipeline_table()) {
    if (!pipeline.shadow_maps) continue;
    SCOPED_TRACE(pipeline.name);
    all["options"]["pipeline"] = pipeline.name;
    const Frame test = render(all);
    ASSERT_EQ(test.shadow_mask_bytes, 3u);
    size_t compared = 0, differing = 0;
    for (int y = 1; y + 1 < 90; ++y) {
      for (int x = 1; x + 1 < 120; ++x) {
        const size_t i = size_t(y * 120 + x);
        if (is_edge_pixel(truth.ids, x, y) || truth.ids.ids[i] != test.ids.ids[i]) continue;
        for (size_t l = 0; l < lights; ++l) {
          const unsigned m = bit(truth, i, l);
          if (bit(truth, i - 1, l) != m || bit(truth, i + 1, l) != m || bit(truth, i - 120, l) != m ||
              bit(truth, i + 120, l) != m)
            continue;  // a shadow edge of this light
          ++compared;
          differing += bit(test, i, l) != m;
        }
      }
    }
    EXPECT_GT(compared, 5000u * lights);
    EXPECT_EQ(differing, 0u);
  }
}

TEST(Reference, TranslucentPaneCompositesOverTheOpaqueHitAndTakesTheId) {
  // A half-transparent red pane (window, opacity 0.5) in front of a wall: the pixel is
  // to_byte(0.5 * pane + 0.5 * wall/255) over the wall's own to_byte colour, as the z-buffer blends.
  json request = json::parse(testing::read_file(testing::examples_dir() / "studio.json"));
  request["scene"]["lights"] = json::array();
  request["options"] = {{"width", 80}, {"height", 60}};
  auto z = testing::render_json(request);
  request["options"]["pipeline"] = "reference";
  auto r = testing::render_json(request);
  size_t translucent_pixels = 0;
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 80; ++x) {
      const uint32_t id = r.result.frame.ids.at(x, y);
      if (id == background_id || !(r.soup.polygons[id].flags & polygon_translucent) ||
          is_edge_pixel(r.result.frame.ids, x, y))
        continue;
      ++translucent_pixels;
      EXPECT_EQ(z.result.frame.ids.at(x, y), id) << x << "," << y;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(testing::channel(r.result.frame.image, x, y, c), testing::channel(z.result.frame.image, x, y, c),
                    1);
    }
  }
  if (translucent_pixels == 0) GTEST_SKIP() << "studio.json shows no translucent pane at this camera";
}

}  // namespace
}  // namespace rr

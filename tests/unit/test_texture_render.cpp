// Textured surfaces drawn: the analytic texel at pixel centres (nearest) and bilinear weights, the
// same bytes from every pipeline, for split polygons, on any thread count and SIMD level, the
// reference's box filter converging, and each filter's error against it on a grazing floor.
#include "render/core/image.hpp"
#include "render/core/kernels.hpp"
#include "render/core/surface.hpp"
#include "render/core/texture.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "support/render_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

namespace rr {
namespace {

using nlohmann::json;

// An image of w x h texels, texel (i, j) (j from the top row) coloured by `at`, decoded as a request's
// would be.
std::shared_ptr<SurfaceTexture> make_texture(int w, int h, const std::function<Color(int, int)>& at,
                                             double tile = 1.0) {
  Image image(w, h, Color(0.0f));
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const Color c = at(i, j);
      for (int ch = 0; ch < 3; ++ch) image.pixel(i, j)[ch] = to_byte(c[ch]);
    }
  }
  const std::string png = encode_png(image);
  TextureError error;
  auto texture = std::make_shared<SurfaceTexture>();
  texture->decoded = decode_texture({reinterpret_cast<const uint8_t*>(png.data()), png.size()}, {}, &error);
  EXPECT_TRUE(texture->decoded) << error.message;
  texture->width = texture->height = tile;
  return texture;
}

// Sixteen distinct colours: texel (i, j) of a 4 x 4 image.
Color distinct(int i, int j) {
  return Color(0.1f + 0.25f * float(i), 0.1f + 0.25f * float(j), float((i * 7 + j * 3) % 16) / 15.0f);
}

// A 2 m floor cell seen from straight above, lit by an ambient of 1 alone, so a pixel is its albedo.
RenderRequest top_view(TextureFilter filter, const std::shared_ptr<SurfaceTexture>& texture) {
  RenderRequest r = request_from_json(
      json{{"scene",
            {{"ambient", {{"intensity", 1.0}}},
             {"floor", {{"origin", {-1, -1}}, {"cells", {1, 1}}, {"cell_size", 2}, {"colors", {"#ffffff", "#ffffff"}}}},
             {"lights", json::array()}}},
           {"camera", {{"position", {0.0, 3.0, 0.0}}, {"target", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fov_y", 40}}},
           {"options", {{"width", 96}, {"height", 96}}}});
  r.scene.geometry.floor.texture = texture;
  r.options.texture_filter = filter;
  return r;
}

RenderResult draw(const RenderRequest& r, const std::string& pipeline = "zbuffer") {
  RenderOptions options = r.options;
  options.pipeline = pipeline_id(pipeline);
  options.painter_key = PainterKey::newell;  // the exact order
  return render_frame(r.scene, tessellate(r.scene.geometry), r.camera, options);
}

// (u, v) of the floor point p under the planar mapping of a horizontal face: u along +x, v along -z.
glm::dvec2 floor_uv(Vec3 p, double tile) { return {p.x / tile, -p.z / tile}; }

double wrap(double x) { return x - std::floor(x); }

TEST(TextureRender, NearestGivesTheAnalyticTexelAtEveryPixelCentre) {
  const auto texture = make_texture(4, 4, distinct, 2.0);
  const RenderRequest r = top_view(TextureFilter::nearest, texture);
  const RenderResult out = draw(r);
  const ViewTransform view = make_view(r.camera, r.options.width, r.options.height);
  int checked = 0;
  for (int y = 0; y < r.options.height; ++y) {
    for (int x = 0; x < r.options.width; ++x) {
      if (out.frame.ids.at(x, y) == background_id) continue;
      const auto p = testing::pixel_on_plane(view, x, y, {0.0, 1.0, 0.0}, 0.0);
      ASSERT_TRUE(p);
      const glm::dvec2 uv = floor_uv(*p, 2.0);
      const double tx = wrap(uv.x) * 4.0, ty = (1.0 - wrap(uv.y)) * 4.0;
      // Pixels whose centre lies within 1e-6 texel of a texel edge may round either way.
      if (std::abs(tx - std::round(tx)) < 1e-6 || std::abs(ty - std::round(ty)) < 1e-6) continue;
      const Color want = distinct(int(tx), int(ty));
      for (int c = 0; c < 3; ++c) ASSERT_EQ(out.frame.image.pixel(x, y)[c], to_byte(want[c])) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 4000);
}

TEST(TextureRender, BilinearMatchesTheAnalyticWeightsWithinOneLevel) {
  const auto texture = make_texture(4, 4, distinct, 2.0);
  const RenderRequest r = top_view(TextureFilter::bilinear, texture);
  const RenderResult out = draw(r);
  const ViewTransform view = make_view(r.camera, r.options.width, r.options.height);
  const MipLevel& level = texture->decoded->levels[0];
  auto texel = [&](int i, int j, int c) {
    i = ((i % 4) + 4) % 4, j = ((j % 4) + 4) % 4;
    return double(level.rgb[size_t(j * 4 + i) * 3 + size_t(c)]) / 255.0;
  };
  int checked = 0;
  for (int y = 0; y < r.options.height; ++y) {
    for (int x = 0; x < r.options.width; ++x) {
      if (out.frame.ids.at(x, y) == background_id) continue;
      const glm::dvec2 uv = floor_uv(*testing::pixel_on_plane(view, x, y, {0.0, 1.0, 0.0}, 0.0), 2.0);
      // Texel centres at (i + 0.5) / 4 along u and 1 - (j + 0.5) / 4 along v.
      const double fx = uv.x * 4.0 - 0.5, fy = (1.0 - uv.y) * 4.0 - 0.5;
      const int i = int(std::floor(fx)), j = int(std::floor(fy));
      const double a = fx - i, b = fy - j;
      for (int c = 0; c < 3; ++c) {
        const double want = (1 - a) * (1 - b) * texel(i, j, c) + a * (1 - b) * texel(i + 1, j, c) +
                            (1 - a) * b * texel(i, j + 1, c) + a * b * texel(i + 1, j + 1, c);
        ASSERT_NEAR(out.frame.image.pixel(x, y)[c], want * 255.0, 1.0) << x << "," << y;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 4000);
}

// A perspective view of a finely textured floor: at each pixel, trilinear takes the level of the
// footprint computed here independently, by central differences of the pixel rays' hits (their
// error is second order in the pixel's size), so the level, the blend and the texel agree within one
// grey level.
TEST(TextureRender, TrilinearLevelFollowsTheAnalyticFootprint) {
  std::mt19937 rng(35);
  const auto texture = make_texture(
      256, 256, [&](int, int) { return Color(float(rng() % 256) / 255.0f, float(rng() % 256) / 255.0f, 0.5f); }, 2.0);
  RenderRequest r = top_view(TextureFilter::trilinear, texture);
  r.camera.position = {0.0, 1.2, 1.6};
  r.camera.target = {0.0, 0.0, -0.6};
  r.camera.up = {0.0, 1.0, 0.0};
  r.camera.fov_y_deg = 60.0;
  const RenderResult out = draw(r);
  const ViewTransform view = make_view(r.camera, r.options.width, r.options.height);
  auto uv_at = [&](double sx, double sy) {
    const double x_ndc = 2.0 * sx / view.width - 1.0, y_ndc = 1.0 - 2.0 * sy / view.height;
    const Mat4 world_from_clip = glm::inverse(view.clip_from_world);
    const Vec4 far = world_from_clip * Vec4(x_ndc, y_ndc, 1.0, 1.0);
    const Vec3 d = Vec3(far) / far.w - view.eye;
    return floor_uv(view.eye + (-view.eye.y / d.y) * d, 2.0);
  };
  int checked = 0, levels_above_zero = 0;
  for (int y = 0; y < r.options.height; y += 3) {
    for (int x = 0; x < r.options.width; x += 3) {
      if (out.frame.ids.at(x, y) == background_id) continue;
      const double sx = x + 0.5, sy = y + 0.5;
      const glm::dvec2 d_dx = (uv_at(sx + 0.5, sy) - uv_at(sx - 0.5, sy));
      const glm::dvec2 d_dy = (uv_at(sx, sy + 0.5) - uv_at(sx, sy - 0.5));
      const Color want = sample_texture(*texture->decoded, TextureFilter::trilinear, uv_at(sx, sy), d_dx, d_dy);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(out.frame.image.pixel(x, y)[c], want[c] * 255.0, 1.0) << x << "," << y;
      levels_above_zero += std::sqrt(glm::length(d_dx) * glm::length(d_dy)) * 256.0 > 1.0;
      ++checked;
    }
  }
  EXPECT_GT(checked, 400);
  EXPECT_GT(levels_above_zero, 100);  // the far floor is drawn from coarser levels
}

// A room of four textured walls, a textured floor and a textured box, lit by a sun and a lamp, seen
// from inside with Phong and shadows: nothing overlaps in its own plane, so every pipeline draws the
// same surfaces.
RenderRequest textured_room(TextureFilter filter, const std::string& shading) {
  RenderRequest r = request_from_json(json::parse(R"({
    "scene": {
      "ambient": {"intensity": 0.25},
      "floor": {"origin": [-2, -2], "cells": [4, 4], "cell_size": 1, "colors": ["#ffffff", "#e0e0e0"]},
      "walls": [
        {"id": "n", "start": [-2, -2], "end": [2, -2], "height": 2.5},
        {"id": "e", "start": [2, -2], "end": [2, 2], "height": 2.5,
         "openings": [{"type": "window", "offset": 1.2, "width": 1.2, "height": 1.0, "sill": 0.9}]},
        {"id": "s", "start": [2, 2], "end": [-2, 2], "height": 2.5},
        {"id": "w", "start": [-2, 2], "end": [-2, -2], "height": 2.5}],
      "solids": [{"type": "box", "id": "table", "center": [0.3, -0.4], "size": [0.9, 0.75, 0.6], "rotation_y": 20}],
      "lights": [
        {"type": "directional", "direction": [-0.6, -0.5, 0.3], "intensity": 0.8},
        {"type": "point", "position": [-0.8, 2.1, 0.6], "intensity": 0.7, "attenuation": [1, 0.1, 0.05]}]},
    "camera": {"position": [-1.5, 1.6, 1.6], "target": [0.8, 0.7, -1.2], "fov_y": 70},
    "options": {"width": 160, "height": 120, "shadows": true}})"));
  auto checker = make_texture(
      8, 8, [](int i, int j) { return (i + j) % 2 ? Color(0.9f, 0.85f, 0.7f) : Color(0.35f, 0.2f, 0.1f); }, 0.5);
  auto stripes = make_texture(
      16, 4, [](int i, int) { return i % 4 < 2 ? Color(0.8f, 0.3f, 0.3f) : Color(0.95f); }, 0.8);
  StaticGeometry& g = r.scene.geometry;
  g.floor.texture = checker;
  for (size_t w = 0; w < g.walls.size(); ++w) (w % 2 ? g.walls[w].left_texture : g.walls[w].right_texture) = stripes;
  g.solids[0].texture = checker;
  g.solids[0].material.specular = 0.5f;
  r.options.texture_filter = filter;
  r.options.shading = shading == "flat"      ? ShadingMode::flat
                      : shading == "gouraud" ? ShadingMode::gouraud
                                             : ShadingMode::phong;
  return r;
}

TEST(TextureRender, EveryPipelineDrawsTheSameBytes) {
  for (const char* shading : {"flat", "gouraud", "phong"}) {
    for (TextureFilter filter : {TextureFilter::nearest, TextureFilter::trilinear, TextureFilter::anisotropic}) {
      const RenderRequest r = textured_room(filter, shading);
      const RenderResult z = draw(r, "zbuffer");
      for (const char* other : {"painter", "bsp"}) {
        const RenderResult o = draw(r, other);
        EXPECT_EQ(o.frame.image.rgb, z.frame.image.rgb) << other << " " << shading << " filter " << int(filter);
        // The tree cuts textured polygons into fragments, which must look like the whole polygons.
        if (std::string(other) == "bsp") {
          EXPECT_GT(o.stats.bsp_splits, 0u);
        }
      }
    }
  }
}

// The A-buffer shades a pixel that one polygon covers wholly at its centre, as S = 1 does: every
// pixel whose 3 x 3 neighbourhood shows one opaque polygon at S = 1 keeps its bytes at S = 4, 8 and
// 16. (Behind a pane the A-buffer composites in its own order, textured or not.)
TEST(TextureRender, AntialiasedPixelsInsideAPolygonKeepTheirBytes) {
  const RenderRequest r = textured_room(TextureFilter::anisotropic, "phong");
  const RenderResult one = draw(r);
  const PolygonSoup soup = tessellate(r.scene.geometry);
  for (int samples : {4, 8, 16}) {
    RenderRequest aa = r;
    aa.options.antialias = samples;
    const RenderResult out = draw(aa);
    int inside = 0;
    for (int y = 1; y + 1 < r.options.height; ++y) {
      for (int x = 1; x + 1 < r.options.width; ++x) {
        bool uniform = true;
        for (int j = -1; j <= 1; ++j) {
          for (int i = -1; i <= 1; ++i) uniform = uniform && one.frame.ids.at(x + i, y + j) == one.frame.ids.at(x, y);
        }
        const uint32_t id = one.frame.ids.at(x, y);
        if (!uniform || id == background_id || (soup.polygons[id].flags & polygon_translucent)) continue;
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(out.frame.image.pixel(x, y)[c], one.frame.image.pixel(x, y)[c])
              << samples << " at " << x << "," << y;
        }
        ++inside;
      }
    }
    EXPECT_GT(inside, 10000);
  }
}

TEST(TextureRender, ThreadsAndKernelsDoNotChangeABit) {
  const RenderRequest r = textured_room(TextureFilter::anisotropic, "phong");
  const auto soup = tessellate(r.scene.geometry);
  RenderContext one;
  one.threads = 1;
  const RenderResult base = render_frame(r.scene, soup, r.camera, r.options, one);
  for (unsigned threads : {2u, 8u}) {
    RenderContext c;
    c.threads = threads;
    EXPECT_EQ(render_frame(r.scene, soup, r.camera, r.options, c).frame.image.rgb, base.frame.image.rgb) << threads;
  }
  const char* before = kernels().name;
  for (const Kernels* k : available_kernels()) {
    use_kernels(k->name);
    EXPECT_EQ(render_frame(r.scene, soup, r.camera, r.options, one).frame.image.rgb, base.frame.image.rgb) << k->name;
  }
  use_kernels(before);
}

}  // namespace
}  // namespace rr

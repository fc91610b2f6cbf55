// Exact fixtures for the rasterizer, clipping and camera conventions: coverage is an integer
// property (no tolerance), projection and interpolation are checked to 1e-6 pixel.
#include "render/core/draw.hpp"
#include "render/pipelines/pipeline.hpp"
#include "support/soup_builder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace rr {
namespace {

// Coverage count per pixel of a list of screen-space triangles.
std::vector<int> coverage(int w, int h, const std::vector<std::array<RasterVertex, 3>>& tris) {
  std::vector<int> count(size_t(w * h), 0);
  for (const auto& t : tris) {
    rasterize_triangle(t[0], t[1], t[2], {0, 0, w, h}, [&](const Fragment& f) { ++count[size_t(f.y * w + f.x)]; });
  }
  return count;
}

std::string as_ascii(const std::vector<int>& count, int w) {
  std::string art;
  for (size_t i = 0; i < count.size(); ++i) {
    art += count[i] == 0 ? '.' : char('0' + count[i]);
    if ((i + 1) % size_t(w) == 0) art += '\n';
  }
  return art;
}

RasterVertex v(double x, double y) { return {x, y, 1.0}; }

TEST(Raster, QuadOnPixelCentresFollowsTopLeftRule) {
  // Every edge passes exactly through pixel centres. Left and top edges own their pixels, right
  // and bottom edges do not, and the diagonal is owned by exactly one of the two triangles.
  auto count = coverage(6, 6, {{v(0.5, 0.5), v(4.5, 0.5), v(4.5, 4.5)}, {v(0.5, 0.5), v(4.5, 4.5), v(0.5, 4.5)}});
  EXPECT_EQ(as_ascii(count, 6),
            "1111..\n"
            "1111..\n"
            "1111..\n"
            "1111..\n"
            "......\n"
            "......\n");
}

TEST(Raster, WindingDoesNotChangeCoverage) {
  auto ccw = coverage(8, 8, {{v(0.7, 1.2), v(7.1, 2.5), v(3.3, 7.9)}});
  auto cw = coverage(8, 8, {{v(0.7, 1.2), v(3.3, 7.9), v(7.1, 2.5)}});
  EXPECT_EQ(ccw, cw);
}

TEST(Raster, RandomQuadsSplitEitherWayCoverEveryPixelExactlyOnce) {
  const unsigned seed = 20261122;
  std::mt19937 rng(seed);
  // Vertices on a coarse 1/8-pixel grid so that edges often pass exactly through pixel centres.
  std::uniform_int_distribution<int> coord(0, 16 * 8);
  for (int trial = 0; trial < 300; ++trial) {
    RasterVertex q[4];
    for (auto& p : q) p = v(coord(rng) / 8.0, coord(rng) / 8.0);
    // Keep only convex quads in order (all turns the same way, non-degenerate).
    double cross[4];
    for (int i = 0; i < 4; ++i) {
      const auto &a = q[i], &b = q[(i + 1) % 4], &c = q[(i + 2) % 4];
      cross[i] = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
    }
    bool convex = (cross[0] > 0 && cross[1] > 0 && cross[2] > 0 && cross[3] > 0) ||
                  (cross[0] < 0 && cross[1] < 0 && cross[2] < 0 && cross[3] < 0);
    if (!convex) continue;
    auto split_a = coverage(16, 16, {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}});
    auto split_b = coverage(16, 16, {{q[0], q[1], q[3]}, {q[1], q[2], q[3]}});
    ASSERT_EQ(split_a, split_b) << "seed " << seed << " trial " << trial;
    for (int c : split_a) ASSERT_LE(c, 1) << "double coverage; seed " << seed << " trial " << trial;
  }
}

TEST(Raster, FanAroundCentreHasNoGapsOrOverlaps) {
  // A 24-gon drawn as 24 triangles around its centre: every pixel whose centre is inside the
  // polygon is drawn once, and none twice.
  std::vector<std::array<RasterVertex, 3>> tris;
  const double cx = 16.0, cy = 16.0, r = 13.0;
  for (int k = 0; k < 24; ++k) {
    double a0 = 2 * pi * k / 24, a1 = 2 * pi * (k + 1) / 24;
    tris.push_back(
        {v(cx, cy), v(cx + r * std::cos(a0), cy + r * std::sin(a0)), v(cx + r * std::cos(a1), cy + r * std::sin(a1))});
  }
  auto count = coverage(32, 32, tris);
  int covered = 0;
  for (int c : count) {
    EXPECT_LE(c, 1);
    covered += c;
  }
  // The polygon's area is 24/2 r^2 sin(2 pi / 24) = 524.3 px^2; the pixel count is close to it.
  EXPECT_NEAR(covered, 524.3, 20.0);
  EXPECT_EQ(count[16 * 32 + 16], 1);
}

TEST(Raster, SubPixelTriangleBetweenCentresCoversNothing) {
  auto count = coverage(4, 4, {{v(1.6, 1.6), v(2.4, 1.6), v(2.0, 2.4)}});
  for (int c : count) EXPECT_EQ(c, 0);
}

TEST(Camera, ProjectsKnownPointsToKnownPixels) {
  Camera cam;
  cam.position = {0, 0, 0};
  cam.target = {0, 0, -1};
  cam.fov_y_deg = 90.0;                          // tan(45 deg) = 1: y_ndc = y / -z
  ViewTransform view = make_view(cam, 100, 50);  // aspect 2: x_ndc = x / (2 * -z)
  auto expect_px = [&](Vec3 p, double sx, double sy) {
    Vec2 s = project_to_screen(view, p);
    EXPECT_NEAR(s.x, sx, 1e-9) << p.x << "," << p.y << "," << p.z;
    EXPECT_NEAR(s.y, sy, 1e-9) << p.x << "," << p.y << "," << p.z;
  };
  expect_px({0, 0, -1}, 50.0, 25.0);    // straight ahead: the image centre
  expect_px({1, 0, -1}, 75.0, 25.0);    // right: x grows
  expect_px({0, 0.5, -1}, 50.0, 12.5);  // up: y shrinks (pixel rows count down)
  expect_px({-4, -2, -4}, 25.0, 37.5);

  cam.target = {1, 0, 0};  // looking along +X with +Y up: +Z is to the right
  view = make_view(cam, 100, 50);
  expect_px({1, 0, 0.5}, 62.5, 25.0);
}

TEST(Clip, PolygonCrossingBehindTheEyeStaysInFrontOfTheNearPlane) {
  Camera cam;
  cam.position = {0, 1, 0};
  cam.target = {0, 1, -1};
  ViewTransform view = make_view(cam, 64, 64);
  std::vector<ClipVertex> in, out, tmp;
  for (Vec3 p : {Vec3(-5, 0, 5), Vec3(5, 0, 5), Vec3(5, 0, -5), Vec3(-5, 0, -5)}) {
    in.push_back({view.clip_from_world * Vec4(p, 1.0), p, glm::vec3(0, 1, 0)});
  }
  ASSERT_TRUE(clip_polygon(in, out, tmp));
  for (const ClipVertex& c : out) {
    EXPECT_GE(c.p_clip.z + c.p_clip.w, -1e-12);
    EXPECT_GT(c.p_clip.w, 0.0);
    EXPECT_NEAR(c.p_world.y, 0.0, 1e-12);  // attributes interpolate along the original plane
    Vec4 again = view.clip_from_world * Vec4(c.p_world, 1.0);
    EXPECT_NEAR(glm::length(again - c.p_clip), 0.0, 1e-9);
  }
  // Entirely behind the eye: nothing is left.
  in.clear();
  for (Vec3 p : {Vec3(-5, 0, 5), Vec3(5, 0, 5), Vec3(0, 2, 3)}) {
    in.push_back({view.clip_from_world * Vec4(p, 1.0), p, glm::vec3(0, 1, 0)});
  }
  EXPECT_FALSE(clip_polygon(in, out, tmp));
}

// A hand-built soup of axis-aligned quads (no tessellator involved), one object each.
PolygonSoup make_quads(const std::vector<std::array<Vec3, 4>>& quads) {
  PolygonSoup soup;
  for (const auto& q : quads) testing::add_polygon(soup, {q.begin(), q.end()});
  return soup;
}

TEST(Clip, FloorThroughTheCameraCoversExactlyTheAnalyticPixels) {
  // A 100 m floor whose vertices lie behind the camera. Pixel (x, y) sees the floor when the ray
  // through its centre hits y = 0 inside |x| < 50, 0 < -z < 50 (and before the far plane).
  const int n = 64;
  PolygonSoup soup = make_quads({{Vec3(-50, 0, 50), Vec3(50, 0, 50), Vec3(50, 0, -50), Vec3(-50, 0, -50)}});
  Scene scene;
  Camera cam;
  cam.position = {0, 1, 0};
  cam.target = {0, 1, -1};
  cam.fov_y_deg = 90.0;
  cam.far = 1000.0;
  RenderOptions opt;
  opt.width = opt.height = n;
  RenderResult r = render_frame(scene, soup, cam, opt);
  int mismatches = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      double nx = (x + 0.5) / (n / 2.0) - 1.0, ny = 1.0 - (y + 0.5) / (n / 2.0);
      bool hit = false;
      if (ny < 0) {
        double t = 1.0 / -ny;  // distance along -Z to reach y = 0 from height 1
        hit = std::abs(t * nx) < 50.0 && t < 50.0;
      }
      mismatches += (r.frame.ids.at(x, y) == 0) != hit;
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(ZBuffer, NearerQuadWinsEvenOneMillimetreApartAtTenMetres) {
  // Depth precision claim of zbuffer.cpp: 1/w as float separates 10.000 m from 10.001 m with the
  // default near/far. The nearer quad (id 1) is drawn second and must own every pixel.
  PolygonSoup soup =
      make_quads({{Vec3(-2, -2, -10.001), Vec3(2, -2, -10.001), Vec3(2, 2, -10.001), Vec3(-2, 2, -10.001)},
                  {Vec3(-2, -2, -10.0), Vec3(2, -2, -10.0), Vec3(2, 2, -10.0), Vec3(-2, 2, -10.0)}});
  Scene scene;
  Camera cam;
  cam.position = {0.3, 0.2, 0};
  cam.target = {0.1, 0.0, -10};
  RenderOptions opt;
  opt.width = 160;
  opt.height = 120;
  RenderResult r = render_frame(scene, soup, cam, opt);
  size_t nearer = 0, farther = 0;
  for (uint32_t id : r.frame.ids.ids) {
    nearer += id == 1;
    farther += id == 0;
  }
  EXPECT_GT(nearer, 1000u);
  EXPECT_EQ(farther, 0u);
}

TEST(ZBuffer, PerspectiveCorrectWeightsLandOnTheRayThroughThePixelCentre) {
  // Interpolating world positions with the fragment weights must give a point that projects back
  // onto the pixel centre: the test of perspective-correct interpolation. Weights come from the
  // vertices snapped to the sub-pixel grid (so they agree with coverage), hence the tolerance: a
  // snapped vertex moves at most half a sub-pixel unit per axis, and so does any point interpolated
  // from them (plus the rounding of the world-space round trip).
  PolygonSoup soup = make_quads({{Vec3(-3, 0, 2), Vec3(3, 0, 2), Vec3(3, 0, -30), Vec3(-3, 0, -30)}});
  Camera cam;
  cam.position = {0.5, 1.5, 3};
  cam.target = {0, 0, -5};
  ViewTransform view = make_view(cam, 80, 60);
  DrawScratch scratch;
  ASSERT_TRUE(project_polygon(view, soup, soup.polygons[0], scratch));
  int checked = 0;
  rasterize_convex(scratch.screen, {0, 0, 80, 60}, [&](const Fragment& f, size_t k) {
    const ClipVertex* c[3] = {&scratch.clipped[0], &scratch.clipped[k + 1], &scratch.clipped[k + 2]};
    Vec3 p = c[0]->p_world * f.b[0] + c[1]->p_world * f.b[1] + c[2]->p_world * f.b[2];
    Vec2 s = project_to_screen(view, p);
    const double snap = 0.5 / double(subpixel_one) + 1e-9;
    EXPECT_NEAR(s.x, f.x + 0.5, snap);
    EXPECT_NEAR(s.y, f.y + 0.5, snap);
    ++checked;
  });
  EXPECT_GT(checked, 500);
}

}  // namespace
}  // namespace rr

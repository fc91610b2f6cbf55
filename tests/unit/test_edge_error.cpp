// The edge-error measure and the supersampled reference it is taken against, on ambient-only
// fixtures whose exact image is known: one flat-coloured polygon over the background, where a
// pixel's exact colour is coverage x colour + (1 - coverage) x background, the coverage being the
// polygon's area inside the pixel square (computed here by clipping, independently of any renderer).
#include "render/core/error_metrics.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "support/soup_builder.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace rr {
namespace {

constexpr int side = 32;                                                         // image width = height, pixels
constexpr std::array<int, 3> colour = {200, 100, 40}, background = {0, 20, 40};  // 8-bit
constexpr double depth = 4.0;                                                    // the polygon's plane: z = -depth

// World point on the plane z = -depth that the camera below projects to screen point (px, py):
// eye at the origin looking down -z, 90 degree field of view, square image.
Vec3 at_screen(double px, double py) {
  return {(2.0 * px / side - 1.0) * depth, (1.0 - 2.0 * py / side) * depth, -depth};
}

// Renders one polygon given in screen points (any winding) with the reference at `samples` rays.
Frame render_polygon(std::vector<Vec2> screen, int samples) {
  PolygonSoup soup;
  std::vector<Vec3> points;
  for (const Vec2& p : screen) points.push_back(at_screen(p.x, p.y));
  if (glm::cross(points[1] - points[0], points[2] - points[0]).z < 0.0) std::reverse(points.begin(), points.end());
  testing::add_polygon(soup, points);
  soup.materials[0].color = Color(colour[0], colour[1], colour[2]) / 255.0f;
  Scene scene;
  scene.background = Color(background[0], background[1], background[2]) / 255.0f;
  scene.ambient = {Color(1.0f), 1.0f};
  Camera camera{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90.0, 0.1, 100.0};
  RenderOptions options;
  options.width = options.height = side;
  options.pipeline = pipeline_id("reference");
  options.antialias = samples;
  return render_frame(scene, soup, camera, options).frame;
}

// Area of the convex polygon `poly` inside the unit pixel square at (x, y): Sutherland-Hodgman
// against the four sides, then the shoelace formula.
double coverage(std::vector<Vec2> poly, int x, int y) {
  auto clip = [&](auto inside, auto cross) {
    std::vector<Vec2> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
      if (inside(a)) out.push_back(a);
      if (inside(a) != inside(b)) out.push_back(cross(a, b));
    }
    poly = out;
  };
  for (int axis = 0; axis < 2; ++axis) {
    for (double bound : {double(axis ? y : x), double((axis ? y : x) + 1)}) {
      const bool low = bound == double(axis ? y : x);
      clip([&](Vec2 p) { return low ? p[axis] >= bound : p[axis] <= bound; },
           [&](Vec2 a, Vec2 b) { return a + (b - a) * ((bound - a[axis]) / (b[axis] - a[axis])); });
    }
  }
  double twice = 0.0;
  for (size_t i = 0; i < poly.size(); ++i)
    twice += poly[i].x * poly[(i + 1) % poly.size()].y - poly[(i + 1) % poly.size()].x * poly[i].y;
  return std::abs(twice) / 2.0;
}

double exact_channel(double area, int ch) { return area * colour[ch] + (1.0 - area) * background[ch]; }

Image exact_image(const std::vector<Vec2>& poly) {
  Image out(side, side, Color(0.0f));
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) {
      const double area = coverage(poly, x, y);
      for (int ch = 0; ch < 3; ++ch)
        out.rgb[size_t(y * side + x) * 3 + size_t(ch)] = uint8_t(std::lround(exact_channel(area, ch)));
    }
  }
  return out;
}

TEST(EdgeError, VerticalEdgeAtAQuarterPixelHasTheAnalyticError) {
  // The polygon covers x < 10.25: column 10 is a quarter covered, which every pattern (the 16 x 16
  // grid and Direct3D's 4, 8 and 16) samples exactly (a quarter of each pattern's x lie below 1/4),
  // so each supersampled reference equals the exact image byte for byte.
  const std::vector<Vec2> half = {{-20, -20}, {10.25, -20}, {10.25, 60}, {-20, 60}};
  const Image exact = exact_image(half);
  EXPECT_EQ(exact.rgb[(5 * side + 10) * 3 + 0], 50);  // 0.25 x 200 + 0.75 x 0
  const Frame truth = render_polygon(half, 256);
  for (int samples : {4, 8, 16, 256}) {
    EXPECT_EQ(render_polygon(half, samples).image.rgb, exact.rgb) << samples << " samples";
  }
  // Edge pixels: columns 9 (covered, centre id differs to its right) and 10 (background, centre id
  // differs to its left); column 11 sees background only. The aliased render is exact in column 9
  // and off by a quarter of |colour - background| in column 10: mean (0 + 0.25 x 93.33) / 2.
  const Frame aliased = render_polygon(half, 1);
  const EdgeError e = edge_error(truth.ids, truth.image, aliased.image);
  EXPECT_EQ(e.pixels, size_t(side * side));
  EXPECT_EQ(e.edge_pixels, size_t(2 * side));
  const double quarter = 0.25 * (200.0 + 80.0 + 0.0) / 3.0;
  EXPECT_NEAR(e.mean, quarter / 2.0, 1e-12);
  EXPECT_NEAR(e.p99, quarter, 1e-12);
  EXPECT_NEAR(e.max, quarter, 1e-12);
  EXPECT_EQ(edge_error(truth.ids, truth.image, truth.image).mean, 0.0);
}

TEST(EdgeError, SupersampledReferenceMatchesExactCoverageOfRandomTriangles) {
  // A straight edge through a pixel: the 16 x 16 grid counts, per column of samples, the samples
  // below the edge at the column's centre, off by at most half a sample (1/32 of the column), and a
  // column's exact area is its width times that height: |count / 256 - area| <= 1/32 per edge
  // (per row for steep edges). So a pixel is within (edges crossing it) / 32 x |colour - background|
  // plus one byte (rounding of the mean and of the exact value) of the exact image.
  const auto seeds = testing::test_seeds(1818, 6);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coord(2.0, side - 2.0);
    std::vector<Vec2> tri = {{coord(rng), coord(rng)}, {coord(rng), coord(rng)}, {coord(rng), coord(rng)}};
    const double twice_area =
        std::abs((tri[1].x - tri[0].x) * (tri[2].y - tri[0].y) - (tri[2].x - tri[0].x) * (tri[1].y - tri[0].y));
    if (twice_area < 40.0) continue;  // slivers: fine, but they say little here
    const Frame truth = render_polygon(tri, 256);
    const Image exact = exact_image(tri);
    for (int y = 0; y < side; ++y) {
      for (int x = 0; x < side; ++x) {
        int corners = 0;  // vertices inside the pixel: each adds an edge crossing it
        for (const Vec2& v : tri) corners += std::floor(v.x) == x && std::floor(v.y) == y;
        const double area = coverage(tri, x, y);
        const double edges = area > 0.0 && area < 1.0 ? 1.0 + corners : 0.0;
        for (int ch = 0; ch < 3; ++ch) {
          const double got = truth.image.rgb[size_t(y * side + x) * 3 + size_t(ch)];
          const double bound = edges * std::abs(colour[ch] - background[ch]) / 32.0 + 1.0;
          ASSERT_LE(std::abs(got - exact_channel(area, ch)), bound)
              << "seed " << seed << " (replay with ROOMRENDER_TEST_SEED=" << seed << "), pixel " << x << "," << y;
        }
      }
    }
    // And the measure of the truth against the exact image stays within the per-pixel bound's mean.
    const EdgeError e = edge_error(truth.ids, exact, truth.image);
    EXPECT_GT(e.edge_pixels, 0u) << "seed " << seed;
    EXPECT_LE(e.mean, 2.0 * 93.34 / 32.0 + 1.0) << "seed " << seed;
  }
}

TEST(EdgeError, AaEdgePixelsAreThoseWithAnotherIdInTheir3x3Block) {
  IdBuffer ids(5, 4);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 5; ++x) ids.ids[size_t(y * 5 + x)] = x >= 3 && y >= 2 ? 7u : 1u;
  }
  // Id 7 fills columns 3-4 of rows 2-3; (2, 1) sees it only diagonally, (4, 3) sees nothing else.
  const char* expected[] = {"00000", "00111", "00111", "00110"};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 5; ++x) EXPECT_EQ(is_aa_edge_pixel(ids, x, y), expected[y][x] == '1') << x << "," << y;
  }
  Image a(5, 4, Color(0.0f)), b(5, 4, Color(0.0f));
  EXPECT_THROW(edge_error(ids, a, Image(4, 4, Color(0.0f))), std::invalid_argument);
  b.rgb[(0 * 5 + 0) * 3] = 90;  // not an edge pixel: not counted
  b.rgb[(1 * 5 + 2) * 3] = 30;  // an edge pixel: error 30 / 3 = 10
  const EdgeError e = edge_error(ids, a, b);
  EXPECT_EQ(e.edge_pixels, 8u);
  EXPECT_NEAR(e.mean, 10.0 / 8.0, 1e-12);
  EXPECT_NEAR(e.p99, 10.0, 1e-12);  // nearest rank: ceil(0.99 x 8) = 8th of 8
}

}  // namespace
}  // namespace rr

// Exact fixtures for the tile A-buffer (render/core/abuffer.hpp): sub-sample coverage of a
// half-plane against its analytic area, shared edges covering each sub-sample once (seeded random
// edges), interpenetrating triangles resolved per sub-sample, and a translucent pane composited
// over an opaque wall. Colours are checked to the byte (to_byte's rounding: 0.5/255).
#include "render/core/abuffer.hpp"
#include "render/core/sample_pattern.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace rr {
namespace {

constexpr int samples_tested[] = {4, 8, 16};
constexpr float byte_tolerance = 0.5f / 255.0f + 1e-6f;

TriangleSetup setup_of(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  const int64_t X[3] = {snap_to_subpixel(a.x), snap_to_subpixel(b.x), snap_to_subpixel(c.x)};
  const int64_t Y[3] = {snap_to_subpixel(a.y), snap_to_subpixel(b.y), snap_to_subpixel(c.y)};
  TriangleSetup s;
  EXPECT_TRUE(setup_triangle(X, Y, s));
  return s;
}

// A constant colour and opacity per item; ids are the items.
class Colours final : public TileShading {
 public:
  std::vector<Color> colours;
  std::vector<float> alphas;
  Color shade(const TileTriangle& t, const Fragment&) override { return colours[t.item]; }
  uint32_t id(uint32_t item) const override { return item; }
  float alpha(uint32_t item) const override { return alphas[item]; }
  bool constant() const override { return true; }
};

// One 64x64 tile resolved over a black background.
struct Tile {
  std::vector<uint8_t> rgb = std::vector<uint8_t>(size_t(abuffer_tile) * abuffer_tile * 3, 0);
  std::vector<uint32_t> ids = std::vector<uint32_t>(size_t(abuffer_tile) * abuffer_tile, background_id);
  float channel(int x, int y, int c) const {
    return float(rgb[(size_t(y) * abuffer_tile + size_t(x)) * 3 + size_t(c)]) / 255.0f;
  }
  uint32_t id(int x, int y) const { return ids[size_t(y) * abuffer_tile + size_t(x)]; }
};

const PixelRect tile_rect{0, 0, abuffer_tile, abuffer_tile};
const double flat[3] = {1.0, 1.0, 1.0};

TEST(ABuffer, HalfPlaneEdgeGivesTheAnalyticCoverageWithinOneOverS) {
  for (int S : samples_tested) {
    for (int j = 1; j < 32; ++j) {
      const double a = double(j) / 32.0 + 1.0 / 512.0;  // off the sample lattice: no ties
      for (bool vertical : {true, false}) {
        SCOPED_TRACE(testing::Message() << "S=" << S << " edge at " << a << (vertical ? " vertical" : " horizontal"));
        // A triangle covering x >= 10 + a (or y >= 10 + a) over the whole tile.
        const glm::dvec2 p0 = vertical ? glm::dvec2{10 + a, -200} : glm::dvec2{-200, 10 + a};
        const glm::dvec2 p1 = vertical ? glm::dvec2{10 + a, 300} : glm::dvec2{300, 10 + a};
        const glm::dvec2 p2 = vertical ? glm::dvec2{400, 50} : glm::dvec2{50, 400};
        TileABuffer buffer;
        buffer.begin(tile_rect, make_sample_set(S));
        ASSERT_TRUE(buffer.add(setup_of(p0, p1, p2), flat, 0, 0));
        buffer.cover_opaque(false, 1);
        Colours colours;
        colours.colours = {Color(1.0f)};
        Tile tile;
        buffer.resolve(colours, Color(0.0f), tile.rgb.data(), tile.ids.data(), abuffer_tile);
        const float coverage = vertical ? tile.channel(10, 30, 0) : tile.channel(30, 10, 0);
        EXPECT_NEAR(coverage, 1.0 - a, 1.0 / S + byte_tolerance);
        // Whole pixels on either side.
        EXPECT_EQ(vertical ? tile.channel(9, 30, 0) : tile.channel(30, 9, 0), 0.0f);
        EXPECT_EQ(vertical ? tile.channel(11, 30, 0) : tile.channel(30, 11, 0), 1.0f);
        // The id is the centre's: covered exactly when the centre (0.5) is right of the edge.
        EXPECT_EQ(vertical ? tile.id(10, 30) : tile.id(30, 10), a < 0.5 ? 0u : background_id);
      }
    }
  }
}

// Per sample of every tile pixel, how many of `triangles` cover it (through sample_spans, so the
// spans are checked not to miss a covered sample).
std::vector<int> sample_counts(const std::vector<TriangleSetup>& triangles, const SampleSet& set) {
  const int n = set.count + 1;
  std::vector<int> count(size_t(abuffer_tile) * abuffer_tile * size_t(n), 0);
  for (const TriangleSetup& s : triangles) {
    SampleEdges se;
    setup_sample_edges(s, flat, set, se);
    sample_spans(s, se, tile_rect, [&](int y, int x, int len, const int64_t e0[3]) {
      int64_t e[3] = {e0[0], e0[1], e0[2]};
      for (int i = 0; i < len; ++i, e[0] += s.step_x[0], e[1] += s.step_x[1], e[2] += s.step_x[2]) {
        const uint32_t m = sample_mask(se, e);
        for (int b = 0; b < n; ++b)
          count[(size_t(y) * abuffer_tile + size_t(x + i)) * size_t(n) + size_t(b)] += int(m >> b & 1u);
      }
    });
  }
  return count;
}

TEST(ABuffer, PolygonsSharingARandomEdgeCoverEachSampleExactlyOnce) {
  const uint32_t seed = 20261202;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> side(-20.0, 84.0);
  for (int trial = 0; trial < 60; ++trial) {
    const int S = samples_tested[trial % 3];
    SCOPED_TRACE(testing::Message() << "seed " << seed << " trial " << trial << " S=" << S);
    // A square far around the tile cut by a random chord from its left side to its right side:
    // the two convex parts, each a fan of two triangles, cover the tile together.
    const double yl = side(rng), yr = side(rng);
    const glm::dvec2 tl{-100, -100}, tr{200, -100}, br{200, 200}, bl{-100, 200};
    const glm::dvec2 l{-100, yl}, r{200, yr};
    std::vector<TriangleSetup> parts;
    parts.push_back(setup_of(tl, tr, r));  // top part: tl, tr, r, l
    parts.push_back(setup_of(tl, r, l));
    parts.push_back(setup_of(l, r, br));  // bottom part: l, r, br, bl
    parts.push_back(setup_of(l, br, bl));
    const std::vector<int> count = sample_counts(parts, make_sample_set(S));
    size_t wrong = 0;
    for (int c : count) wrong += c != 1;
    EXPECT_EQ(wrong, 0u) << "chord from (-100, " << yl << ") to (200, " << yr << ")";
  }
}

TEST(ABuffer, InterpenetratingTrianglesResolvePerSample) {
  // A's 1/w grows along x and equals B's (1) at x = c, inside pixel 20: A is nearer right of c.
  const double c = 20.0 + 0.53;
  auto inv_w_a = [&](double x) { return 1.0 + 0.001 * (x - c); };
  const glm::dvec2 a0{-100, -100}, a1{300, -100}, a2{100, 300};
  const TriangleSetup sa = setup_of(a0, a1, a2);
  const double wa[3] = {inv_w_a(a0.x), inv_w_a(a1.x), inv_w_a(a2.x)};
  const TriangleSetup sb = setup_of({-100, -100}, {300, -100}, {100, 300});
  for (int S : samples_tested) {
    SCOPED_TRACE(testing::Message() << "S=" << S);
    const SampleSet set = make_sample_set(S);
    TileABuffer buffer;
    buffer.begin(tile_rect, set);
    ASSERT_TRUE(buffer.add(sb, flat, 1, 0));  // B first: A takes only the samples where it is nearer
    buffer.cover_opaque(true, 0);
    ASSERT_TRUE(buffer.add(sa, wa, 0, 0));
    buffer.cover_opaque(true, 0);
    Colours colours;
    colours.colours = {Color(1.0f, 0.0f, 0.0f), Color(0.0f, 1.0f, 0.0f)};
    Tile tile;
    buffer.resolve(colours, Color(0.0f), tile.rgb.data(), tile.ids.data(), abuffer_tile);
    int right = 0;  // samples of pixel 20 right of c
    for (int i = 0; i < S; ++i) right += 20.5 + set.dx[i] / double(subpixel_one) > c;
    EXPECT_NEAR(tile.channel(20, 30, 0), float(right) / float(S), byte_tolerance);
    EXPECT_NEAR(tile.channel(20, 30, 1), float(S - right) / float(S), byte_tolerance);
    EXPECT_EQ(tile.channel(19, 30, 1), 1.0f);
    EXPECT_EQ(tile.channel(21, 30, 0), 1.0f);
    EXPECT_EQ(tile.id(20, 30), 1u);  // the centre (20.5) is left of c: B's
    EXPECT_EQ(tile.id(21, 30), 0u);
  }
}

TEST(ABuffer, TranslucentPaneOverAnOpaqueWallCompositesToTheAnalyticColour) {
  const Color wall(0.2f, 0.4f, 0.6f), pane(1.0f, 0.8f, 0.0f);
  const float alpha = 0.25f;
  const Color over = alpha * pane + (1.0f - alpha) * wall;
  const double edge = 30.0 + 0.7;  // the pane covers x >= edge, not pixel 30's centre
  for (int S : samples_tested) {
    for (bool pane_in_front : {true, false}) {
      SCOPED_TRACE(testing::Message() << "S=" << S << (pane_in_front ? " pane in front" : " pane behind"));
      const SampleSet set = make_sample_set(S);
      TileABuffer buffer;
      buffer.begin(tile_rect, set);
      ASSERT_TRUE(buffer.add(setup_of({-100, -100}, {300, -100}, {100, 300}), flat, 0, 0));
      buffer.cover_opaque(true, 0);
      const double z = pane_in_front ? 2.0 : 0.5, pane_w[3] = {z, z, z};
      ASSERT_TRUE(buffer.add(setup_of({edge, -200}, {edge, 300}, {400, 50}), pane_w, 1, 0));
      buffer.cover_translucent(true, 0, 0);
      Colours colours;
      colours.colours = {wall, pane};
      colours.alphas = {1.0f, alpha};
      Tile tile;
      buffer.resolve(colours, Color(0.0f), tile.rgb.data(), tile.ids.data(), abuffer_tile);
      int covered = 0;  // samples of pixel 30 right of the edge
      for (int i = 0; i < S; ++i) covered += 30.5 + set.dx[i] / double(subpixel_one) >= edge;
      const float share = pane_in_front ? float(covered) / float(S) : 0.0f;
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(tile.channel(40, 10, ch), pane_in_front ? over[ch] : wall[ch], byte_tolerance);
        EXPECT_NEAR(tile.channel(20, 10, ch), wall[ch], byte_tolerance);
        EXPECT_NEAR(tile.channel(30, 10, ch), share * over[ch] + (1.0f - share) * wall[ch], byte_tolerance);
      }
      EXPECT_EQ(tile.id(40, 10), pane_in_front ? 1u : 0u);
      EXPECT_EQ(tile.id(30, 10), 0u);  // the centre (30.5) is left of the pane's edge
    }
  }
}

TEST(ABuffer, PastTheLayerCapTheFirstCompositedLayersAreDropped) {
  TileABuffer buffer;
  buffer.begin(tile_rect, make_sample_set(4));
  ASSERT_TRUE(buffer.add(setup_of({-100, -100}, {300, -100}, {100, 300}), flat, 0, 0));
  buffer.cover_opaque(false, 1);
  Colours colours;
  colours.colours = {Color(0.0f)};
  colours.alphas = {1.0f};
  const int panes = max_translucent_layers + 3;
  for (int n = 1; n <= panes; ++n) {
    // Opaque panes in composite order: the last one drawn is all that shows, if it was kept.
    ASSERT_TRUE(buffer.add(setup_of({-100, -100}, {300, -100}, {100, 300}), flat, uint32_t(n), 0));
    buffer.cover_translucent(false, 2, uint32_t(n));
    colours.colours.push_back(Color(float(n) / float(panes)));
    colours.alphas.push_back(1.0f);
  }
  Tile tile;
  buffer.resolve(colours, Color(0.0f), tile.rgb.data(), tile.ids.data(), abuffer_tile);
  EXPECT_EQ(tile.channel(5, 5, 0), 1.0f);
  EXPECT_EQ(tile.id(5, 5), uint32_t(panes));
}

}  // namespace
}  // namespace rr

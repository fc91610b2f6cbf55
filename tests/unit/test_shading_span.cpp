// The span shading path's pieces against the per-pixel code they replace, at every SIMD level of
// kernels.hpp: span_weights against pixel_weights (bit for bit, including edge values too large to
// step in doubles), the write_bytes kernel against to_byte (every float that matters), and
// SpecularTable against std::pow (within its stated bound).
// That a shaded span equals fragment() pixel for pixel is held end to end by
// Visibility.MatchesPerFragmentZBufferingOnEveryExampleAndMode.
#include "render/core/image.hpp"
#include "render/core/kernels.hpp"
#include "render/core/raster.hpp"
#include "render/core/shading.hpp"
#include "render/pipelines/visibility.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace rr {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every covered pixel of a random triangle, row by row: span_weights over the row's span gives each
// pixel the same doubles as pixel_weights. Coordinates up to the guard band's reach for the largest
// image (1.5 max_image_side_for_raster pixels, the bound raster.hpp's int64 edge functions hold to)
// make edge values past 2^52, where the int64 path is taken.
void check_random_triangles(uint32_t seed, double reach, size_t* pixels, size_t* past_2_52) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> near(-8.0, 72.0), far(-reach, reach), inv_w(0.01, 4.0);
  for (int t = 0; t < 200; ++t) {
    int64_t X[3], Y[3];
    double w[3];
    for (int v = 0; v < 3; ++v) {
      // One far vertex in half the triangles, two in a quarter: a long edge far from the tile.
      const bool distant = (v == 2 && t % 2 == 0) || (v == 1 && t % 4 == 0);
      X[v] = snap_to_subpixel(distant ? far(rng) : near(rng));
      Y[v] = snap_to_subpixel(distant ? far(rng) : near(rng));
      w[v] = inv_w(rng);
    }
    TriangleSetup s;
    if (!setup_triangle(X, Y, s)) continue;
    const int px0 = std::max(0, s.px0), px1 = std::min(tile_size - 1, s.px1);
    int64_t e_row[3] = {s.edge(0, px0, 0), s.edge(1, px0, 0), s.edge(2, px0, 0)};
    for (int y = 0; y < tile_size; ++y, e_row[0] += s.step_y[0], e_row[1] += s.step_y[1], e_row[2] += s.step_y[2]) {
      if (y < s.py0 || y > s.py1 || px0 > px1) continue;
      int64_t first, last = px1 - px0;
      row_span(s, e_row, first, last);
      if (last < first) continue;
      SurfaceShader::Span span;
      span_weights(s, w, px0 + int(first), y, int(last - first + 1), span);
      ASSERT_EQ(span.count, size_t(last - first + 1));
      for (int64_t i = 0; i <= last - first; ++i) {
        const int x = px0 + int(first + i);
        const int64_t e[3] = {s.edge(0, x, y), s.edge(1, x, y), s.edge(2, x, y)};
        constexpr int64_t exact = int64_t{1} << 52;
        *past_2_52 += std::abs(e[0]) >= exact || std::abs(e[1]) >= exact || std::abs(e[2]) >= exact;
        Fragment f;
        pixel_weights(s, w, e, f);
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(same_bits(span.b[c][i], f.b[c]))
              << "seed " << seed << " triangle " << t << " pixel " << x << "," << y << " weight " << c << ": "
              << span.b[c][i] << " vs " << f.b[c];
        }
        ++*pixels;
      }
    }
  }
}

// Restores the process's kernel set when a test ends.
struct ForcedKernels {
  const char* before = kernels().name;
  ~ForcedKernels() { use_kernels(before); }
};

TEST(ShadingSpan, WeightsAreThoseOfPixelWeightsBitForBitAtEveryLevel) {
  ForcedKernels restore;
  for (const Kernels* k : available_kernels()) {
    SCOPED_TRACE(k->name);
    ASSERT_TRUE(use_kernels(k->name));
    size_t pixels = 0, past_2_52 = 0;
    for (uint32_t seed = 1; seed <= 20; ++seed) check_random_triangles(seed, 1e3, &pixels, &past_2_52);
    const double reach = 1.5 * double(max_image_side_for_raster);
    for (uint32_t seed = 101; seed <= 120; ++seed) check_random_triangles(seed, reach, &pixels, &past_2_52);
    EXPECT_GT(pixels, 100000u);    // the triangles really covered pixels of the tile
    EXPECT_GT(past_2_52, 10000u);  // and the int64 path was taken
  }
}

TEST(ShadingSpan, WriteBytesIsToByteForEveryFloatThatMattersAtEveryLevel) {
  // Exhaustively around every rounding boundary (k + 0.5) / 255 and around 0 and 1, the extremes,
  // then at random; each channel of spans of every length up to the kernel's.
  std::vector<float> values;
  for (int k = -1; k <= 256; ++k) {
    float v = float((k + 0.5) / 255.0);
    for (int step = 0; step < 64; ++step) v = std::nextafter(v, -1.0f);
    for (int step = 0; step < 128; ++step, v = std::nextafter(v, 2.0f)) values.push_back(v);
  }
  for (float v : {0.0f, -0.0f, 1.0f, 1e30f, -1e30f, std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                  std::numeric_limits<float>::denorm_min()}) {
    values.push_back(v);
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> any(-0.5f, 1.5f);
  for (int i = 0; i < 300000; ++i) values.push_back(any(rng));
  for (const Kernels* k : available_kernels()) {
    SCOPED_TRACE(k->name);
    size_t at = 0, n = 0;
    while (at + 3 * kernel_span <= values.size()) {
      n = n % kernel_span + 1;  // spans of 1, 2, ... kernel_span pixels in turn
      const float* const in[3] = {&values[at], &values[at + n], &values[at + 2 * n]};
      std::vector<uint8_t> rgb(3 * n + 1, 0xAB);  // one byte past the span, which must stay
      k->write_bytes(in, n, rgb.data());
      for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(rgb[3 * i + size_t(c)], to_byte(in[c][i])) << "value " << in[c][i] << " (seed 7)";
        }
      }
      ASSERT_EQ(rgb[3 * n], 0xAB) << "a byte past the span was written";
      at += 3 * n;
    }
  }
}

TEST(ShadingSpan, SpecularTableIsWithinItsBoundOfPow) {
  for (float shininess : {1.0f, 1.5f, 2.0f, 3.0f, 8.0f, 32.0f, 100.0f, 777.0f, 1000.0f, 10000.0f}) {
    const SpecularTable table(shininess);
    double worst = 0.0;
    // Dense in x, and densest near 1 where a high exponent's lobe lives.
    for (int i = 0; i <= 200000; ++i) {
      for (const double x : {i / 200000.0, 1.0 - i / 2e8}) {
        const float xf = float(x);
        const double exact = std::pow(double(xf), double(shininess));
        worst = std::max(worst, std::abs(double(table(xf)) - exact));
      }
    }
    EXPECT_LE(worst, double(specular_table_error)) << "shininess " << shininess;
    std::printf("shininess %g: worst |table - pow| %.3g\n", double(shininess), worst);
    EXPECT_EQ(table(0.0f), 0.0f) << "shininess " << shininess;
    EXPECT_EQ(table(-0.5f), 0.0f) << "shininess " << shininess;
  }
}

}  // namespace
}  // namespace rr

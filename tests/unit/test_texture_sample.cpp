// Texture lookups (render/core/texture.hpp): each filter against hand-computed weights and levels,
// repeat wrapping, finite colours for any input, and the box mean against exact means on a
// checkerboard. Tolerances: colours are floats of byte / 255, so 1e-6 is a float's rounding of a
// value in [0, 1]; wider ones say why where they are used.
#include "render/core/image.hpp"
#include "render/core/texture.hpp"
#include "support/image_bytes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace rr {
namespace texture_sample_tests {
namespace {

using testing::as_bytes;
using testing::decode_ok;
using testing::random_image;
using testing::texture_of;

// Texel (i, j) of a level (j from the top) as a colour, and the (u, v) of its centre.
Color texel_color(const MipLevel& level, int i, int j) {
  const uint8_t* t = level.rgb.data() + (size_t(j) * size_t(level.width) + size_t(i)) * 3;
  return {float(t[0] / 255.0), float(t[1] / 255.0), float(t[2] / 255.0)};
}
glm::dvec2 centre(const MipLevel& level, int i, int j) {
  return {(i + 0.5) / level.width, 1.0 - (j + 0.5) / level.height};
}

// Level k of an image alone, so texel_bilinear reads it as level 0.
TextureImage level_alone(const TextureImage& image, size_t k) {
  TextureImage one;
  one.levels = {image.levels[k]};
  return one;
}

void expect_color_near(Color actual, Color expected, double tolerance, const std::string& where = "") {
  EXPECT_NEAR(actual.r, expected.r, tolerance) << where;
  EXPECT_NEAR(actual.g, expected.g, tolerance) << where;
  EXPECT_NEAR(actual.b, expected.b, tolerance) << where;
}

TEST(TextureSample, NearestIsTheTexelAnywhereInside) {
  auto texture = texture_of(random_image(4, 3, 21));
  ASSERT_TRUE(texture);
  const MipLevel& level = texture->levels[0];
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> inside(0.02, 0.98);  // away from the edges' rounding
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 4; ++i) {
      const Color expected = texel_color(level, i, j);
      EXPECT_EQ(sample_texture(*texture, TextureFilter::nearest, centre(level, i, j), {}, {}), expected);
      for (int k = 0; k < 20; ++k) {
        const glm::dvec2 uv{(i + inside(rng)) / 4.0, 1.0 - (j + inside(rng)) / 3.0};
        EXPECT_EQ(sample_texture(*texture, TextureFilter::nearest, uv, {}, {}), expected) << uv.x << "," << uv.y;
      }
    }
  }
}

TEST(TextureSample, BilinearWeightsByHand) {
  auto texture = texture_of(random_image(4, 3, 31));
  ASSERT_TRUE(texture);
  const MipLevel& level = texture->levels[0];
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 4; ++i)
      expect_color_near(texel_bilinear(*texture, centre(level, i, j)), texel_color(level, i, j), 1e-6);
  }
  auto mix4 = [&](int i0, int i1, int j0, int j1, double fx, double fy) {
    const Color a = texel_color(level, i0, j0), b = texel_color(level, i1, j0);
    const Color c = texel_color(level, i0, j1), d = texel_color(level, i1, j1);
    Color out;
    for (int k = 0; k < 3; ++k)
      out[k] = float((1 - fy) * ((1 - fx) * a[k] + fx * b[k]) + fy * ((1 - fx) * c[k] + fx * d[k]));
    return out;
  };
  // A quarter of a texel right of texel 1's centre, three quarters of one below row 0's centre.
  const glm::dvec2 uv{(1.5 + 0.25) / 4.0, 1.0 - (0.5 + 0.75) / 3.0};
  expect_color_near(texel_bilinear(*texture, uv), mix4(1, 2, 0, 1, 0.25, 0.75), 1e-6);
  expect_color_near(sample_texture(*texture, TextureFilter::bilinear, uv, {}, {}), mix4(1, 2, 0, 1, 0.25, 0.75), 1e-6);
  // Across the wrap: 0.1 texel right of the left edge sits between the last column (0.4) and the
  // first (0.6); 0.2 texel below the top between the bottom row (0.3) and the top one (0.7).
  const glm::dvec2 corner{0.1 / 4.0, 1.0 - 0.2 / 3.0};
  expect_color_near(texel_bilinear(*texture, corner), mix4(3, 0, 2, 0, 0.6, 0.7), 1e-6);
}

TEST(TextureSample, RepeatsForEveryIntegerShift) {
  auto texture = texture_of(random_image(5, 4, 41));
  ASSERT_TRUE(texture);
  const glm::dvec2 points[] = {{0.3, 0.7}, {0.01, 0.99}, {0.95, 0.05}, {0.5, 0.5}};
  const int shifts[] = {-1000, -3, -1, 1, 2, 7, 1000};
  const glm::dvec2 footprint{0.3, 0.1};
  for (const glm::dvec2& uv : points) {
    for (int ku : shifts) {
      for (int kv : shifts) {
        const glm::dvec2 moved{uv.x + ku, uv.y + kv};
        EXPECT_EQ(sample_texture(*texture, TextureFilter::nearest, moved, {}, {}),
                  sample_texture(*texture, TextureFilter::nearest, uv, {}, {}));
        // The shifted coordinate rounds differently (0.3 + 7 - 7 != 0.3): equal to a float's rounding.
        for (TextureFilter f : {TextureFilter::bilinear, TextureFilter::trilinear, TextureFilter::anisotropic}) {
          expect_color_near(sample_texture(*texture, f, moved, footprint, {0.0, 0.05}),
                            sample_texture(*texture, f, uv, footprint, {0.0, 0.05}), 1e-6);
        }
      }
    }
  }
}

TEST(TextureSample, NonFiniteInputsGiveFiniteColours) {
  auto texture = texture_of(random_image(6, 5, 51));
  ASSERT_TRUE(texture);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const double odd[] = {0.0, 0.3, -0.7, inf, -inf, nan, 1e300, -1e300, 1e-310, -1e-20};
  for (double a : odd) {
    for (double b : odd) {
      for (TextureFilter f :
           {TextureFilter::nearest, TextureFilter::bilinear, TextureFilter::trilinear, TextureFilter::anisotropic}) {
        for (const Color c :
             {sample_texture(*texture, f, {a, b}, {0.1, 0.0}, {0.0, 0.1}),
              sample_texture(*texture, f, {0.3, 0.4}, {a, b}, {b, 0.2}),
              sample_texture(*texture, f, {a, 0.4}, {a, b}, {b, a}),
              sample_texture_box(*texture, {a, b}, {a, 0.1}, {0.1, b}, 3), texel_bilinear(*texture, {a, b})}) {
          for (int k = 0; k < 3; ++k) {
            EXPECT_TRUE(c[k] >= 0.0f && c[k] <= 1.0f) << a << " " << b << " " << int(f) << ": " << c[k];
          }
        }
      }
    }
  }
}

TEST(TextureSample, TrilinearPicksLevelOfFootprint) {
  auto texture = texture_of(random_image(16, 16, 61));  // levels 16, 8, 4, 2, 1
  ASSERT_TRUE(texture);
  ASSERT_EQ(texture->levels.size(), 5u);
  const glm::dvec2 uv{0.37, 0.61};
  auto level_k = [&](size_t k) { return texel_bilinear(level_alone(*texture, k), uv); };
  for (int k = 0; k < 5; ++k) {
    const double texels = std::ldexp(1.0, k);
    // A square footprint of 2^k texels a side, or a rectangle of the same area (its sides' geometric
    // mean is 2^k), along the axes or turned: level k.
    EXPECT_EQ(sample_texture(*texture, TextureFilter::trilinear, uv, {texels / 16, 0.0}, {0.0, texels / 16}),
              level_k(size_t(k)));
    EXPECT_EQ(sample_texture(*texture, TextureFilter::trilinear, uv, {0.0, -4 * texels / 16}, {texels / 64, 0.0}),
              level_k(size_t(k)));
    const double c = std::sqrt(0.5) * texels / 16;
    expect_color_near(sample_texture(*texture, TextureFilter::trilinear, uv, {2 * c, 2 * c}, {-c / 2, c / 2}),
                      level_k(size_t(k)), 1e-6);
    if (k < 4) {
      // Half-way in log2 blends the two levels equally.
      const double between = texels * std::sqrt(2.0) / 16;
      const Color blend = 0.5f * level_k(size_t(k)) + 0.5f * level_k(size_t(k) + 1);
      expect_color_near(sample_texture(*texture, TextureFilter::trilinear, uv, {between, 0.0}, {0.0, between}), blend,
                        1e-6);
    }
  }
  // Below a texel: level 0 alone (a footprint without area too); beyond the last level: the 1 x 1 mean.
  EXPECT_EQ(sample_texture(*texture, TextureFilter::trilinear, uv, {0.2 / 16, 0.0}, {0.0, 0.3 / 16}), level_k(0));
  EXPECT_EQ(sample_texture(*texture, TextureFilter::trilinear, uv, {0.0, 0.0}, {0.0, 0.0}), level_k(0));
  EXPECT_EQ(sample_texture(*texture, TextureFilter::trilinear, uv, {100.0, 0.0}, {0.0, 100.0}), level_k(4));
}

TEST(TextureSample, AnisotropicIsotropicIsTrilinear) {
  auto texture = texture_of(random_image(16, 16, 71));
  ASSERT_TRUE(texture);
  std::mt19937 rng(72);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0), length(0.001, 0.5);
  for (int n = 0; n < 200; ++n) {
    const glm::dvec2 uv{coordinate(rng), coordinate(rng)};
    const double a = length(rng), angle = coordinate(rng);
    // Equal lengths: (x, y) and (-y, x) sum the same two squares.
    const glm::dvec2 dx{a * std::cos(angle), a * std::sin(angle)}, dy{-dx.y, dx.x};
    EXPECT_EQ(sample_texture(*texture, TextureFilter::anisotropic, uv, dx, dy),
              sample_texture(*texture, TextureFilter::trilinear, uv, dx, dy));
  }
}

TEST(TextureSample, AnisotropicFourToOneTakesFourTaps) {
  auto texture = texture_of(random_image(16, 16, 81));
  ASSERT_TRUE(texture);
  const glm::dvec2 uv{0.43, 0.29};
  // 8 texels along x, 2 along y: ratio 4, four taps at the level of 8 / 4 = 2 texels (level 1), at
  // uv + (-3/8, -1/8, 1/8, 3/8) of the major axis.
  const glm::dvec2 dx{8.0 / 16, 0.0}, dy{0.0, 2.0 / 16};
  const TextureImage level1 = level_alone(*texture, 1);
  Color expected(0.0f);
  for (double t : {-3.0 / 8, -1.0 / 8, 1.0 / 8, 3.0 / 8}) expected += 0.25f * texel_bilinear(level1, uv + t * dx);
  expect_color_near(sample_texture(*texture, TextureFilter::anisotropic, uv, dx, dy), expected, 1e-6);
  // The same with the axes exchanged, and the major axis along y.
  expect_color_near(sample_texture(*texture, TextureFilter::anisotropic, uv, dy, dx), expected, 1e-6);
  Color along_y(0.0f);
  for (double t : {-3.0 / 8, -1.0 / 8, 1.0 / 8, 3.0 / 8})
    along_y += 0.25f * texel_bilinear(level1, uv + t * glm::dvec2(0.0, 0.5));
  expect_color_near(sample_texture(*texture, TextureFilter::anisotropic, uv, {2.0 / 16, 0.0}, {0.0, 0.5}), along_y,
                    1e-6);
  // Trilinear would have taken level 3 (8 texels) at uv alone.
  EXPECT_NE(sample_texture(*texture, TextureFilter::trilinear, uv, dx, dy), expected);
}

TEST(TextureSample, AnisotropicRoundsTapsUpAndClampsThem) {
  auto texture = texture_of(random_image(16, 16, 82));
  ASSERT_TRUE(texture);
  const glm::dvec2 uv{0.71, 0.12};
  auto level = [&](size_t k, glm::dvec2 at) { return texel_bilinear(level_alone(*texture, k), at); };
  // 5 texels by 2: ratio 2.5 -> 3 taps at lambda = log2(5 / 3), between levels 0 and 1.
  {
    const glm::dvec2 dx{5.0 / 16, 0.0}, dy{0.0, 2.0 / 16};
    const float f = float(std::log2(5.0 / 3.0));
    Color expected(0.0f);
    for (double t : {-1.0 / 3, 0.0, 1.0 / 3}) {
      expected += ((1.0f - f) * level(0, uv + t * dx) + f * level(1, uv + t * dx)) / 3.0f;
    }
    expect_color_near(sample_texture(*texture, TextureFilter::anisotropic, uv, dx, dy), expected, 1e-6);
  }
  // 64 texels by 1: 16 taps, not 64, at lambda = log2(64 / 16) = 2, coarser than the shorter axis's 0.
  {
    const glm::dvec2 dx{4.0, 0.0}, dy{0.0, 1.0 / 16};
    Color expected(0.0f);
    for (int i = 0; i < 16; ++i) expected += level(2, uv + ((i + 0.5) / 16 - 0.5) * dx) / 16.0f;
    expect_color_near(sample_texture(*texture, TextureFilter::anisotropic, uv, dx, dy), expected, 1e-6);
  }
}

// The checkerboard of 8 x 8 texels, white where i + j is odd: (1 - s(i) s(j)) / 2 with s(i) = (-1)^i.
// Its bilinear interpolant is (1 - S(x) S(y)) / 2, S the linear interpolant of s (a triangle wave), x
// and y in texels from the first texel's centre.
std::shared_ptr<const TextureImage> checkerboard() {
  Image board;
  board.width = board.height = 8;
  for (int j = 0; j < 8; ++j) {
    for (int i = 0; i < 8; ++i) {
      for (int c = 0; c < 3; ++c) board.rgb.push_back((i + j) % 2 ? 255 : 0);
    }
  }
  return texture_of(board);
}

// The mean of S over [a, b], exactly: S is linear between integers, where the trapezoid rule is exact.
double triangle_mean(double a, double b) {
  auto s = [](double x) { return 1.0 - 2.0 * std::abs(x - 2.0 * std::round(x / 2.0)); };
  double sum = 0.0;
  for (double p = a; p < b;) {
    const double q = std::min(b, std::floor(p) + 1.0);
    sum += 0.5 * (s(p) + s(q)) * (q - p);
    p = q;
  }
  return sum / (b - a);
}

TEST(TextureSample, BoxMeanOverWholePeriodsIsTheMeanColour) {
  // The parallelogram with edges (3, 1) and (-1, 3) texels covers five cells of the pattern's
  // lattice ((1, 1), (1, -1)), tilted to the texel grid and starting off it. n x n midpoints on it
  // integrate this interpolant exactly for n a power of two: its Fourier modes (k1, k2) / 2 (k odd)
  // alias to zero only if 3 k1 + k2 and 3 k2 - k1 are both multiples of 2n, forcing 5 k2 = 0 mod n.
  auto texture = checkerboard();
  ASSERT_TRUE(texture);
  const glm::dvec2 dx{3.0 / 8, 1.0 / 8}, dy{-1.0 / 8, 3.0 / 8};
  for (const glm::dvec2 uv : {glm::dvec2{0.1234, 0.5678}, glm::dvec2{-3.3, 7.01}}) {
    for (int n : {4, 16, 64}) {
      expect_color_near(sample_texture_box(*texture, uv, dx, dy, n), Color(0.5f), 1e-6, "n = " + std::to_string(n));
    }
  }
  // n = 1 is the one bilinear tap at the centre.
  EXPECT_EQ(sample_texture_box(*texture, {0.1234, 0.5678}, dx, dy, 1), texel_bilinear(*texture, {0.1234, 0.5678}));
}

TEST(TextureSample, BoxMeanConvergesToTheExactMean) {
  // A 1.3 x 0.7 texel rectangle off the pattern's lattice: its exact mean is (1 - mean S(x) mean S(y))
  // / 2. The midpoint rule's error on a piecewise-bilinear integrand shrinks like 1 / n^2 (the
  // kinks): measured 3.8e-3, 3.2e-4 and 1.2e-5 for n = 4, 16, 64, i.e. below 0.09 / n^2; the bound
  // is 0.2 / n^2.
  auto texture = checkerboard();
  ASSERT_TRUE(texture);
  const glm::dvec2 uv{0.1234, 0.5678}, dx{1.3 / 8, 0.0}, dy{0.0, 0.7 / 8};
  const double x = uv.x * 8 - 0.5, y = (1.0 - uv.y) * 8 - 0.5;
  const double exact = 0.5 * (1.0 - triangle_mean(x - 0.65, x + 0.65) * triangle_mean(y - 0.35, y + 0.35));
  double previous = 1.0;
  for (int n : {4, 16, 64}) {
    const double error = std::abs(double(sample_texture_box(*texture, uv, dx, dy, n).r) - exact);
    EXPECT_LE(error, 0.2 / (n * n)) << "n = " << n;
    EXPECT_LT(error, previous) << "n = " << n;
    previous = error;
  }
}

}  // namespace
}  // namespace texture_sample_tests
}  // namespace rr

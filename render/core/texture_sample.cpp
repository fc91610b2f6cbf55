// Filtered lookups of a TextureImage (texture.hpp): (u, v) in tiles and a footprint in (u, v) per
// pixel -> a display colour. Plain scalar double arithmetic in a fixed order, compiled without
// contraction into fused multiply-adds, so a lookup gives the same colour on every thread, run and
// CPU. Any input, NaN and infinities included, gives a finite colour from texels inside the image.
#include "render/core/texture.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace rr {
namespace {

// Channel sums in byte units (0..255 per texel).
struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;
};

Rgb mix(const Rgb& a, const Rgb& b, double t) {
  const double s = 1.0 - t;
  return {s * a.r + t * b.r, s * a.g + t * b.g, s * a.b + t * b.b};
}

Color to_color(const Rgb& c, double scale) {
  return {float(c.r * scale / 255.0), float(c.g * scale / 255.0), float(c.b * scale / 255.0)};
}

// A coordinate wrapped into [0, 1]: 1 only when u lies an ulp below an integer, which every lookup
// below reads as the image's last texel. A non-finite coordinate is taken as 0; a huge one is an
// integer and wraps to 0.
double wrap01(double u) { return std::isfinite(u) ? u - std::floor(u) : 0.0; }

// Position in texel widths across the image from its left (u) or top (v) edge: [0, 1].
double from_left(double u) { return wrap01(u); }
double from_top(double v) { return 1.0 - wrap01(v); }

int nearest_index(double t01, int n) { return std::min(int(t01 * n), n - 1); }

// The two texels around t01 * n (centres at i + 0.5) along one axis, wrapped, and the second's weight.
struct AxisPair {
  int i0, i1;
  double f;
};

AxisPair axis_pair(double t01, int n) {
  const double x = t01 * n - 0.5;  // in [-0.5, n - 0.5]
  const double x0 = std::floor(x);
  const int i = int(x0);
  return {i < 0 ? n - 1 : i, i + 1 >= n ? 0 : i + 1, x - x0};
}

const uint8_t* texel(const MipLevel& level, int i, int j) {
  return level.rgb.data() + (size_t(j) * size_t(level.width) + size_t(i)) * 3;
}

Rgb bilinear(const MipLevel& level, double s01, double t01) {
  const AxisPair x = axis_pair(s01, level.width), y = axis_pair(t01, level.height);
  const uint8_t *a = texel(level, x.i0, y.i0), *b = texel(level, x.i1, y.i0);
  const uint8_t *c = texel(level, x.i0, y.i1), *d = texel(level, x.i1, y.i1);
  const double wx = 1.0 - x.f, wy = 1.0 - y.f;
  auto channel = [&](int k) { return wy * (wx * a[k] + x.f * b[k]) + y.f * (wx * c[k] + x.f * d[k]); };
  return {channel(0), channel(1), channel(2)};
}

Rgb bilinear_uv(const MipLevel& level, glm::dvec2 uv) { return bilinear(level, from_left(uv.x), from_top(uv.y)); }

// Bilinear in the levels floor(lambda) and floor(lambda) + 1, blended by lambda's fraction; lambda is
// clamped to [0, last level] (NaN to 0).
Rgb trilinear(const TextureImage& image, glm::dvec2 uv, double lambda) {
  const double s = from_left(uv.x), t = from_top(uv.y);
  const int last = int(image.levels.size()) - 1;
  if (!(lambda > 0.0)) return bilinear(image.levels.front(), s, t);
  if (lambda >= double(last)) return bilinear(image.levels.back(), s, t);
  const int level = int(lambda);
  const double f = lambda - double(level);
  const Rgb fine = bilinear(image.levels[size_t(level)], s, t);
  if (f == 0.0) return fine;
  return mix(fine, bilinear(image.levels[size_t(level) + 1], s, t), f);
}

// The length of a footprint axis in level-0 texels (u scaled by the width, v by the height).
double texels(const TextureImage& image, glm::dvec2 duv) {
  const double x = duv.x * image.width(), y = duv.y * image.height();
  return std::sqrt(x * x + y * y);
}

Rgb anisotropic(const TextureImage& image, glm::dvec2 uv, glm::dvec2 duv_dx, glm::dvec2 duv_dy) {
  const double rho_x = texels(image, duv_dx), rho_y = texels(image, duv_dy);
  const bool x_major = !(rho_y > rho_x);
  const double rho_max = x_major ? rho_x : rho_y, rho_min = x_major ? rho_y : rho_x;
  const glm::dvec2 major = x_major ? duv_dx : duv_dy;
  // rho_min = 0 gives an infinite ratio and NaN (0 / 0, inf / inf) fails the comparison: 16 taps for
  // a degenerate footprint, one when it has no length at all.
  int taps = 1;
  if (rho_max > 0.0) {
    const double ratio = rho_max / rho_min;
    taps = ratio < 16.0 ? std::max(1, int(std::ceil(ratio))) : 16;
  }
  const double lambda = std::log2(rho_max / taps);
  if (taps == 1) return trilinear(image, uv, lambda);
  Rgb sum;
  for (int i = 0; i < taps; ++i) {
    const double along = (i + 0.5) / taps - 0.5;
    const Rgb c = trilinear(image, {uv.x + along * major.x, uv.y + along * major.y}, lambda);
    sum.r += c.r, sum.g += c.g, sum.b += c.b;
  }
  const double inv = 1.0 / taps;
  return {sum.r * inv, sum.g * inv, sum.b * inv};
}

}  // namespace

Color sample_texture(const TextureImage& image, TextureFilter filter, glm::dvec2 uv, glm::dvec2 duv_dx,
                     glm::dvec2 duv_dy) {
  assert(!image.levels.empty());
  switch (filter) {
    case TextureFilter::nearest: {
      const MipLevel& level = image.levels.front();
      const uint8_t* c =
          texel(level, nearest_index(from_left(uv.x), level.width), nearest_index(from_top(uv.y), level.height));
      return {float(c[0] / 255.0), float(c[1] / 255.0), float(c[2] / 255.0)};
    }
    case TextureFilter::bilinear:
      return to_color(bilinear_uv(image.levels.front(), uv), 1.0);
    case TextureFilter::trilinear: {
      const double rho = std::sqrt(texels(image, duv_dx) * texels(image, duv_dy));  // texture.hpp: the area's side
      return to_color(trilinear(image, uv, std::log2(rho)), 1.0);
    }
    case TextureFilter::anisotropic:
      return to_color(anisotropic(image, uv, duv_dx, duv_dy), 1.0);
  }
  return {0.0f, 0.0f, 0.0f};
}

Color texel_bilinear(const TextureImage& image, glm::dvec2 uv) {
  return to_color(bilinear_uv(image.levels.front(), uv), 1.0);
}

Color sample_texture_box(const TextureImage& image, glm::dvec2 uv, glm::dvec2 duv_dx, glm::dvec2 duv_dy, int n) {
  n = std::max(n, 1);
  const MipLevel& level = image.levels.front();
  Rgb sum;
  for (int j = 0; j < n; ++j) {
    const double t = (j + 0.5) / n - 0.5;
    for (int i = 0; i < n; ++i) {
      const double s = (i + 0.5) / n - 0.5;
      const Rgb c = bilinear_uv(level, {uv.x + s * duv_dx.x + t * duv_dy.x, uv.y + s * duv_dx.y + t * duv_dy.y});
      sum.r += c.r, sum.g += c.g, sum.b += c.b;
    }
  }
  return to_color(sum, 1.0 / (double(n) * double(n)));
}

}  // namespace rr

// SurfaceShader's span API (see shading.hpp): the pixels of one row of one fan triangle of the bound
// polygon, given their perspective-correct weights, shaded together. Flat and Gouraud do per pixel
// the same float operations, in the same order, as fragment(), so they give the same bytes; Phong
// evaluates light_terms' model per pixel in floats like shade_phong, with the specular lobe from a
// SpecularTable instead of std::pow. Each loop runs over structure-of-arrays buffers, light by light;
// the arithmetic ones are kernels.hpp's, built for each SIMD level.
#include "render/core/shading.hpp"

#include "render/core/kernels.hpp"
#include "render/core/shadow_rays.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace rr {

namespace {

constexpr size_t cap = SurfaceShader::span_capacity;

void fill(SurfaceShader::SpanColors& out, size_t count, Color c) {
  for (size_t i = 0; i < count; ++i) out.r[i] = c.r, out.g[i] = c.g, out.b[i] = c.b;
}

}  // namespace

SpecularTable::SpecularTable(float shininess) : shininess_(shininess), values_(intervals + 1) {
  const double s = double(shininess), x_min = std::pow(double(specular_cutoff), 1.0 / s);
  x_min_ = float(x_min);
  scale_ = float(double(intervals) / (1.0 - double(x_min_)));
  for (int i = 0; i <= intervals; ++i) {
    const double x = double(x_min_) + (1.0 - double(x_min_)) * double(i) / double(intervals);
    values_[size_t(i)] = float(std::pow(x, s));
  }
}

void SurfaceShader::write_bytes(const SpanColors& c, size_t count, uint8_t* rgb) {
  const float* const in[3] = {c.r, c.g, c.b};
  kernels().write_bytes(in, count, rgb);
}

size_t SurfaceShader::bind_specular_table(float shininess) {
  for (size_t t = 0; t < specular_tables_.size(); ++t) {
    if (specular_tables_[t].shininess() == shininess) return t;
  }
  specular_tables_.emplace_back(shininess);
  return specular_tables_.size() - 1;
}

namespace {

// Whether every PCF tap of every pixel of a span lies wholly on one side of the receiver: then each
// pixel's shadow_visibility is exactly 1 (all taps lit) or 0 (none), and `decided` says which. The
// span's shadow coordinates lie on the segment between its end pixels' (perspective-correct weights
// move the point along one line in world space, and the map's coordinates are affine in it), so the
// test is filter_taps' block test over the blocks under the whole segment's footprint, with margins
// for the rounding of the interpolated coordinates. False when undecided, near the map's edge (where
// taps clamp and their offsets are not bounded by radius + 1), or when the footprint is large.
bool span_decided(const ShadowMaps& maps, const ShadowLight& light, const ShadowReceiver& receiver, Vec3 a, Vec3 b,
                  float& decided) {
  const ShadowMap& map = maps.maps[size_t(light.map[0])];
  const int side = maps.side, radius = maps.pcf / 2;
  const double texel = std::max(light.texel_u, light.texel_v);
  const double g_max = shadow_max_slope * texel;
  const glm::dvec2 g = glm::clamp(receiver.gradient[0], glm::dvec2(-g_max), glm::dvec2(g_max));
  const double slope = std::max(std::abs(g.x), std::abs(g.y)) / texel;
  const double bias = (maps.bias + maps.slope_bias * slope + receiver.shift) * texel;
  constexpr double margin_texels = 1e-6;
  const double u0 = std::min(a.x, b.x) - margin_texels, u1 = std::max(a.x, b.x) + margin_texels;
  const double v0 = std::min(a.y, b.y) - margin_texels, v1 = std::max(a.y, b.y) + margin_texels;
  const double inner0 = radius + 1, inner1 = side - radius - 2;
  if (!(u0 >= inner0 && u1 <= inner1 && v0 >= inner0 && v1 <= inner1)) return false;  // also NaN
  const int bu0 = (int(u0) - radius) / shadow_block, bu1 = (int(u1) + radius) / shadow_block;
  const int bv0 = (int(v0) - radius) / shadow_block, bv1 = (int(v1) + radius) / shadow_block;
  if ((bu1 - bu0 + 1) * (bv1 - bv0 + 1) > 16) return false;
  float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
  for (int bv = bv0; bv <= bv1; ++bv) {
    for (int bu = bu0; bu <= bu1; ++bu) {
      lo = std::min(lo, map.block_min[size_t(bv * map.blocks_per_row + bu)]);
      hi = std::max(hi, map.block_max[size_t(bv * map.blocks_per_row + bu)]);
    }
  }
  const double spread = (std::abs(g.x) + std::abs(g.y)) * (radius + 1);
  const double n0 = std::min(a.z, b.z), n1 = std::max(a.z, b.z);
  const double margin = 1e-9 * (std::abs(n0) + std::abs(n1) + spread + bias + 1.0);
  if (double(hi) <= n0 + bias - spread - margin) return decided = 1.0f, true;
  if (double(lo) > n1 + bias + spread + margin) return decided = 0.0f, true;
  return false;
}

}  // namespace

// The visibility of shadowed light s at each pixel of the span, as visibility() gives it. Runs of
// up to 8 pixels that span_decided settles take no lookup per pixel (shorter runs than the span's
// have smaller footprints, so more of them are settled).
void SurfaceShader::span_visibility(const Span& span, size_t s, float* vis) const {
  if (rays_) {
    const size_t k = span.k;
    const Vec3 w0 = world_[0], w1 = world_[k + 1], w2 = world_[k + 2];
    for (size_t i = 0; i < span.count; ++i)
      vis[i] = ray_visibility(shadowed_[s], span.b[0][i] * w0 + span.b[1][i] * w1 + span.b[2][i] * w2);
    return;
  }
  const size_t n = shadowed_.size(), k = span.k;
  const Vec3 c0 = coords_[s], c1 = coords_[(k + 1) * n + s], c2 = coords_[(k + 2) * n + s];
  const Shadowed& light = shadowed_[s];
  auto coords = [&](size_t i) { return span.b[0][i] * c0 + span.b[1][i] * c1 + span.b[2][i] * c2; };
  const bool by_runs = light.light->directional && light.light->map[0] >= 0;
  constexpr size_t run = 8;
  for (size_t first = 0; first < span.count; first += run) {
    const size_t last = std::min(first + run, span.count) - 1;
    float decided = 0.0f;
    if (by_runs && last > first &&
        span_decided(*maps_, *light.light, light.receiver, coords(first), coords(last), decided)) {
      std::fill(vis + first, vis + last + 1, decided);
      continue;
    }
    for (size_t i = first; i <= last; ++i) vis[i] = shadow_visibility(*maps_, *light.light, light.receiver, coords(i));
  }
}

void SurfaceShader::span_tint(const Span& span, size_t s, const float* vis, SpanColors& tint) const {
  const size_t k = span.k;
  const Vec3 w0 = world_[0], w1 = world_[k + 1], w2 = world_[k + 2];
  for (size_t i = 0; i < span.count; ++i) {
    const Color t = vis[i] > 0.0f ? shadow_ray_transmittance(*glass_, input_.soup, self_,
                                                             span.b[0][i] * w0 + span.b[1][i] * w1 + span.b[2][i] * w2,
                                                             *shadowed_[s].ray_light)
                                  : Color(1.0f);
    tint.r[i] = t.r, tint.g[i] = t.g, tint.b[i] = t.b;
  }
}

void SurfaceShader::shade_span(const Span& span, SpanColors& out) const {
  if (mask_) [[unlikely]] {
    Fragment f;
    f.y = span.y;
    for (size_t i = 0; i < span.count; ++i) {
      f.x = span.x + int(i);
      for (int c = 0; c < 3; ++c) f.b[c] = span.b[c][i];
      write_mask(f, span.k);
    }
  }
  if (textured_) {  // per pixel: the texture lookup does not vectorize
    Fragment f;
    f.y = span.y;
    for (size_t i = 0; i < span.count; ++i) {
      f.x = span.x + int(i);
      for (int c = 0; c < 3; ++c) f.b[c] = span.b[c][i];
      const Color c = shade_textured(f, span.k);
      out.r[i] = c.r, out.g[i] = c.g, out.b[i] = c.b;
    }
    return;
  }
  if (constant_) return fill(out, span.count, current_);
  switch (mode_) {
    case ShadingMode::flat:
      return span_flat(span, out);
    case ShadingMode::gouraud:
      return span_gouraud(span, out);
    case ShadingMode::phong:
      return span_phong(span, out);
  }
}

// Flat with shadow maps: the unshadowed sum plus each shadowed light's term times its visibility.
void SurfaceShader::span_flat(const Span& span, SpanColors& out) const {
  fill(out, span.count, bound_terms_[0]);
  alignas(16) float vis[cap];
  SpanColors tint;
  for (size_t s = 0; s < shadowed_.size(); ++s) {
    span_visibility(span, s, vis);
    const Color t = bound_terms_[1 + s];
    if (glass_) {
      span_tint(span, s, vis, tint);
      for (size_t i = 0; i < span.count; ++i) {
        out.r[i] += (vis[i] * tint.r[i]) * t.r, out.g[i] += (vis[i] * tint.g[i]) * t.g;
        out.b[i] += (vis[i] * tint.b[i]) * t.b;
      }
      continue;
    }
    for (size_t i = 0; i < span.count; ++i) {
      out.r[i] += vis[i] * t.r, out.g[i] += vis[i] * t.g, out.b[i] += vis[i] * t.b;
    }
  }
}

// Gouraud: the vertex terms of fan triangle (0, k+1, k+2), weighted; a shadowed light's term is
// added where its visibility is above 0, and 0 elsewhere (which can only turn a -0 into +0: the
// same byte).
void SurfaceShader::span_gouraud(const Span& span, SpanColors& out) const {
  const size_t n = shadowed_.size(), width = 1 + n, count = span.count;
  const Kernels& simd = kernels();
  alignas(16) float b0[cap], b1[cap], b2[cap], vis[cap];
  const double* const weights[3] = {span.b[0], span.b[1], span.b[2]};
  float* const b[3] = {b0, b1, b2};
  float* const rgb[3] = {out.r, out.g, out.b};
  SpanColors tint;
  simd.to_float3(weights, count, b);
  const Color* t0 = &bound_terms_[0];
  const Color* t1 = &bound_terms_[(span.k + 1) * width];
  const Color* t2 = &bound_terms_[(span.k + 2) * width];
  const auto terms = [&](size_t layer) {
    const Color a = t0[layer], c1 = t1[layer], c2 = t2[layer];
    return std::array<float, 9>{a.r, a.g, a.b, c1.r, c1.g, c1.b, c2.r, c2.g, c2.b};
  };
  simd.gouraud_span(b, count, terms(0).data(), nullptr, rgb);
  for (size_t s = 0; s < n; ++s) {
    span_visibility(span, s, vis);
    if (glass_) {
      const Color a = t0[1 + s], c1 = t1[1 + s], c2 = t2[1 + s];
      span_tint(span, s, vis, tint);
      for (size_t i = 0; i < count; ++i) {
        const float v = vis[i];
        const float r = (v * tint.r[i]) * (b0[i] * a.r + b1[i] * c1.r + b2[i] * c2.r);
        const float g = (v * tint.g[i]) * (b0[i] * a.g + b1[i] * c1.g + b2[i] * c2.g);
        const float bl = (v * tint.b[i]) * (b0[i] * a.b + b1[i] * c1.b + b2[i] * c2.b);
        out.r[i] += v > 0.0f ? r : 0.0f;
        out.g[i] += v > 0.0f ? g : 0.0f;
        out.b[i] += v > 0.0f ? bl : 0.0f;
      }
      continue;
    }
    simd.gouraud_span(b, count, terms(1 + s).data(), vis, rgb);
  }
}

void SurfaceShader::span_phong(const Span& span, SpanColors& out) const {
  const size_t count = span.count, k = span.k;
  const Kernels& simd = kernels();
  PhongPixels p;
  alignas(16) float b0[cap], b1[cap], b2[cap], vis[cap];
  const double* const weights[3] = {span.b[0], span.b[1], span.b[2]};
  float* const b[3] = {b0, b1, b2};
  SpanColors tint;
  simd.to_float3(weights, count, b);
  const glm::vec3 q0 = eye_to_p_[0], q1 = eye_to_p_[k + 1], q2 = eye_to_p_[k + 2];
  const glm::vec3 n0 = normal_[0], n1 = normal_[k + 1], n2 = normal_[k + 2];
  const float q[9] = {q0.x, q0.y, q0.z, q1.x, q1.y, q1.z, q2.x, q2.y, q2.z};
  const float nrm[9] = {n0.x, n0.y, n0.z, n1.x, n1.y, n1.z, n2.x, n2.y, n2.z};
  simd.phong_pixels(b, count, q, nrm, p);
  fill(out, count, ambient_);
  evaluated_per_pixel_ += count * active_.size();
  for (const ActiveLight& a : active_) {
    const SpanColors* tinted = nullptr;
    if (a.shadow >= 0) {
      span_visibility(span, size_t(a.shadow), vis);
      if (glass_) span_tint(span, size_t(a.shadow), vis, tint), tinted = &tint;
    } else {
      std::fill_n(vis, count, 1.0f);
    }
    span_phong_light(a, p, count, vis, tinted, out);
  }
}

// One light's Blinn-Phong term at every pixel of the span, scaled by its attenuation and visibility
// (and by `tint`, the panes' per pixel, when given); nothing where the light is behind the shading
// normal or fully shadowed.
void SurfaceShader::span_phong_light(const ActiveLight& a, const PhongPixels& p, size_t count, const float* vis,
                                     const SpanColors* tint, SpanColors& out) const {
  const PhongSpanLight light{{a.to_light.x, a.to_light.y, a.to_light.z},
                             {a.position.x, a.position.y, a.position.z},
                             {a.attenuation.x, a.attenuation.y, a.attenuation.z},
                             {a.diffuse.x, a.diffuse.y, a.diffuse.z},
                             {a.specular.x, a.specular.y, a.specular.z},
                             a.point,
                             a.has_specular};
  const SpecularLookup table = a.has_specular ? specular_tables_[table_].lookup() : SpecularLookup{};
  const float* const tints[3] = {tint ? tint->r : nullptr, tint ? tint->g : nullptr, tint ? tint->b : nullptr};
  float* const rgb[3] = {out.r, out.g, out.b};
  kernels().phong_light(light, p, count, vis, tint ? tints : nullptr, table, rgb);
}

}  // namespace rr

// SurfaceShader's span API (see shading.hpp): the pixels of one row of one fan triangle of the bound
// polygon, given their perspective-correct weights, shaded together. Flat and Gouraud do per pixel
// the same float operations, in the same order, as fragment(), so they give the same bytes; Phong
// evaluates light_terms' model per pixel in floats like shade_phong, with the specular lobe from a
// SpecularTable instead of std::pow. Each loop runs over structure-of-arrays buffers, light by light.
#include "render/core/shading.hpp"

#include "render/core/shadow_rays.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace rr {

namespace {

constexpr size_t cap = SurfaceShader::span_capacity;

void fill(SurfaceShader::SpanColors& out, size_t count, Color c) {
  for (size_t i = 0; i < count; ++i) out.r[i] = c.r, out.g[i] = c.g, out.b[i] = c.b;
}

void to_float(const double* in, size_t count, float* out) {
  for (size_t i = 0; i < count; ++i) out[i] = float(in[i]);
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
  // Each pixel's 3 bytes go out as one 4-byte store whose last byte the next pixel's store
  // overwrites; the last pixel writes 3 bytes, so nothing past the span is touched.
  alignas(16) uint32_t packed[cap];
  for (size_t i = 0; i < count; ++i) {
    packed[i] = uint32_t(byte_of(c.r[i])) | uint32_t(byte_of(c.g[i])) << 8 | uint32_t(byte_of(c.b[i])) << 16;
  }
  if (count == 0) return;
  for (size_t i = 0; i + 1 < count; ++i) std::memcpy(rgb + 3 * i, &packed[i], 4);
  const uint32_t last = packed[count - 1];
  uint8_t* px = rgb + 3 * (count - 1);
  px[0] = uint8_t(last), px[1] = uint8_t(last >> 8), px[2] = uint8_t(last >> 16);
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
  alignas(16) float b0[cap], b1[cap], b2[cap], vis[cap];
  SpanColors tint;
  to_float(span.b[0], count, b0), to_float(span.b[1], count, b1), to_float(span.b[2], count, b2);
  const Color* t0 = &bound_terms_[0];
  const Color* t1 = &bound_terms_[(span.k + 1) * width];
  const Color* t2 = &bound_terms_[(span.k + 2) * width];
  for (size_t i = 0; i < count; ++i) {
    out.r[i] = b0[i] * t0[0].r + b1[i] * t1[0].r + b2[i] * t2[0].r;
    out.g[i] = b0[i] * t0[0].g + b1[i] * t1[0].g + b2[i] * t2[0].g;
    out.b[i] = b0[i] * t0[0].b + b1[i] * t1[0].b + b2[i] * t2[0].b;
  }
  for (size_t s = 0; s < n; ++s) {
    span_visibility(span, s, vis);
    const Color a = t0[1 + s], b = t1[1 + s], c = t2[1 + s];
    if (glass_) {
      span_tint(span, s, vis, tint);
      for (size_t i = 0; i < count; ++i) {
        const float v = vis[i];
        const float r = (v * tint.r[i]) * (b0[i] * a.r + b1[i] * b.r + b2[i] * c.r);
        const float g = (v * tint.g[i]) * (b0[i] * a.g + b1[i] * b.g + b2[i] * c.g);
        const float bl = (v * tint.b[i]) * (b0[i] * a.b + b1[i] * b.b + b2[i] * c.b);
        out.r[i] += v > 0.0f ? r : 0.0f;
        out.g[i] += v > 0.0f ? g : 0.0f;
        out.b[i] += v > 0.0f ? bl : 0.0f;
      }
      continue;
    }
    for (size_t i = 0; i < count; ++i) {
      const float v = vis[i];
      const float r = v * (b0[i] * a.r + b1[i] * b.r + b2[i] * c.r);
      const float g = v * (b0[i] * a.g + b1[i] * b.g + b2[i] * c.g);
      const float bl = v * (b0[i] * a.b + b1[i] * b.b + b2[i] * c.b);
      out.r[i] += v > 0.0f ? r : 0.0f;
      out.g[i] += v > 0.0f ? g : 0.0f;
      out.b[i] += v > 0.0f ? bl : 0.0f;
    }
  }
}

// Per pixel of a Phong span: the unit normal, the unit vector to the eye and the position relative
// to the eye.
struct SurfaceShader::PhongPixels {
  alignas(16) float nx[cap], ny[cap], nz[cap];
  alignas(16) float ex[cap], ey[cap], ez[cap];
  alignas(16) float qx[cap], qy[cap], qz[cap];
};

void SurfaceShader::span_phong(const Span& span, SpanColors& out) const {
  const size_t count = span.count, k = span.k;
  PhongPixels p;
  alignas(16) float b0[cap], b1[cap], b2[cap], vis[cap];
  SpanColors tint;
  to_float(span.b[0], count, b0), to_float(span.b[1], count, b1), to_float(span.b[2], count, b2);
  const glm::vec3 q0 = eye_to_p_[0], q1 = eye_to_p_[k + 1], q2 = eye_to_p_[k + 2];
  const glm::vec3 n0 = normal_[0], n1 = normal_[k + 1], n2 = normal_[k + 2];
  for (size_t i = 0; i < count; ++i) {
    const float qx = b0[i] * q0.x + b1[i] * q1.x + b2[i] * q2.x;
    const float qy = b0[i] * q0.y + b1[i] * q1.y + b2[i] * q2.y;
    const float qz = b0[i] * q0.z + b1[i] * q1.z + b2[i] * q2.z;
    float nx = b0[i] * n0.x + b1[i] * n1.x + b2[i] * n2.x;
    float ny = b0[i] * n0.y + b1[i] * n1.y + b2[i] * n2.y;
    float nz = b0[i] * n0.z + b1[i] * n1.z + b2[i] * n2.z;
    // Every quotient is computed, then selected: a division under a condition keeps the loop from
    // vectorizing (it might trap), and 0 / 0 here only makes a NaN that is not selected.
    const float n_len = std::sqrt(nx * nx + ny * ny + nz * nz);
    const bool n_ok = n_len > 0.0f;
    const float ux = nx / n_len, uy = ny / n_len, uz = nz / n_len;
    nx = n_ok ? ux : n0.x, ny = n_ok ? uy : n0.y, nz = n_ok ? uz : n0.z;
    const float q_len = std::sqrt(qx * qx + qy * qy + qz * qz);
    const bool q_ok = q_len > 0.0f;
    const float ex = -qx / q_len, ey = -qy / q_len, ez = -qz / q_len;
    p.ex[i] = q_ok ? ex : nx, p.ey[i] = q_ok ? ey : ny, p.ez[i] = q_ok ? ez : nz;
    p.nx[i] = nx, p.ny[i] = ny, p.nz[i] = nz;
    p.qx[i] = qx, p.qy[i] = qy, p.qz[i] = qz;
  }
  fill(out, count, ambient_);
  evaluated_per_pixel_ += count * active_.size();
  for (const ActiveLight& a : active_) {
    const SpanColors* tinted = nullptr;
    if (a.shadow >= 0) {
      span_visibility(span, size_t(a.shadow), vis);
      if (glass_) span_tint(span, size_t(a.shadow), vis, tint), tinted = &tint;
    } else {
      for (size_t i = 0; i < count; ++i) vis[i] = 1.0f;
    }
    span_phong_light(a, p, count, vis, tinted, out);
  }
}

// One light's Blinn-Phong term at every pixel of the span, scaled by its attenuation and visibility
// (and by `tint`, the panes' per pixel, when given); nothing where the light is behind the shading
// normal or fully shadowed.
void SurfaceShader::span_phong_light(const ActiveLight& a, const PhongPixels& p, size_t count, const float* vis,
                                     const SpanColors* tint, SpanColors& out) const {
  alignas(16) float lx[cap], ly[cap], lz[cap], attenuation[cap];
  if (a.point) {
    for (size_t i = 0; i < count; ++i) {
      const float dx = a.position.x - p.qx[i], dy = a.position.y - p.qy[i], dz = a.position.z - p.qz[i];
      const float dist = std::sqrt(dx * dx + dy * dy + dz * dz);
      lx[i] = dx / dist, ly[i] = dy / dist, lz[i] = dz / dist;  // NaN at dist 0, and weight 0 below
      const float at = 1.0f / (a.attenuation.x + a.attenuation.y * dist + a.attenuation.z * dist * dist);
      attenuation[i] = dist > 0.0f ? at : 0.0f;
    }
  } else {
    std::fill_n(lx, count, a.to_light.x), std::fill_n(ly, count, a.to_light.y), std::fill_n(lz, count, a.to_light.z);
    std::fill_n(attenuation, count, 1.0f);
  }
  alignas(16) float n_dot_l[cap], n_dot_h[cap], weight[cap], spec[cap];
  for (size_t i = 0; i < count; ++i) {
    const float nl = p.nx[i] * lx[i] + p.ny[i] * ly[i] + p.nz[i] * lz[i];
    const float hx = lx[i] + p.ex[i], hy = ly[i] + p.ey[i], hz = lz[i] + p.ez[i];
    const float h_len = std::sqrt(hx * hx + hy * hy + hz * hz);
    const float nh = (p.nx[i] * hx + p.ny[i] * hy + p.nz[i] * hz) / h_len;
    const float w = attenuation[i] * vis[i];
    n_dot_l[i] = nl;
    n_dot_h[i] = h_len > 0.0f ? nh : 0.0f;
    weight[i] = nl > 0.0f ? w : 0.0f;  // also 0 where vis or the attenuation is 0
  }
  if (a.has_specular) {
    const SpecularTable& table = specular_tables_[table_];
    for (size_t i = 0; i < count; ++i) spec[i] = table(n_dot_h[i]);
  }
  if (tint) {
    for (size_t i = 0; i < count; ++i) {
      const float s = a.has_specular ? spec[i] : 0.0f;
      const float w = weight[i];
      const float r = (a.diffuse.r * n_dot_l[i] + a.specular.r * s) * (w * tint->r[i]);
      const float g = (a.diffuse.g * n_dot_l[i] + a.specular.g * s) * (w * tint->g[i]);
      const float b = (a.diffuse.b * n_dot_l[i] + a.specular.b * s) * (w * tint->b[i]);
      out.r[i] += w > 0.0f ? r : 0.0f;
      out.g[i] += w > 0.0f ? g : 0.0f;
      out.b[i] += w > 0.0f ? b : 0.0f;
    }
    return;
  }
  for (size_t i = 0; i < count; ++i) {
    const float s = a.has_specular ? spec[i] : 0.0f;
    const float w = weight[i];
    const float r = (a.diffuse.r * n_dot_l[i] + a.specular.r * s) * w;
    const float g = (a.diffuse.g * n_dot_l[i] + a.specular.g * s) * w;
    const float b = (a.diffuse.b * n_dot_l[i] + a.specular.b * s) * w;
    out.r[i] += w > 0.0f ? r : 0.0f;
    out.g[i] += w > 0.0f ? g : 0.0f;
    out.b[i] += w > 0.0f ? b : 0.0f;
  }
}

}  // namespace rr

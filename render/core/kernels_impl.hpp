// The loops of kernels.hpp, written once as plain loops the compiler vectorizes; included by
// kernels_sse2.cpp, kernels_avx2.cpp and kernels_avx512.cpp, each compiled for its level with
// RR_KERNELS_NS naming its namespace and RR_KERNELS_NAME the set.
#include "render/core/kernels.hpp"

namespace rr::RR_KERNELS_NS {

namespace {

// The loops below use no library templates (std::min and the like): a copy of one that is not
// inlined would be a weak symbol compiled for this level, which the linker may pick for every caller.
// Selections are written as std::min writes them, (b < a) ? b : a, so the values are the same.
// A pointer marked __restrict promises that the array a loop writes through it overlaps none it
// reads, so the loop vectorizes without run-time overlap checks.

void depth_span(double z0, double dz_dx, int n, uint32_t id, float* depth, uint32_t* visible) {
  for (int i = 0; i < n; ++i) {  // branch-free so that it vectorizes
    const float z = float(z0 + double(i) * dz_dx);
    const bool nearer = z > depth[i];
    depth[i] = nearer ? z : depth[i];
    visible[i] = nearer ? id : visible[i];
  }
}

void grouped_depth_span(double z0, double dz_dx, int n, uint32_t id, uint32_t group, const uint32_t* group_of,
                        float* depth, uint32_t* visible) {
  for (int i = 0; i < n; ++i) {
    const float z = float(z0 + double(i) * dz_dx);
    const uint32_t v = visible[i];
    const bool same_plane = v != no_visible && group_of[v] == group;
    const bool nearer = !same_plane && z > depth[i];
    depth[i] = nearer ? z : depth[i];
    visible[i] = nearer ? id : v;
  }
}

void classify_points(const double* x, const double* y, const double* z, size_t stride, size_t rows, size_t n,
                     const double plane[4], double epsilon, uint8_t* __restrict side, size_t by_side[4]) {
  const double nx = plane[0], ny = plane[1], nz = plane[2], offset = plane[3], below = -epsilon;
  // Flags as 64-bit integers, as wide as the doubles they come from, so that the loops vectorize.
  alignas(64) int64_t flags[classify_block];
  for (size_t i = 0; i < n; ++i) flags[i] = 0;
  for (size_t k = 0; k < rows; ++k) {
    const double* __restrict xs = x + k * stride;
    const double* __restrict ys = y + k * stride;
    const double* __restrict zs = z + k * stride;
    for (size_t i = 0; i < n; ++i) {
      const double d = nx * xs[i] + ny * ys[i] + nz * zs[i] - offset;
      flags[i] |= (d > epsilon ? int64_t{1} : int64_t{0}) | (d < below ? int64_t{2} : int64_t{0});
    }
  }
  int64_t front = 0, back = 0, both = 0;
  for (size_t i = 0; i < n; ++i) {
    side[i] = uint8_t(flags[i]);
    front += flags[i] & 1, back += flags[i] >> 1, both += flags[i] == 3 ? 1 : 0;
  }
  by_side[1] += size_t(front - both), by_side[2] += size_t(back - both), by_side[3] += size_t(both);
  by_side[0] += n - size_t(front + back - both);
}

void span_weights(const int64_t first[3], const int64_t step[3], const double w[3], double inv_area, int n,
                  double* const b[3]) {
  constexpr int64_t exact = int64_t{1} << 52;
  for (int k = 0; k < 3; ++k) {
    // Stepped in double while every value is an integer below 2^52 (exact), else converted one by one.
    const int64_t last = first[k] + int64_t(n - 1) * step[k];
    double* __restrict e = b[k];
    if (first[k] > -exact && first[k] < exact && last > -exact && last < exact) {
      const double e0 = double(first[k]), de = double(step[k]);
      for (int i = 0; i < n; ++i) e[i] = e0 + double(i) * de;
    } else {
      for (int i = 0; i < n; ++i) e[i] = double(first[k] + int64_t(i) * step[k]);
    }
  }
  double* __restrict b0 = b[0];
  double* __restrict b1 = b[1];
  double* __restrict b2 = b[2];
  alignas(64) double sum[kernel_span], inv[kernel_span];
  for (int i = 0; i < n; ++i) {
    b0[i] = b0[i] * inv_area * w[0], b1[i] = b1[i] * inv_area * w[1], b2[i] = b2[i] * inv_area * w[2];
    sum[i] = b0[i] + b1[i] + b2[i];
  }
  // 1 / sum, or 0 where the sum is not positive: dividing in a loop of its own and selecting in the
  // next keeps both free of control flow (a division under a condition might trap), so they vectorize.
  for (int i = 0; i < n; ++i) inv[i] = 1.0 / sum[i];
  for (int i = 0; i < n; ++i) {
    const double inv_sum = sum[i] > 0.0 ? inv[i] : 0.0;
    b0[i] = b0[i] * inv_sum, b1[i] = b1[i] * inv_sum, b2[i] = b2[i] * inv_sum;
  }
}

void to_float3(const double* const in[3], size_t n, float* const out[3]) {
  for (int c = 0; c < 3; ++c) {
    const double* __restrict from = in[c];
    float* __restrict to = out[c];
    for (size_t i = 0; i < n; ++i) to[i] = float(from[i]);
  }
}

void gouraud_span(const float* const b[3], size_t n, const float t[9], const float* __restrict vis,
                  float* const out[3]) {
  const float* __restrict b0 = b[0];
  const float* __restrict b1 = b[1];
  const float* __restrict b2 = b[2];
  for (int c = 0; c < 3; ++c) {
    const float t0 = t[c], t1 = t[3 + c], t2 = t[6 + c];
    float* __restrict o = out[c];
    if (!vis) {
      for (size_t i = 0; i < n; ++i) o[i] = b0[i] * t0 + b1[i] * t1 + b2[i] * t2;
      continue;
    }
    for (size_t i = 0; i < n; ++i) {
      const float v = vis[i];
      const float term = v * (b0[i] * t0 + b1[i] * t1 + b2[i] * t2);
      o[i] += v > 0.0f ? term : 0.0f;
    }
  }
}

void phong_pixels(const float* const b[3], size_t n, const float q[9], const float nrm[9], PhongPixels& __restrict p) {
  const float* __restrict b0 = b[0];
  const float* __restrict b1 = b[1];
  const float* __restrict b2 = b[2];
  for (size_t i = 0; i < n; ++i) {
    const float qx = b0[i] * q[0] + b1[i] * q[3] + b2[i] * q[6];
    const float qy = b0[i] * q[1] + b1[i] * q[4] + b2[i] * q[7];
    const float qz = b0[i] * q[2] + b1[i] * q[5] + b2[i] * q[8];
    float nx = b0[i] * nrm[0] + b1[i] * nrm[3] + b2[i] * nrm[6];
    float ny = b0[i] * nrm[1] + b1[i] * nrm[4] + b2[i] * nrm[7];
    float nz = b0[i] * nrm[2] + b1[i] * nrm[5] + b2[i] * nrm[8];
    // Every quotient is computed, then selected: a division under a condition keeps the loop from
    // vectorizing (it might trap), and 0 / 0 here only makes a NaN that is not selected.
    const float n_len = __builtin_sqrtf(nx * nx + ny * ny + nz * nz);
    const bool n_ok = n_len > 0.0f;
    const float ux = nx / n_len, uy = ny / n_len, uz = nz / n_len;
    nx = n_ok ? ux : nrm[0], ny = n_ok ? uy : nrm[1], nz = n_ok ? uz : nrm[2];
    const float q_len = __builtin_sqrtf(qx * qx + qy * qy + qz * qz);
    const bool q_ok = q_len > 0.0f;
    const float ex = -qx / q_len, ey = -qy / q_len, ez = -qz / q_len;
    p.ex[i] = q_ok ? ex : nx, p.ey[i] = q_ok ? ey : ny, p.ez[i] = q_ok ? ez : nz;
    p.nx[i] = nx, p.ny[i] = ny, p.nz[i] = nz;
    p.qx[i] = qx, p.qy[i] = qy, p.qz[i] = qz;
  }
}

void phong_light(const PhongSpanLight& a, const PhongPixels& __restrict p, size_t n, const float* __restrict vis,
                 const float* const* tint, SpecularLookup table, float* const out[3]) {
  alignas(64) float lx[kernel_span], ly[kernel_span], lz[kernel_span], attenuation[kernel_span];
  if (a.point) {
    for (size_t i = 0; i < n; ++i) {
      const float dx = a.position[0] - p.qx[i], dy = a.position[1] - p.qy[i], dz = a.position[2] - p.qz[i];
      const float dist = __builtin_sqrtf(dx * dx + dy * dy + dz * dz);
      lx[i] = dx / dist, ly[i] = dy / dist, lz[i] = dz / dist;  // NaN at dist 0, and weight 0 below
      const float at = 1.0f / (a.attenuation[0] + a.attenuation[1] * dist + a.attenuation[2] * dist * dist);
      attenuation[i] = dist > 0.0f ? at : 0.0f;
    }
  } else {
    for (size_t i = 0; i < n; ++i) {
      lx[i] = a.to_light[0], ly[i] = a.to_light[1], lz[i] = a.to_light[2], attenuation[i] = 1.0f;
    }
  }
  alignas(64) float n_dot_l[kernel_span], n_dot_h[kernel_span], weight[kernel_span], spec[kernel_span];
  for (size_t i = 0; i < n; ++i) {
    const float nl = p.nx[i] * lx[i] + p.ny[i] * ly[i] + p.nz[i] * lz[i];
    const float hx = lx[i] + p.ex[i], hy = ly[i] + p.ey[i], hz = lz[i] + p.ez[i];
    const float h_len = __builtin_sqrtf(hx * hx + hy * hy + hz * hz);
    const float nh = (p.nx[i] * hx + p.ny[i] * hy + p.nz[i] * hz) / h_len;
    const float w = attenuation[i] * vis[i];
    n_dot_l[i] = nl;
    n_dot_h[i] = h_len > 0.0f ? nh : 0.0f;
    weight[i] = nl > 0.0f ? w : 0.0f;  // also 0 where vis or the attenuation is 0
  }
  for (size_t i = 0; i < n; ++i) spec[i] = 0.0f;
  if (a.has_specular) {
    for (size_t i = 0; i < n; ++i) {
      const float t = (n_dot_h[i] - table.x_min) * table.scale;
      const bool on = t > 0.0f;  // false for NaN too
      const float tt = on ? t : 0.0f;
      const float at = table.top < tt ? table.top : tt;
      const int j = int(at);
      const float d = tt - float(j);
      const float frac = 1.0f < d ? 1.0f : d;
      const float v = table.values[j] + frac * (table.values[j + 1] - table.values[j]);
      spec[i] = on ? v : 0.0f;
    }
  }
  for (int c = 0; c < 3; ++c) {
    const float diffuse = a.diffuse[c], specular = a.specular[c];
    const float* __restrict tinted = tint ? tint[c] : nullptr;
    float* __restrict o = out[c];
    if (tinted) {
      for (size_t i = 0; i < n; ++i) {
        const float w = weight[i];
        const float term = (diffuse * n_dot_l[i] + specular * spec[i]) * (w * tinted[i]);
        o[i] += w > 0.0f ? term : 0.0f;
      }
    } else {
      for (size_t i = 0; i < n; ++i) {
        const float w = weight[i];
        const float term = (diffuse * n_dot_l[i] + specular * spec[i]) * w;
        o[i] += w > 0.0f ? term : 0.0f;
      }
    }
  }
}

// A channel's display byte, as to_byte gives it (clamped to [0, 1], rounded half up), in 32 bits.
inline uint32_t byte_value(float v) {
  const float positive = v > 0.0f ? v : 0.0f;  // also NaN to 0
  const float clamped = 1.0f < positive ? 1.0f : positive;
  return uint32_t(int(clamped * 255.0f + 0.5f));
}

void write_bytes(const float* const in[3], size_t n, uint8_t* rgb) {
  // Packed in 32-bit lanes (a loop that vectorizes), then each pixel's 3 bytes go out as one 4-byte
  // store whose last byte the next pixel's store overwrites; the last pixel writes 3 bytes, so
  // nothing past the span is touched.
  alignas(64) uint32_t packed[kernel_span];
  const float* __restrict r = in[0];
  const float* __restrict g = in[1];
  const float* __restrict b = in[2];
  for (size_t i = 0; i < n; ++i) packed[i] = byte_value(r[i]) | byte_value(g[i]) << 8 | byte_value(b[i]) << 16;
  if (n == 0) return;
  for (size_t i = 0; i + 1 < n; ++i) __builtin_memcpy(rgb + 3 * i, &packed[i], 4);
  const uint32_t last = packed[n - 1];
  uint8_t* px = rgb + 3 * (n - 1);
  px[0] = uint8_t(last), px[1] = uint8_t(last >> 8), px[2] = uint8_t(last >> 16);
}

}  // namespace

const Kernels set{RR_KERNELS_NAME, depth_span,   grouped_depth_span, classify_points, span_weights,
                  to_float3,       gouraud_span, phong_pixels,       phong_light,     write_bytes};

}  // namespace rr::RR_KERNELS_NS

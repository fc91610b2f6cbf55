// The per-pixel inner loops, compiled once per x86-64 level (baseline SSE2, AVX2, AVX-512) from one
// source (kernels_impl.hpp); the best level the CPU runs is picked once per process, or the one the
// environment variable ROOMRENDER_SIMD names (sse2, avx2, avx512). The loops use only IEEE
// operations in a fixed order (no fused multiply-add: -ffp-contract=off), so every level gives the
// same bytes; tests/unit/test_kernels.cpp renders the examples with each one forced and compares.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace rr {

// The longest span the shading kernels below take (SurfaceShader::span_capacity).
constexpr size_t kernel_span = 64;

// Per pixel of a Phong span: the unit normal, the unit vector to the eye and the position relative
// to the eye.
struct PhongPixels {
  alignas(64) float nx[kernel_span], ny[kernel_span], nz[kernel_span];
  alignas(64) float ex[kernel_span], ey[kernel_span], ez[kernel_span];
  alignas(64) float qx[kernel_span], qy[kernel_span], qz[kernel_span];
};

// One light of a Phong span, in the span shader's floats (eye-relative position for a point light,
// unit vector toward it for a directional one).
struct PhongSpanLight {
  float to_light[3], position[3], attenuation[3], diffuse[3], specular[3];
  bool point, has_specular;
};

// A SpecularTable's samples and mapping: x^shininess at x is values[i] + frac (values[i + 1] -
// values[i]) for t = (x - x_min) scale, i = int(min(t, top)), frac = min(t - i, 1); 0 unless t > 0.
struct SpecularLookup {
  const float* values;
  float x_min, scale, top;
};

struct Kernels {
  const char* name;
  // Depth test and write of one span of an opaque triangle: pixel i (0 <= i < n) has
  // z = float(z0 + double(i) * dz_dx); where z > depth[i], depth[i] = z and visible[i] = id.
  void (*depth_span)(double z0, double dz_dx, int n, uint32_t id, float* depth, uint32_t* visible);
  // The same for a triangle in plane group `group` (not 0): a pixel whose visible[i] (not
  // no_visible) has group_of[visible[i]] == group keeps it whatever the depths say.
  void (*grouped_depth_span)(double z0, double dz_dx, int n, uint32_t id, uint32_t group, const uint32_t* group_of,
                             float* depth, uint32_t* visible);
  // The BSP splitter's classification of n <= classify_block points per row of `rows` rows (row k at
  // x + k stride, and so for y and z) against the plane n.p = offset (plane = {nx, ny, nz, offset}):
  // d = nx x + ny y + nz z - offset, in that order; side[i] gets bit 0 where some row's d > epsilon
  // and bit 1 where some row's d < -epsilon, and by_side[v] grows by the number of i with side[i] == v.
  void (*classify_points)(const double* x, const double* y, const double* z, size_t stride, size_t rows, size_t n,
                          const double plane[4], double epsilon, uint8_t* side, size_t by_side[4]);

  // The shading spans' loops (shading_span.cpp and visibility.cpp say what each computes; the
  // arrays hold n <= kernel_span pixels). Perspective-correct weights of n pixels along +x: edge k's
  // value at pixel i is first[k] + i step[k] (exact), weighed by w[k] inv_area; b[k][i] is its share
  // of the three, or 0 where their sum is not positive.
  void (*span_weights)(const int64_t first[3], const int64_t step[3], const double w[3], double inv_area, int n,
                       double* const b[3]);
  void (*to_float3)(const double* const in[3], size_t n, float* const out[3]);
  // Gouraud: with vis null, out[c][i] = b0 t[c] + b1 t[3 + c] + b2 t[6 + c]; else out[c][i] gains
  // v times that where v = vis[i] > 0 (a shadowed light's term).
  void (*gouraud_span)(const float* const b[3], size_t n, const float t[9], const float* vis, float* const out[3]);
  // Phong: the pixels' normals, eye vectors and positions from the vertices' q[3 v + c] (position
  // relative to the eye) and nrm[3 v + c] (normal); then one light's Blinn-Phong term added to out,
  // scaled by vis and, when tint is not null, by tint[c][i].
  void (*phong_pixels)(const float* const b[3], size_t n, const float q[9], const float nrm[9], PhongPixels& p);
  void (*phong_light)(const PhongSpanLight& a, const PhongPixels& p, size_t n, const float* vis,
                      const float* const* tint, SpecularLookup table, float* const out[3]);
  // Display bytes, 3 per pixel: to_byte of each channel.
  void (*write_bytes)(const float* const in[3], size_t n, uint8_t* rgb);
};

constexpr uint32_t no_visible = 0xFFFFFFFFu;  // visible[] where nothing was drawn
constexpr size_t classify_block = 64;         // the most points classify_points takes at once

// The set in use by this process.
const Kernels& kernels();
// Every set this CPU can run, baseline first.
std::span<const Kernels* const> available_kernels();
// Makes `name` the set in use (tests and benchmarks); false, changing nothing, when this CPU cannot
// run it or no set has that name. Not for use while a render runs.
bool use_kernels(std::string_view name);

namespace kernels_sse2 {
extern const Kernels set;
}
namespace kernels_avx2 {
extern const Kernels set;
}
namespace kernels_avx512 {
extern const Kernels set;
}

}  // namespace rr

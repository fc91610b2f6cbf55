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
};

constexpr uint32_t no_visible = 0xFFFFFFFFu;
constexpr size_t classify_block = 64;  // the most points classify_points takes at once  // visible[] where nothing was drawn

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

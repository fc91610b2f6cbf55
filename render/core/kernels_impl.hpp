// The loops of kernels.hpp, written once as plain loops the compiler vectorizes; included by
// kernels_sse2.cpp, kernels_avx2.cpp and kernels_avx512.cpp, each compiled for its level with
// RR_KERNELS_NS naming its namespace and RR_KERNELS_NAME the set.
#include "render/core/kernels.hpp"

namespace rr::RR_KERNELS_NS {

namespace {

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

}  // namespace

const Kernels set{RR_KERNELS_NAME, depth_span, grouped_depth_span, classify_points};

}  // namespace rr::RR_KERNELS_NS

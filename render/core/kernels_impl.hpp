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

}  // namespace

const Kernels set{RR_KERNELS_NAME, depth_span, grouped_depth_span};

}  // namespace rr::RR_KERNELS_NS

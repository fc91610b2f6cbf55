// The kernels of kernels_impl.hpp for the avx2 level (flags in CMakeLists.txt).
#define RR_KERNELS_NS kernels_avx2
#define RR_KERNELS_NAME "avx2"
#include "render/core/kernels_impl.hpp"

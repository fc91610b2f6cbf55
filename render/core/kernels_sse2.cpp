// The kernels of kernels_impl.hpp for the sse2 level (flags in CMakeLists.txt).
#define RR_KERNELS_NS kernels_sse2
#define RR_KERNELS_NAME "sse2"
#include "render/core/kernels_impl.hpp"

// The kernels of kernels_impl.hpp for the avx512 level (flags in CMakeLists.txt).
#define RR_KERNELS_NS kernels_avx512
#define RR_KERNELS_NAME "avx512"
#include "render/core/kernels_impl.hpp"

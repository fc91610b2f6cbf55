// Picks the kernel set (see kernels.hpp): the highest level the CPU supports, unless ROOMRENDER_SIMD
// names a lower one.
#include "render/core/kernels.hpp"

#include <atomic>
#include <cstdlib>
#include <string>
#include <vector>

namespace rr {

namespace {

bool cpu_runs(const Kernels& k) {
  const std::string_view name = k.name;
#if !defined(__x86_64__)
  return name == "sse2";  // elsewhere the sets are all portable builds: keep the first
#else
  if (name == "avx512")
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
           __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
  if (name == "avx2") return __builtin_cpu_supports("avx2");
  return true;
#endif
}

const std::vector<const Kernels*>& runnable() {
  static const std::vector<const Kernels*> sets = [] {
    std::vector<const Kernels*> out;
    for (const Kernels* k : {&kernels_sse2::set, &kernels_avx2::set, &kernels_avx512::set}) {
      if (cpu_runs(*k)) out.push_back(k);
    }
    return out;
  }();
  return sets;
}

const Kernels* initial() {
  const auto& sets = runnable();
  if (const char* wanted = std::getenv("ROOMRENDER_SIMD")) {
    for (const Kernels* k : sets) {
      if (std::string_view(k->name) == wanted) return k;
    }
  }
  return sets.back();
}

std::atomic<const Kernels*>& active() {
  static std::atomic<const Kernels*> set{initial()};
  return set;
}

}  // namespace

const Kernels& kernels() { return *active().load(std::memory_order_relaxed); }

std::span<const Kernels* const> available_kernels() { return runnable(); }

bool use_kernels(std::string_view name) {
  for (const Kernels* k : runnable()) {
    if (k->name == name) {
      active().store(k, std::memory_order_relaxed);
      return true;
    }
  }
  return false;
}

}  // namespace rr

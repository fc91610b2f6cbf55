// Hex form of a 64-bit hash (hash.hpp).
#include "render/core/hash.hpp"

namespace rr {

std::string hex64(uint64_t value) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i, value >>= 4) out[size_t(i)] = digits[value & 0xfu];
  return out;
}

}  // namespace rr

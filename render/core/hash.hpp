// The one hash of the tree: 64-bit FNV-1a (offset basis 0xcbf29ce484222325, prime 0x100000001b3),
// fed incrementally, and its 16-lowercase-hex-digit form. Stored-scene ids and ETags hash text with
// it, scene_id() hashes the static geometry's canonical bytes, the fuzz harness picks variants.
// Not cryptographic: equal inputs hash alike, but a collision can be crafted on purpose.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace rr {

class Fnv1a {
 public:
  static constexpr uint64_t offset_basis = 0xcbf29ce484222325ull;
  static constexpr uint64_t prime = 0x100000001b3ull;

  void add_bytes(std::string_view bytes) {
    for (unsigned char c : bytes) state_ = (state_ ^ c) * prime;
  }
  // The value's bytes least significant first, so a hash does not depend on the host's byte order.
  void add_u64(uint64_t value) {
    for (int i = 0; i < 8; ++i, value >>= 8) state_ = (state_ ^ (value & 0xffu)) * prime;
  }
  void add_u32(uint32_t value) {
    for (int i = 0; i < 4; ++i, value >>= 8) state_ = (state_ ^ (value & 0xffu)) * prime;
  }
  void add_u8(uint8_t value) { state_ = (state_ ^ value) * prime; }

  uint64_t value() const { return state_; }

 private:
  uint64_t state_ = offset_basis;
};

inline uint64_t fnv1a(std::string_view bytes) {
  Fnv1a h;
  h.add_bytes(bytes);
  return h.value();
}

// 16 lowercase hex digits, most significant first.
std::string hex64(uint64_t value);

// hex64(fnv1a(bytes)): stored-scene ids, ETags.
inline std::string hash_hex(std::string_view bytes) { return hex64(fnv1a(bytes)); }

}  // namespace rr

// The hash module: FNV-1a 64 against published test vectors, streaming equal to one call, integers
// fed least significant byte first, and the hex form.
#include "render/core/hash.hpp"

#include <gtest/gtest.h>

namespace rr {
namespace {

TEST(Hash, Fnv1aMatchesPublishedVectors) {
  EXPECT_EQ(fnv1a(""), 0xcbf29ce484222325ull);  // the offset basis
  EXPECT_EQ(fnv1a("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a("foobar"), 0x85944171f73967e8ull);
  EXPECT_EQ(hash_hex(""), "cbf29ce484222325");
  EXPECT_EQ(hash_hex("a"), "af63dc4c8601ec8c");
}

TEST(Hash, StreamingEqualsOneCall) {
  Fnv1a h;
  h.add_bytes("foo");
  h.add_bytes("");
  h.add_bytes("bar");
  EXPECT_EQ(h.value(), fnv1a("foobar"));
}

TEST(Hash, IntegersGoLeastSignificantByteFirst) {
  Fnv1a wide, narrow, bytes;
  wide.add_u64(0x0807060504030201ull);
  narrow.add_u32(0x04030201u);
  narrow.add_u32(0x08070605u);
  for (uint8_t b = 1; b <= 8; ++b) bytes.add_u8(b);
  EXPECT_EQ(wide.value(), bytes.value());
  EXPECT_EQ(narrow.value(), bytes.value());
  EXPECT_EQ(bytes.value(), fnv1a("\x01\x02\x03\x04\x05\x06\x07\x08"));
}

TEST(Hash, HexIsSixteenLowercaseDigits) {
  EXPECT_EQ(hex64(0), "0000000000000000");
  EXPECT_EQ(hex64(0x00ab0000000000ffull), "00ab0000000000ff");
  EXPECT_EQ(hex64(~0ull), "ffffffffffffffff");
}

}  // namespace
}  // namespace rr

#include "support/image_bytes.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <random>

namespace rr::testing {

std::string u32_be(uint32_t v) {
  return {char(v >> 24), char((v >> 16) & 0xFF), char((v >> 8) & 0xFF), char(v & 0xFF)};
}

std::string png_chunk(const std::string& type, const std::string& data) {
  const std::string body = type + data;
  const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()));
  return u32_be(uint32_t(data.size())) + body + u32_be(uint32_t(crc));
}

std::string png_head(uint32_t w, uint32_t h, char colour_type) {
  return std::string("\x89PNG\r\n\x1a\n", 8) +
         png_chunk("IHDR", u32_be(w) + u32_be(h) + std::string{char(8), colour_type, 0, 0, 0});
}

std::string base64_encode(std::string_view bytes, bool pad) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    if (n > 1) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (n > 2) v |= uint8_t(bytes[i + 2]);
    for (size_t k = 0; k < 4; ++k) {
      if (k <= n) {
        out.push_back(digits[(v >> (18 - 6 * k)) & 63]);
      } else if (pad) {
        out.push_back('=');
      }
    }
  }
  return out;
}

std::span<const uint8_t> as_bytes(std::string_view s) { return {reinterpret_cast<const uint8_t*>(s.data()), s.size()}; }

Image random_image(int w, int h, uint32_t seed) {
  std::mt19937 rng(seed);
  Image image;
  image.width = w, image.height = h;
  image.rgb.resize(size_t(w) * size_t(h) * 3);
  for (uint8_t& b : image.rgb) b = uint8_t(rng() & 0xFF);
  return image;
}

std::shared_ptr<const TextureImage> decode_ok(std::span<const uint8_t> bytes) {
  TextureError error;
  std::shared_ptr<const TextureImage> image = decode_texture(bytes, {}, &error);
  EXPECT_TRUE(image) << error.message;
  return image;
}

std::shared_ptr<const TextureImage> texture_of(const Image& image) { return decode_ok(as_bytes(encode_png(image))); }

}  // namespace rr::testing

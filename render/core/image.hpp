// Framebuffers and their file formats: RGB8 images <-> PNG (stb_image_write, compiled in image.cpp
// alone / stb_image, compiled in texture_decode.cpp alone), and the raw id-buffer format:
// little-endian uint32 width, uint32 height, then width*height uint32 polygon ids, row-major from
// the top-left, 0xFFFFFFFF for background.
#pragma once

#include "render/core/math.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rr {

constexpr uint32_t background_id = 0xFFFFFFFFu;

struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3, row-major from the top-left

  Image() = default;
  Image(int w, int h, Color fill);
  uint8_t* pixel(int x, int y) { return rgb.data() + (size_t(y) * size_t(width) + size_t(x)) * 3; }
  const uint8_t* pixel(int x, int y) const { return rgb.data() + (size_t(y) * size_t(width) + size_t(x)) * 3; }
};

struct IdBuffer {
  int width = 0;
  int height = 0;
  std::vector<uint32_t> ids;  // width * height

  IdBuffer() = default;
  IdBuffer(int w, int h) : width(w), height(h), ids(size_t(w) * size_t(h), background_id) {}
  uint32_t at(int x, int y) const { return ids[size_t(y) * size_t(width) + size_t(x)]; }
};

// One display value in [0, 1] -> 8 bits, rounded to nearest. Inline: the rasterizers call it per
// written channel.
inline uint8_t to_byte(float v) {
  if (!(v > 0.0f)) return 0;  // also maps NaN to black rather than to undefined behaviour
  if (v >= 1.0f) return 255;
  return uint8_t(v * 255.0f + 0.5f);
}

std::string encode_png(const Image& image);
// Throws std::runtime_error when the bytes are not a PNG stb_image can read.
Image decode_png(std::string_view png);

std::string encode_id_buffer(const IdBuffer& ids);
// Throws std::runtime_error when the size does not match the header.
IdBuffer decode_id_buffer(std::string_view bytes);

}  // namespace rr

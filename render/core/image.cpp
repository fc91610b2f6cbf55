// Framebuffer encoding. This is the only translation unit that compiles stb_image_write (static, so
// it cannot clash with Debian's libstb.so if something else links it); the decoders live in
// texture_decode.cpp, behind image_decode.hpp.
#include "render/core/image.hpp"
#include "render/core/image_decode.hpp"

#include <cstring>
#include <stdexcept>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

namespace rr {

Image::Image(int w, int h, Color fill) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3) {
  const uint8_t c[3] = {to_byte(fill.r), to_byte(fill.g), to_byte(fill.b)};
  for (size_t i = 0; i < rgb.size(); i += 3) std::memcpy(&rgb[i], c, 3);
}

namespace {
void append_bytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}
}  // namespace

std::string encode_png(const Image& image) {
  std::string png;
  png.reserve(image.rgb.size() / 4 + 1024);
  if (!stbi_write_png_to_func(append_bytes, &png, image.width, image.height, 3, image.rgb.data(), image.width * 3)) {
    throw std::runtime_error("PNG encoding failed");
  }
  return png;
}

Image decode_png(std::string_view png) {
  // The decoder also reads JPEG: without the PNG signature this refuses.
  if (!png.starts_with(std::string_view("\x89PNG\r\n\x1a\n", 8))) {
    throw std::runtime_error("not a readable PNG: no PNG signature");
  }
  Image image;
  std::string failure;
  if (!decode_rgb8({reinterpret_cast<const uint8_t*>(png.data()), png.size()}, image, &failure)) {
    throw std::runtime_error("not a readable PNG: " + failure);
  }
  return image;
}

namespace {
void put_u32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(char((v >> (8 * i)) & 0xFF));
}
uint32_t get_u32(std::string_view in, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t(uint8_t(in[at + size_t(i)])) << (8 * i);
  return v;
}
}  // namespace

std::string encode_id_buffer(const IdBuffer& ids) {
  std::string out;
  out.reserve(8 + ids.ids.size() * 4);
  put_u32(out, uint32_t(ids.width));
  put_u32(out, uint32_t(ids.height));
  for (uint32_t id : ids.ids) put_u32(out, id);
  return out;
}

IdBuffer decode_id_buffer(std::string_view bytes) {
  if (bytes.size() < 8) throw std::runtime_error("id buffer shorter than its header");
  uint32_t w = get_u32(bytes, 0), h = get_u32(bytes, 4);
  if (w == 0 || h == 0 || w > 65536 || h > 65536 || bytes.size() != 8 + size_t(w) * h * 4) {
    throw std::runtime_error("id buffer size does not match its header");
  }
  IdBuffer ids{static_cast<int>(w), static_cast<int>(h)};
  for (size_t i = 0; i < ids.ids.size(); ++i) ids.ids[i] = get_u32(bytes, 8 + i * 4);
  return ids;
}

}  // namespace rr

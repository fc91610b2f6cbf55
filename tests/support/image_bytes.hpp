// Encoded image bytes built by hand for tests of the decoders and the request format: PNG chunks
// with their CRC, a header that claims any size, and base64 for data: URIs.
#pragma once

#include "render/core/image.hpp"
#include "render/core/texture.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace rr::testing {

std::string u32_be(uint32_t v);
// A PNG chunk: length, type, data and the CRC of type and data.
std::string png_chunk(const std::string& type, const std::string& data);
// The PNG signature and an IHDR (8 bits per channel, colour type 2 = RGB or 6 = RGBA) claiming
// w x h pixels, with a correct CRC, and nothing else.
std::string png_head(uint32_t w, uint32_t h, char colour_type = 2);
// Standard base64 (RFC 4648), with or without '=' padding.
std::string base64_encode(std::string_view bytes, bool pad = true);

std::span<const uint8_t> as_bytes(std::string_view s);
// An image of w x h random texels, the same for the same seed.
Image random_image(int w, int h, uint32_t seed);
// decode_texture with the default limits, with a test failure naming the refusal when it refuses.
std::shared_ptr<const TextureImage> decode_ok(std::span<const uint8_t> bytes);
// The image through encode_png and decode_texture.
std::shared_ptr<const TextureImage> texture_of(const Image& image);

}  // namespace rr::testing

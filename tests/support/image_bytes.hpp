// Encoded image bytes built by hand for tests of the decoders and the request format: PNG chunks
// with their CRC, a header that claims any size, and base64 for data: URIs.
#pragma once

#include <cstdint>
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

}  // namespace rr::testing

// The image decoders behind one function, in one translation unit (texture_decode.cpp): PNG by
// libpng, JPEG by libjpeg-turbo. Encoded bytes -> RGB8 rows from the top (grey expanded, alpha
// dropped), or the decoder's reason for refusing them ("IHDR: CRC error", "Bogus Huffman table
// definition", ...).
#pragma once

#include "render/core/image.hpp"

#include <cstdint>
#include <span>
#include <string>

namespace rr {

bool decode_rgb8(std::span<const uint8_t> encoded, Image& image, std::string* failure);

}  // namespace rr

// stb_image behind one function, so that one translation unit (texture_decode.cpp) compiles it, with
// PNG and JPEG only: encoded bytes -> RGB8 rows from the top (grey expanded, alpha dropped), or
// stb_image's reason for refusing them ("bad png sig", "too large", ...).
#pragma once

#include "render/core/image.hpp"

#include <cstdint>
#include <span>
#include <string>

namespace rr {

bool decode_rgb8(std::span<const uint8_t> encoded, Image& image, std::string* failure);

}  // namespace rr

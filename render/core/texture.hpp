// Texture images: decoding with bounds, mipmaps, and filtered lookups (docs/textures.md).
//
// Colour space: a texel is its byte / 255, the same display values as every Color in a scene (the
// renderer has no gamma), and every filter averages those values. One rule for decoding, mipmaps,
// every filter and the reference.
//
// Coordinates: (u, v) in tiles. u grows to the right of the image and v upward, so (0, 0) is the
// bottom-left corner of the image and (1, 1) its top-right; texel (i, j) of a level of size w x h
// (j counted from the image's top row) has its centre at u = (i + 0.5) / w, v = 1 - (j + 0.5) / h.
// Wrapping repeats in both directions. A footprint is the derivatives of (u, v) per pixel along the
// screen's x and y.
#pragma once

#include "render/core/math.hpp"
#include "render/core/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rr {

// Bounds checked on an encoded image's header, before anything is decoded.
struct TextureLimits {
  int max_side = 8192;                  // pixels, either dimension
  size_t max_pixels = size_t{1} << 24;  // width x height
};

// One level of a mip chain: RGB bytes, rows from the image's top.
struct MipLevel {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

// A decoded image with its mip chain, immutable once made and shared by every material that uses it.
struct TextureImage {
  // [0]: the image; each next one halves each side (rounding down, at least 1) down to 1 x 1, each texel
  // the mean of the area of the previous level it covers (a partly covered texel of an odd side weighs
  // its share), rounded to the nearest byte.
  std::vector<MipLevel> levels;
  std::string content_id;  // 16 hex digits: FNV-1a (hash.hpp) of the encoded bytes
  int width() const { return levels.front().width; }
  int height() const { return levels.front().height; }
  size_t bytes() const;  // heap bytes of the levels: their texels and the array holding them
};

// Why an encoded image was refused.
struct TextureError {
  enum class Kind { too_large, unreadable };
  Kind kind = Kind::unreadable;
  std::string message;  // for the user: what was wrong ("PNG header says 100000 x 100000 pixels; ...")
};

// Decodes a PNG or JPEG (sniffed from its first bytes; nothing else is accepted) to RGB, dropping
// any alpha, and builds its mip chain. Reads the header first and refuses an image over `limits`
// without decoding it. Returns null and fills *error when refused.
std::shared_ptr<const TextureImage> decode_texture(std::span<const uint8_t> encoded, const TextureLimits& limits,
                                                   TextureError* error);

// Sniffs a PNG or JPEG from its first bytes and reads its header's size without decoding it: false,
// and *error filled, when it is neither, its header is unreadable or the size is over `limits` (what
// decode_texture checks before it decodes).
bool read_texture_header(std::span<const uint8_t> encoded, const TextureLimits& limits, int* width, int* height,
                         TextureError* error);

// The bytes of a `data:` URI ("data:image/png;base64,...": a media type, ";base64", a comma, then
// base64). Returns false and fills *error on anything else, or when the decoded bytes would exceed
// max_bytes (checked from the length before decoding).
bool decode_data_uri(std::string_view uri, size_t max_bytes, std::vector<uint8_t>& bytes, std::string* error);

// The filtered colour of the image at (u, v) for a pixel whose footprint is (du_dx, dv_dx) along the
// screen's x and (du_dy, dv_dy) along y:
//   nearest      the texel of level 0 holding (u, v);
//   bilinear     the four nearest texels of level 0, weighted by distance;
//   trilinear    bilinear in the two levels around lambda = log2(rho), blended linearly (level 0
//                alone when lambda <= 0), rho the geometric mean of the footprint's two axes in
//                level-0 texels: the side of a square of the footprint's area, not OpenGL's longer
//                axis, which blurs a surface seen at a grazing angle far more than the exact box
//                filter does (docs/textures.md measures both);
//   anisotropic  N = rho_max / rho_min rounded up, at most 16, trilinear taps spread evenly along the
//                longer axis, each at lambda = log2(rho_max / N): the shorter axis's level, or a
//                coarser one when N was clamped; their mean.
Color sample_texture(const TextureImage& image, TextureFilter filter, glm::dvec2 uv, glm::dvec2 duv_dx,
                     glm::dvec2 duv_dy);

// Level 0 bilinearly filtered at (u, v), with repeat wrapping: the reference's tap.
Color texel_bilinear(const TextureImage& image, glm::dvec2 uv);

// The mean of the image over the pixel's footprint parallelogram (a box filter over the
// pixel, mapped to the surface by the derivatives), from `n` x `n` stratified bilinear taps of level 0.
Color sample_texture_box(const TextureImage& image, glm::dvec2 uv, glm::dvec2 duv_dx, glm::dvec2 duv_dy, int n);

}  // namespace rr

// Error measures of a render against the reference (docs/accuracy.md): visibility error (share of
// pixels whose polygon id differs, over all pixels and over pixels off the reference's id edges),
// shading error (RMSE and PSNR of the 8-bit RGB image) and shadow error (share of pixels whose
// per-light lit state differs), and edge error (colour error on the pixels around the reference's id
// edges, against the 256-sample reference: docs/antialiasing.md) and texture error (colour error on
// the textured pixels away from edges: docs/textures.md). The first argument is always the
// reference; buffers must have one size (std::invalid_argument otherwise). `roomrender compare`
// prints these as JSON.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/image.hpp"
#include "render/core/tessellate.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace rr {

// A pixel with a 4-neighbour (inside the image) of another id, background included: polygon
// borders, intersection lines and silhouettes, where two exact methods may disagree by rounding.
bool is_edge_pixel(const IdBuffer& ids, int x, int y);

struct VisibilityError {
  size_t pixels = 0;              // all pixels
  size_t differing = 0;           // id differs from the reference
  size_t non_edge_pixels = 0;     // pixels that are not edge pixels of the reference
  size_t non_edge_differing = 0;  // of those, id differs
  double share() const { return pixels ? double(differing) / double(pixels) : 0.0; }
  double non_edge_share() const { return non_edge_pixels ? double(non_edge_differing) / double(non_edge_pixels) : 0.0; }
};
VisibilityError visibility_error(const IdBuffer& reference, const IdBuffer& test);

// RMSE over every channel of every pixel, in 8-bit units: sqrt(sum (a - b)^2 / (3 * pixels));
// PSNR = 20 log10(255 / RMSE) dB, infinite for identical images.
struct ShadingError {
  double rmse = 0.0;
  double psnr_db = 0.0;
};
ShadingError shading_error(const Image& reference, const Image& test);

// Frame::shadow_mask compared a pixel (`bytes_per_pixel` bytes) at a time: a pixel differs when any
// of its lights' lit state does.
// With the image's width (compare_frames gives it), the pixels are also split into the band of
// shadow_edge_band pixels (Chebyshev distance) around the reference's shadow edges, where a map's
// resolution or a raster's interpolated position may decide otherwise than the exact ray, and the
// pixels away from it, where they should not. A shadow edge pixel's mask differs from one of its
// 4-neighbours' in the reference.
constexpr int shadow_edge_band = 2;
struct ShadowError {
  size_t pixels = 0;
  size_t differing = 0;
  bool split = false;  // the band and away counts below are filled
  size_t band_pixels = 0, band_differing = 0;
  size_t away_pixels = 0, away_differing = 0;
  double share() const { return pixels ? double(differing) / double(pixels) : 0.0; }
  double band_share() const { return band_pixels ? double(band_differing) / double(band_pixels) : 0.0; }
  double away_share() const { return away_pixels ? double(away_differing) / double(away_pixels) : 0.0; }
};
// width 0: no split (the length of a row is not known).
ShadowError shadow_error(std::span<const uint8_t> reference, std::span<const uint8_t> test, size_t bytes_per_pixel = 1,
                         int width = 0);

// An anti-aliasing edge pixel: its 3x3 neighbourhood (clipped to the image) in the reference's
// centre-sample id buffer holds more than one id, background included. Every pixel that a straight
// polygon border crosses is one (a line through the pixel square has a neighbouring centre on its
// far side); a sliver that misses every centre of the 3x3 block is not seen.
bool is_aa_edge_pixel(const IdBuffer& ids, int x, int y);

// Colour error on the anti-aliasing edge pixels of `reference_ids`: a pixel's error is the mean of
// |reference - test| over R, G and B (8-bit units); `mean` averages it over the edge pixels, `p99` is
// its 99th percentile (nearest rank: the smallest value at least 99 % of the edge pixels reach or
// stay below), `max` the largest. Zero everywhere when there is no edge pixel.
struct EdgeError {
  size_t pixels = 0;       // all pixels
  size_t edge_pixels = 0;  // anti-aliasing edge pixels of the reference
  double mean = 0.0;
  double p99 = 0.0;
  double max = 0.0;
};
EdgeError edge_error(const IdBuffer& reference_ids, const Image& reference, const Image& test);

// Colour error on the textured pixels away from edges, so that filtering error is not mixed with
// edge error: pixels whose reference polygon is textured (`textured[id]` non-zero), that are not
// edge pixels of the reference (is_edge_pixel) and, when `test_ids` is given, where the test drew the
// same polygon. RMSE and PSNR as shading_error's, over those pixels; infinite PSNR when they agree
// (or there are none: `pixels` says which). A reference id past the end of `textured` is an error
// (std::invalid_argument): the ids and the polygon list are not of one tessellation.
struct TexturedPixelError {
  size_t pixels = 0;
  double rmse = 0.0;
  double psnr_db = 0.0;
};
TexturedPixelError texture_error(const IdBuffer& reference_ids, std::span<const uint8_t> textured,
                                 const Image& reference, const Image& test, const IdBuffer* test_ids = nullptr);
// One byte per polygon id of `soup`: 1 where the polygon has texture coordinates (Polygon::uv_map).
std::vector<uint8_t> textured_polygons(const PolygonSoup& soup);

struct ErrorMeasures {
  int width = 0, height = 0;
  std::optional<VisibilityError> visibility;
  std::optional<ShadingError> shading;
  std::optional<ShadowError> shadow;
};
// Every measure the two frames allow: shadow only when both carry a shadow mask.
ErrorMeasures compare_frames(const Frame& reference, const Frame& test);

}  // namespace rr

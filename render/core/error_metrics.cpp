// Error measures (see error_metrics.hpp). Plain loops over same-sized buffers; sums in doubles of
// integer squares, which are exact up to 2^53 / 255^2 ~ 1.4e11 channel values.
#include "render/core/error_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

namespace rr {

namespace {
void require_same_size(int w0, int h0, int w1, int h1, const char* what) {
  if (w0 != w1 || h0 != h1) {
    throw std::invalid_argument(std::string(what) + " sizes differ: " + std::to_string(w0) + "x" + std::to_string(h0) +
                                " and " + std::to_string(w1) + "x" + std::to_string(h1));
  }
}
}  // namespace

bool is_edge_pixel(const IdBuffer& ids, int x, int y) {
  const uint32_t id = ids.at(x, y);
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int nx = x + dx[k], ny = y + dy[k];
    if (nx >= 0 && ny >= 0 && nx < ids.width && ny < ids.height && ids.at(nx, ny) != id) return true;
  }
  return false;
}

VisibilityError visibility_error(const IdBuffer& reference, const IdBuffer& test) {
  require_same_size(reference.width, reference.height, test.width, test.height, "id buffer");
  VisibilityError e;
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      const bool differs = reference.at(x, y) != test.at(x, y);
      ++e.pixels;
      e.differing += differs;
      if (is_edge_pixel(reference, x, y)) continue;
      ++e.non_edge_pixels;
      e.non_edge_differing += differs;
    }
  }
  return e;
}

ShadingError shading_error(const Image& reference, const Image& test) {
  require_same_size(reference.width, reference.height, test.width, test.height, "image");
  double sum = 0.0;
  for (size_t i = 0; i < reference.rgb.size(); ++i) {
    const double d = double(reference.rgb[i]) - double(test.rgb[i]);
    sum += d * d;
  }
  ShadingError e;
  e.rmse = reference.rgb.empty() ? 0.0 : std::sqrt(sum / double(reference.rgb.size()));
  e.psnr_db = e.rmse > 0.0 ? 20.0 * std::log10(255.0 / e.rmse) : std::numeric_limits<double>::infinity();
  return e;
}

TexturedPixelError texture_error(const IdBuffer& reference_ids, std::span<const uint8_t> textured,
                                 const Image& reference, const Image& test, const IdBuffer* test_ids) {
  require_same_size(reference_ids.width, reference_ids.height, reference.width, reference.height, "id buffer");
  require_same_size(reference.width, reference.height, test.width, test.height, "image");
  if (test_ids)
    require_same_size(reference_ids.width, reference_ids.height, test_ids->width, test_ids->height, "id buffer");
  double sum = 0.0;
  TexturedPixelError e;
  for (int y = 0; y < reference_ids.height; ++y) {
    for (int x = 0; x < reference_ids.width; ++x) {
      const uint32_t id = reference_ids.at(x, y);
      if (id == background_id) continue;
      if (id >= textured.size()) {
        throw std::invalid_argument("polygon id " + std::to_string(id) + " is not among the " +
                                    std::to_string(textured.size()) + " polygons of the scene");
      }
      if (!textured[id] || is_edge_pixel(reference_ids, x, y)) continue;
      if (test_ids && test_ids->at(x, y) != id) continue;
      const uint8_t* a = reference.pixel(x, y);
      const uint8_t* b = test.pixel(x, y);
      for (int c = 0; c < 3; ++c) sum += (double(a[c]) - double(b[c])) * (double(a[c]) - double(b[c]));
      ++e.pixels;
    }
  }
  e.rmse = e.pixels ? std::sqrt(sum / double(3 * e.pixels)) : 0.0;
  e.psnr_db = e.rmse > 0.0 ? 20.0 * std::log10(255.0 / e.rmse) : std::numeric_limits<double>::infinity();
  return e;
}

std::vector<uint8_t> textured_polygons(const PolygonSoup& soup) {
  std::vector<uint8_t> textured(soup.polygons.size(), 0);
  for (const Polygon& poly : soup.polygons) {
    if (poly.id < textured.size()) textured[poly.id] = poly.uv_map != 0;
  }
  return textured;
}

ShadowError shadow_error(std::span<const uint8_t> reference, std::span<const uint8_t> test, size_t bytes_per_pixel,
                         int width) {
  if (reference.size() != test.size()) {
    throw std::invalid_argument("shadow mask sizes differ: " + std::to_string(reference.size()) + " and " +
                                std::to_string(test.size()) + " bytes");
  }
  if (bytes_per_pixel == 0 || reference.size() % bytes_per_pixel != 0) {
    throw std::invalid_argument("shadow mask of " + std::to_string(reference.size()) + " bytes is not made of " +
                                std::to_string(bytes_per_pixel) + "-byte pixels");
  }
  ShadowError e;
  e.pixels = reference.size() / bytes_per_pixel;
  auto same = [&](std::span<const uint8_t> x, size_t i, std::span<const uint8_t> y, size_t j) {
    return std::equal(x.begin() + ptrdiff_t(i * bytes_per_pixel), x.begin() + ptrdiff_t((i + 1) * bytes_per_pixel),
                      y.begin() + ptrdiff_t(j * bytes_per_pixel));
  };
  for (size_t i = 0; i < e.pixels; ++i) e.differing += !same(reference, i, test, i);
  if (width <= 0 || e.pixels % size_t(width) != 0) return e;
  // The band: the reference's shadow edge pixels, dilated by shadow_edge_band along rows, then columns.
  const size_t w = size_t(width), h = e.pixels / w, r = size_t(shadow_edge_band);
  std::vector<uint8_t> edge(e.pixels, 0), rows(e.pixels, 0);
  for (size_t y = 0; y < h; ++y) {
    for (size_t x = 0; x < w; ++x) {
      const size_t i = y * w + x;
      edge[i] =
          (x > 0 && !same(reference, i, reference, i - 1)) || (x + 1 < w && !same(reference, i, reference, i + 1)) ||
          (y > 0 && !same(reference, i, reference, i - w)) || (y + 1 < h && !same(reference, i, reference, i + w));
    }
  }
  for (size_t y = 0; y < h; ++y) {
    for (size_t x = 0; x < w; ++x) {
      for (size_t nx = x > r ? x - r : 0; nx <= std::min(x + r, w - 1); ++nx) rows[y * w + x] |= edge[y * w + nx];
    }
  }
  e.split = true;
  for (size_t y = 0; y < h; ++y) {
    for (size_t x = 0; x < w; ++x) {
      bool band = false;
      for (size_t ny = y > r ? y - r : 0; ny <= std::min(y + r, h - 1); ++ny) band = band || rows[ny * w + x];
      const bool differs = !same(reference, y * w + x, test, y * w + x);
      (band ? e.band_pixels : e.away_pixels)++;
      (band ? e.band_differing : e.away_differing) += differs;
    }
  }
  return e;
}

bool is_aa_edge_pixel(const IdBuffer& ids, int x, int y) {
  const uint32_t id = ids.at(x, y);
  for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, ids.height - 1); ++ny) {
    for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, ids.width - 1); ++nx) {
      if (ids.at(nx, ny) != id) return true;
    }
  }
  return false;
}

EdgeError edge_error(const IdBuffer& reference_ids, const Image& reference, const Image& test) {
  require_same_size(reference.width, reference.height, test.width, test.height, "image");
  require_same_size(reference_ids.width, reference_ids.height, reference.width, reference.height,
                    "id buffer and image");
  EdgeError e;
  e.pixels = size_t(reference.width) * size_t(reference.height);
  // Per-pixel errors in thirds of an 8-bit step (the channel sum), integers: the sum is exact.
  std::vector<int> errors;
  for (int y = 0; y < reference.height; ++y) {
    for (int x = 0; x < reference.width; ++x) {
      if (!is_aa_edge_pixel(reference_ids, x, y)) continue;
      const size_t i = (size_t(y) * size_t(reference.width) + size_t(x)) * 3;
      int sum = 0;
      for (int ch = 0; ch < 3; ++ch) sum += std::abs(int(reference.rgb[i + ch]) - int(test.rgb[i + ch]));
      errors.push_back(sum);
    }
  }
  e.edge_pixels = errors.size();
  if (errors.empty()) return e;
  double total = 0.0;
  for (int v : errors) total += v;
  std::sort(errors.begin(), errors.end());
  const size_t rank = (errors.size() * 99 + 99) / 100;  // ceil(0.99 n), 1-based
  e.mean = total / (3.0 * double(errors.size()));
  e.p99 = errors[rank - 1] / 3.0;
  e.max = errors.back() / 3.0;
  return e;
}

ErrorMeasures compare_frames(const Frame& reference, const Frame& test) {
  ErrorMeasures m;
  m.width = reference.image.width;
  m.height = reference.image.height;
  m.visibility = visibility_error(reference.ids, test.ids);
  m.shading = shading_error(reference.image, test.image);
  if (!reference.shadow_mask.empty() && !test.shadow_mask.empty()) {
    if (reference.shadow_mask_bytes != test.shadow_mask_bytes) {
      throw std::invalid_argument("shadow masks of " + std::to_string(reference.shadow_mask_bytes) + " and " +
                                  std::to_string(test.shadow_mask_bytes) + " bytes a pixel");
    }
    m.shadow =
        shadow_error(reference.shadow_mask, test.shadow_mask, reference.shadow_mask_bytes, reference.image.width);
  }
  return m;
}

}  // namespace rr

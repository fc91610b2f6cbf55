// The one triangle rasterizer. Input: three vertices in screen space (pixels, y down) with their
// 1/w. Output: a callback per covered pixel with the interpolated 1/w (the depth every pipeline
// compares: larger is nearer) and perspective-correct barycentrics.
// Coverage rule: pixel (x, y) is covered when its centre (x + 0.5, y + 0.5) is strictly inside the
// triangle, or exactly on a top or left edge (the top-left rule), so triangles sharing an edge cover
// each pixel on it exactly once. Vertices snap to 1/16384 pixel (14 sub-pixel bits); edge functions
// are exact 64-bit integers, so coverage never depends on rounding. Either winding is accepted.
// TriangleSetup holds that integer set-up; the tiled z-buffer (visibility.cpp) uses the same one,
// so both rasterizers cover the same pixels and compute the same weights bit for bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rr {

struct RasterVertex {
  double x = 0.0;  // screen pixels
  double y = 0.0;
  double inv_w = 1.0;  // 1 / clip w = 1 / view depth
};

struct PixelRect {  // half-open: x0 <= x < x1, y0 <= y < y1
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct Fragment {
  int x = 0, y = 0;
  double inv_w = 0.0;             // depth key: larger is nearer
  double b[3] = {0.0, 0.0, 0.0};  // perspective-correct weights of v0, v1, v2 (sum to 1)
};

// Why 14 bits, and what they need. Clipping keeps x and y within the guard band, so a vertex lies
// within [-S/2, 3S/2] pixels of an image whose sides are at most S (max_image_side_for_raster):
// |X| <= 1.5 S 2^b in sub-pixel units. An edge function at a pixel centre inside the image is
// dx (py - y0) - dy (px - x0) with |dx|, |dy| <= 2 S 2^b and |py - y0|, |px - x0| <= 1.5 S 2^b, so
// it and every partial sum on the way (c, c + x step_x, ...) stay within 6 S^2 2^(2b); the set-up's
// area products within 4 S^2 2^(2b). Both fit int64 when S 2^b < 1.24e9, and snapped coordinates
// fit the binned int32 when 1.5 S 2^b < 2^31. With S = 65536 and b = 14, S 2^b = 1.07e9. More bits
// would need smaller images, and would push the edge values of triangles over about 4,000 pixels
// past 2^52, where span_weights leaves its double stepping for int64.
// A vertex then moves at most 2^-15 pixel per axis when snapped, which is what separates the
// rasterizer's coverage from the reference's exact projection (docs/accuracy.md, "Specks").
constexpr int subpixel_bits = 14;
constexpr int64_t subpixel_one = int64_t{1} << subpixel_bits;
constexpr int max_image_side_for_raster = 65536;
static_assert(double(max_image_side_for_raster) * double(subpixel_one) < 1.24e9, "edge functions fit int64");
static_assert(1.5 * double(max_image_side_for_raster) * double(subpixel_one) < 2147483648.0, "binned X, Y fit int32");

namespace detail {
// std::llround (half away from zero) without the libm call: v - trunc(v) is exact for |v| < 2^52,
// far beyond the guard band's coordinates in sub-pixel units (below 2^31).
inline int64_t snap_round(double v) {
  const int64_t t = int64_t(v);
  const double d = v - double(t);
  return d >= 0.5 ? t + 1 : d <= -0.5 ? t - 1 : t;
}
inline int64_t floor_div(int64_t a, int64_t b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
// Top-left rule for an edge a -> b of a triangle wound so that its area is positive with y down
// (interior on the right of each edge as drawn on screen): a top edge is horizontal going right,
// a left edge goes up.
inline bool is_top_left(int64_t dx, int64_t dy) { return (dy == 0 && dx > 0) || dy < 0; }
}  // namespace detail

inline int64_t snap_to_subpixel(double pixels) { return detail::snap_round(pixels * double(subpixel_one)); }

// A snapped triangle's edge functions. Edge k runs from vertex order[k+1] to order[k+2] and weighs
// vertex order[k]; at the centre of pixel (x, y) it is E_k = c[k] + x * step_x[k] + y * step_y[k],
// already less the top-left bias (1 on an edge that is not top or left), so a pixel is covered
// exactly when all three are >= 0.
struct TriangleSetup {
  int order[3] = {0, 1, 2};
  int64_t c[3] = {}, step_x[3] = {}, step_y[3] = {}, bias[3] = {};
  int px0 = 0, py0 = 0, px1 = -1, py1 = -1;  // inclusive pixel bounds of the covered centres (unclipped)
  double inv_area = 0.0;

  int64_t edge(int k, int x, int y) const { return c[k] + int64_t(x) * step_x[k] + int64_t(y) * step_y[k]; }
};

// False when the snapped triangle has zero area (it covers no pixel centre).
inline bool setup_triangle(const int64_t X[3], const int64_t Y[3], TriangleSetup& s) {
  int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
  if (area == 0) return false;
  s.order[0] = 0, s.order[1] = 1, s.order[2] = 2;
  if (area < 0) {  // make the winding positive; the caller's weights follow the original order
    std::swap(s.order[1], s.order[2]);
    area = -area;
  }
  const int64_t half = subpixel_one / 2;
  const int64_t min_x = std::min({X[0], X[1], X[2]}), max_x = std::max({X[0], X[1], X[2]});
  const int64_t min_y = std::min({Y[0], Y[1], Y[2]}), max_y = std::max({Y[0], Y[1], Y[2]});
  s.px0 = int(detail::floor_div(min_x - half + subpixel_one - 1, subpixel_one));
  s.px1 = int(detail::floor_div(max_x - half, subpixel_one));
  s.py0 = int(detail::floor_div(min_y - half + subpixel_one - 1, subpixel_one));
  s.py1 = int(detail::floor_div(max_y - half, subpixel_one));
  for (int k = 0; k < 3; ++k) {
    const int i0 = s.order[(k + 1) % 3], i1 = s.order[(k + 2) % 3];
    const int64_t dx = X[i1] - X[i0], dy = Y[i1] - Y[i0];
    // E(p) = dx * (p.y - y0) - dy * (p.x - x0); > 0 inside. Pixels on a non-top-left edge are
    // excluded by testing E - 1 >= 0 there instead of E >= 0.
    s.bias[k] = detail::is_top_left(dx, dy) ? 0 : 1;
    s.c[k] = dx * (half - Y[i0]) - dy * (half - X[i0]) - s.bias[k];
    s.step_x[k] = -dy * subpixel_one;
    s.step_y[k] = dx * subpixel_one;
  }
  s.inv_area = 1.0 / double(area);
  return true;
}

// The covered pixels of a row are one span (the triangle is convex): its ends, as offsets from the
// pixel where the edge values are e[], found exactly from the integer edge functions. Empty when
// last < first. `last` starts as the largest offset wanted.
inline void row_span(const TriangleSetup& s, const int64_t e[3], int64_t& first, int64_t& last) {
  first = 0;
  for (int k = 0; k < 3; ++k) {
    if (s.step_x[k] > 0) {
      first = std::max(first, -detail::floor_div(e[k], s.step_x[k]));
    } else if (s.step_x[k] < 0) {
      last = std::min(last, e[k] < 0 ? int64_t{-1} : e[k] / -s.step_x[k]);
    } else if (e[k] < 0) {
      last = -1;
    }
  }
}

// 1/w and the perspective-correct weights (in the caller's vertex order) at a covered pixel whose
// edge values are e[]; inv_w[] is in the caller's order too.
inline void pixel_weights(const TriangleSetup& s, const double inv_w[3], const int64_t e[3], Fragment& f) {
  // Undo the top-left bias (it only decides ties) before weighting.
  const double l0 = double(e[0] + s.bias[0]) * s.inv_area * inv_w[s.order[0]];
  const double l1 = double(e[1] + s.bias[1]) * s.inv_area * inv_w[s.order[1]];
  const double l2 = double(e[2] + s.bias[2]) * s.inv_area * inv_w[s.order[2]];
  const double sum = l0 + l1 + l2;
  f.inv_w = sum;
  const double inv_sum = sum > 0.0 ? 1.0 / sum : 0.0;
  f.b[s.order[0]] = l0 * inv_sum;
  f.b[s.order[1]] = l1 * inv_sum;
  f.b[s.order[2]] = l2 * inv_sum;
}

template <class Fn>
void rasterize_triangle(const RasterVertex& a, const RasterVertex& b, const RasterVertex& c, const PixelRect& rect,
                        Fn&& fn) {
  const int64_t X[3] = {snap_to_subpixel(a.x), snap_to_subpixel(b.x), snap_to_subpixel(c.x)};
  const int64_t Y[3] = {snap_to_subpixel(a.y), snap_to_subpixel(b.y), snap_to_subpixel(c.y)};
  TriangleSetup s;
  if (!setup_triangle(X, Y, s)) return;
  const int px0 = std::max(rect.x0, s.px0), px1 = std::min(rect.x1 - 1, s.px1);
  const int py0 = std::max(rect.y0, s.py0), py1 = std::min(rect.y1 - 1, s.py1);
  if (px0 > px1 || py0 > py1) return;
  const double inv_w[3] = {a.inv_w, b.inv_w, c.inv_w};
  int64_t e_row[3] = {s.edge(0, px0, py0), s.edge(1, px0, py0), s.edge(2, px0, py0)};
  Fragment f;
  for (int y = py0; y <= py1; ++y) {
    // Rather than test every pixel of the bounding box, which for a long thin triangle is mostly
    // empty, walk the row's exact span.
    int64_t first, last = px1 - px0;
    row_span(s, e_row, first, last);
    int64_t e[3] = {e_row[0] + first * s.step_x[0], e_row[1] + first * s.step_x[1], e_row[2] + first * s.step_x[2]};
    for (int x = px0 + int(first); x <= px0 + int(std::max(last, first - 1)); ++x) {
      f.x = x;
      f.y = y;
      pixel_weights(s, inv_w, e, f);
      fn(f);
      for (int k = 0; k < 3; ++k) e[k] += s.step_x[k];
    }
    for (int k = 0; k < 3; ++k) e_row[k] += s.step_y[k];
  }
}

}  // namespace rr

// The one triangle rasterizer. Input: three vertices in screen space (pixels, y down) with their
// 1/w. Output: a callback per covered pixel with the interpolated 1/w (the depth every pipeline
// compares: larger is nearer) and perspective-correct barycentrics.
// Coverage rule: pixel (x, y) is covered when its centre (x + 0.5, y + 0.5) is strictly inside the
// triangle, or exactly on a top or left edge (the top-left rule), so triangles sharing an edge cover
// each pixel on it exactly once. Vertices snap to 1/256 pixel (8 sub-pixel bits); edge functions are
// exact 64-bit integers, so coverage never depends on rounding. Either winding is accepted.
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
  double inv_w = 0.0;  // depth key: larger is nearer
  double b[3] = {0.0, 0.0, 0.0};  // perspective-correct weights of v0, v1, v2 (sum to 1)
};

constexpr int subpixel_bits = 8;
constexpr int64_t subpixel_one = int64_t{1} << subpixel_bits;

namespace detail {
// std::llround (half away from zero) without the libm call: v - trunc(v) is exact for |v| < 2^52,
// far beyond the guard band's coordinates in 1/256 pixel.
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

template <class Fn>
void rasterize_triangle(const RasterVertex& a, const RasterVertex& b, const RasterVertex& c,
                        const PixelRect& rect, Fn&& fn) {
  const RasterVertex* v[3] = {&a, &b, &c};
  int64_t X[3], Y[3];
  for (int i = 0; i < 3; ++i) {
    X[i] = detail::snap_round(v[i]->x * double(subpixel_one));
    Y[i] = detail::snap_round(v[i]->y * double(subpixel_one));
  }
  int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
  if (area == 0) return;  // degenerate after snapping: covers no pixel centre
  int order[3] = {0, 1, 2};
  if (area < 0) {  // make the winding positive; the caller's weights follow the original order
    std::swap(order[1], order[2]);
    area = -area;
  }
  // Edge k runs from vertex order[k+1] to order[k+2]; its function weights vertex order[k].
  int64_t e_row[3], step_x[3], step_y[3], bias[3];
  const int64_t half = subpixel_one / 2;
  int64_t min_x = std::min({X[0], X[1], X[2]}), max_x = std::max({X[0], X[1], X[2]});
  int64_t min_y = std::min({Y[0], Y[1], Y[2]}), max_y = std::max({Y[0], Y[1], Y[2]});
  int px0 = int(std::max<int64_t>(rect.x0, detail::floor_div(min_x - half + subpixel_one - 1, subpixel_one)));
  int px1 = int(std::min<int64_t>(rect.x1 - 1, detail::floor_div(max_x - half, subpixel_one)));
  int py0 = int(std::max<int64_t>(rect.y0, detail::floor_div(min_y - half + subpixel_one - 1, subpixel_one)));
  int py1 = int(std::min<int64_t>(rect.y1 - 1, detail::floor_div(max_y - half, subpixel_one)));
  if (px0 > px1 || py0 > py1) return;
  const int64_t cx = int64_t(px0) * subpixel_one + half, cy = int64_t(py0) * subpixel_one + half;
  for (int k = 0; k < 3; ++k) {
    int i0 = order[(k + 1) % 3], i1 = order[(k + 2) % 3];
    int64_t dx = X[i1] - X[i0], dy = Y[i1] - Y[i0];
    // E(p) = dx * (p.y - y0) - dy * (p.x - x0); > 0 inside. Pixels on a non-top-left edge are
    // excluded by testing E - 1 >= 0 there instead of E >= 0.
    bias[k] = detail::is_top_left(dx, dy) ? 0 : 1;
    e_row[k] = dx * (cy - Y[i0]) - dy * (cx - X[i0]) - bias[k];
    step_x[k] = -dy * subpixel_one;
    step_y[k] = dx * subpixel_one;
  }
  const double inv_area = 1.0 / double(area);
  const double inv_w[3] = {v[order[0]]->inv_w, v[order[1]]->inv_w, v[order[2]]->inv_w};
  Fragment f;
  for (int y = py0; y <= py1; ++y) {
    // The covered pixels of a row are one span (the triangle is convex): find its ends from the
    // exact edge functions rather than test every pixel of the bounding box, which for a long thin
    // triangle is mostly empty. The test below still decides each pixel.
    int64_t first = 0, last = px1 - px0;
    for (int k = 0; k < 3; ++k) {
      if (step_x[k] > 0) {
        first = std::max(first, -detail::floor_div(e_row[k], step_x[k]));
      } else if (step_x[k] < 0) {
        last = std::min(last, e_row[k] < 0 ? int64_t{-1} : e_row[k] / -step_x[k]);
      } else if (e_row[k] < 0) {
        last = -1;
      }
    }
    int64_t e0 = e_row[0] + first * step_x[0], e1 = e_row[1] + first * step_x[1], e2 = e_row[2] + first * step_x[2];
    for (int x = px0 + int(first); x <= px0 + int(std::max(last, first - 1)); ++x) {
      if ((e0 | e1 | e2) >= 0) {
        // Undo the top-left bias (it only decides ties) before weighting.
        double l0 = double(e0 + bias[0]) * inv_area * inv_w[0];
        double l1 = double(e1 + bias[1]) * inv_area * inv_w[1];
        double l2 = double(e2 + bias[2]) * inv_area * inv_w[2];
        double sum = l0 + l1 + l2;
        f.x = x;
        f.y = y;
        f.inv_w = sum;
        double inv_sum = sum > 0.0 ? 1.0 / sum : 0.0;
        f.b[order[0]] = l0 * inv_sum;
        f.b[order[1]] = l1 * inv_sum;
        f.b[order[2]] = l2 * inv_sum;
        fn(f);
      }
      e0 += step_x[0];
      e1 += step_x[1];
      e2 += step_x[2];
    }
    e_row[0] += step_y[0];
    e_row[1] += step_y[1];
    e_row[2] += step_y[2];
  }
}

}  // namespace rr

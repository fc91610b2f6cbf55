// The plan grid the cells are derived on (cells_build.cpp): squares of side `square` metres from
// `origin`, row j spanning z in origin.y + [j, j + 1] * square. What a convex or simple plan polygon
// holds or meets, row by row, and the runs a band's squares are stored as. Internal to the cells.
#pragma once

#include "render/core/cells.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace rr::detail {

struct PlanGrid {
  Vec2 origin{0.0};
  double square = 0.0;
  int nx = 0, nz = 0;
  size_t at(int i, int j) const { return size_t(j) * size_t(nx) + size_t(i); }
  double x(int i) const { return origin.x + double(i) * square; }
  double z(int j) const { return origin.y + double(j) * square; }
  int column(double x_m) const;  // the column holding x (may lie outside [0, nx))
  int row(double z_m) const;
};

// Calls f(j, i0, i1) for every row j of the grid whose squares [i0, i1] (inclusive, clamped to the
// grid, i0 <= i1) lie wholly inside the convex polygon `poly` (either winding).
template <class F>
void convex_inside_rows(const PlanGrid& grid, std::span<const Vec2> poly, F&& f);

// Calls f(j, i0, i1) for every row j and the squares [i0, i1] (clamped) that the closed segment p-q
// widened by `margin` meets.
template <class F>
void segment_rows(const PlanGrid& grid, Vec2 p, Vec2 q, double margin, F&& f);

// Calls f(j, i0, i1) for every row j and the squares [i0, i1] (clamped) whose centres lie inside the
// simple polygon `poly` (even-odd rule).
template <class F>
void polygon_centre_rows(const PlanGrid& grid, std::span<const Vec2> poly, F&& f);

// The x-range [a, b] of the convex polygon on the line z = z_m; false when the line misses it.
bool convex_span(std::span<const Vec2> poly, double z_m, double& a, double& b);

// Per-square values of one band -> its runs (CellBand::row_first, runs).
void encode_runs(const PlanGrid& grid, const std::vector<uint32_t>& values, CellBand& band);
// The value of square (i, j) of a band (a cell, blocked_square or zone_bit | zone).
uint32_t run_value(const CellBand& band, int i, int j);

// ---- template definitions ----

template <class F>
void convex_inside_rows(const PlanGrid& grid, std::span<const Vec2> poly, F&& f) {
  double zlo = poly[0].y, zhi = poly[0].y;
  for (const Vec2& p : poly) zlo = std::min(zlo, p.y), zhi = std::max(zhi, p.y);
  const int j0 = std::max(0, grid.row(zlo)), j1 = std::min(grid.nz - 1, grid.row(zhi));
  for (int j = j0; j <= j1; ++j) {
    double a0, b0, a1, b1;
    if (!convex_span(poly, grid.z(j), a0, b0) || !convex_span(poly, grid.z(j + 1), a1, b1)) continue;
    const double lo = std::max(a0, a1), hi = std::min(b0, b1);
    // Squares [x(i), x(i) + square] within [lo, hi]: convexity puts the whole square inside.
    const int i0 = std::max(0, int(std::ceil((lo - grid.origin.x) / grid.square)));
    const int i1 = std::min(grid.nx - 1, int(std::floor((hi - grid.origin.x) / grid.square)) - 1);
    if (i0 <= i1) f(j, i0, i1);
  }
}

template <class F>
void segment_rows(const PlanGrid& grid, Vec2 p, Vec2 q, double margin, F&& f) {
  const int j0 = std::max(0, grid.row(std::min(p.y, q.y) - margin));
  const int j1 = std::min(grid.nz - 1, grid.row(std::max(p.y, q.y) + margin));
  for (int j = j0; j <= j1; ++j) {
    const double za = grid.z(j) - margin, zb = grid.z(j + 1) + margin;
    // The part of the segment with z in [za, zb], by its parameter range.
    double t0 = 0.0, t1 = 1.0;
    const double dz = q.y - p.y;
    if (dz != 0.0) {
      double ta = (za - p.y) / dz, tb = (zb - p.y) / dz;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
      if (t0 > t1) continue;
    }
    const double xa = p.x + t0 * (q.x - p.x), xb = p.x + t1 * (q.x - p.x);
    const int i0 = std::max(0, grid.column(std::min(xa, xb) - margin));
    const int i1 = std::min(grid.nx - 1, grid.column(std::max(xa, xb) + margin));
    if (i0 <= i1) f(j, i0, i1);
  }
}

template <class F>
void polygon_centre_rows(const PlanGrid& grid, std::span<const Vec2> poly, F&& f) {
  if (poly.size() < 3) return;
  double zlo = poly[0].y, zhi = poly[0].y;
  for (const Vec2& p : poly) zlo = std::min(zlo, p.y), zhi = std::max(zhi, p.y);
  const int j0 = std::max(0, grid.row(zlo)), j1 = std::min(grid.nz - 1, grid.row(zhi));
  std::vector<double> xs;
  for (int j = j0; j <= j1; ++j) {
    const double zc = grid.z(j) + 0.5 * grid.square;
    xs.clear();
    for (size_t k = 0; k < poly.size(); ++k) {
      const Vec2 a = poly[k], b = poly[(k + 1) % poly.size()];
      if ((a.y > zc) == (b.y > zc)) continue;  // half-open: a vertex on the line counts once
      xs.push_back(a.x + (zc - a.y) * (b.x - a.x) / (b.y - a.y));
    }
    std::sort(xs.begin(), xs.end());
    for (size_t k = 0; k + 1 < xs.size(); k += 2) {
      // Centres x(i) + square / 2 in [xs[k], xs[k + 1]).
      const int i0 = std::max(0, int(std::ceil((xs[k] - grid.origin.x) / grid.square - 0.5)));
      const int i1 = std::min(grid.nx - 1, int(std::ceil((xs[k + 1] - grid.origin.x) / grid.square - 0.5)) - 1);
      if (i0 <= i1) f(j, i0, i1);
    }
  }
}

}  // namespace rr::detail

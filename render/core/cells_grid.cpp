// The plan grid's non-template parts (see cells_grid.hpp).
#include "render/core/cells_grid.hpp"

#include <limits>

namespace rr::detail {

namespace {
int clamp_index(double v) {
  // Far outside the grid is as good as just outside it; keeps the cast defined.
  return int(std::clamp(std::floor(v), -1.0e9, 1.0e9));
}
}  // namespace

int PlanGrid::column(double x_m) const { return clamp_index((x_m - origin.x) / square); }
int PlanGrid::row(double z_m) const { return clamp_index((z_m - origin.y) / square); }

bool convex_span(std::span<const Vec2> poly, double z_m, double& a, double& b) {
  a = std::numeric_limits<double>::infinity(), b = -a;
  for (size_t k = 0; k < poly.size(); ++k) {
    const Vec2 p = poly[k], q = poly[(k + 1) % poly.size()];
    if (!((p.y <= z_m && z_m <= q.y) || (q.y <= z_m && z_m <= p.y))) continue;
    if (p.y == q.y) {
      a = std::min({a, p.x, q.x}), b = std::max({b, p.x, q.x});
      continue;
    }
    const double x = p.x + (z_m - p.y) * (q.x - p.x) / (q.y - p.y);
    a = std::min(a, x), b = std::max(b, x);
  }
  return a <= b;
}

void encode_runs(const PlanGrid& grid, const std::vector<uint32_t>& values, CellBand& band) {
  band.row_first.assign(size_t(grid.nz) + 1, 0);
  band.runs.clear();
  for (int j = 0; j < grid.nz; ++j) {
    band.row_first[size_t(j)] = uint32_t(band.runs.size());
    for (int i = 0; i < grid.nx; ++i) {
      const uint32_t v = values[grid.at(i, j)];
      if (i == 0 || band.runs.back().value != v) band.runs.push_back({uint32_t(i), v});
    }
  }
  band.row_first[size_t(grid.nz)] = uint32_t(band.runs.size());
  band.runs.shrink_to_fit();
}

uint32_t run_value(const CellBand& band, int i, int j) {
  const CellBand::Run* first = band.runs.data() + band.row_first[size_t(j)];
  const CellBand::Run* last = band.runs.data() + band.row_first[size_t(j) + 1];
  // The last run starting at or before column i.
  const CellBand::Run* it =
      std::upper_bound(first, last, uint32_t(i), [](uint32_t x, const CellBand::Run& r) { return x < r.x; });
  return (it - 1)->value;
}

}  // namespace rr::detail

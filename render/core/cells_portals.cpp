// build_cells, second half (see cells_build.hpp): the portals between the cells the first half found,
// each band's squares stored as runs, every polygon's cells and every hierarchy node's mask.
// Portals: an opening's hole (or the gaps around its drawn door leaf) between the cells beside its
// doorway zone; the squares where two cells of one enclosed region meet, as boxes from the band's
// floor to its ceiling; and per cell, the squares its floor does not cover (to and from the outside
// below), those its ceilings do not cover (up to the outside; all of it when they are not drawn) and
// all of it from above (a ceiling is not seen from above, so it hides nothing below it).
#include "render/core/cells_build.hpp"

#include <algorithm>
#include <limits>
#include <map>

namespace rr::detail {

namespace {

PortalShape quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d, bool horizontal = false) {
  PortalShape s;
  s.corners[0] = a, s.corners[1] = b, s.corners[2] = c, s.corners[3] = d;
  s.count = 4;
  s.horizontal = horizontal;
  return s;
}

PortalShape box(Vec3 lo, Vec3 hi) {
  PortalShape s;
  for (int k = 0; k < 8; ++k)
    s.corners[size_t(k)] = Vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
  s.count = 8;
  return s;
}

// A vertical rectangle u in [u0, u1], world y in [y0, y1] on a wall's centre plane, widened by the margin.
PortalShape centre_rect(const WallPlan& p, double u0, double u1, double y0, double y1) {
  const double m = cell_solid_margin_m;
  const Vec2 a = p.at(u0 - m, 0.0), b = p.at(u1 + m, 0.0);
  return quad({a.x, y0 - m, a.y}, {b.x, y0 - m, b.y}, {b.x, y1 + m, b.y}, {a.x, y1 + m, a.y});
}

struct Pending {
  std::vector<Portal> portals;
  std::vector<PortalShape>& shapes;
  size_t pairs = 0;

  // Both directions between a and b through the same shapes.
  void link(uint32_t a, uint32_t b, PortalKind kind, uint32_t first, uint32_t count, uint32_t alt_first = 0,
            uint32_t alt_count = 0, uint32_t leaf = no_object) {
    Portal p;
    p.kind = kind, p.first = first, p.count = count, p.alt_first = alt_first, p.alt_count = alt_count;
    p.leaf_object = leaf, p.pair = uint32_t(pairs++);
    p.from = a, p.to = b;
    portals.push_back(p);
    p.from = b, p.to = a;
    portals.push_back(p);
  }
  uint32_t add(const PortalShape& s) {
    shapes.push_back(s);
    return uint32_t(shapes.size() - 1);
  }
};

// The cells of square (i, j) of a band: its own, or a doorway zone's neighbours; none when blocked.
template <class F>
void for_square_cells(const BandBuild& band, const std::vector<Zone>& zones, size_t s, F&& f) {
  const uint32_t v = band.value[s];
  if (v == blocked_square) return;
  if (v & zone_bit) {
    for (uint32_t c : zones[v & ~zone_bit].cells) f(c);
    return;
  }
  f(v);
}

void opening_portals(const StaticGeometry& g, const CellsBuild& b, Pending& out) {
  for (const Zone& zone : b.zones) {
    if (zone.cells.size() < 2) continue;
    for (const ZoneOpening& zo : zone.openings) {
      const Wall& w = g.walls[zo.wall];
      const Opening& o = w.openings[zo.opening];
      const WallPlan p = wall_plan(w);
      const double lo = o.type == OpeningType::door ? 0.0 : o.sill;
      const double hi = std::min(w.height, lo + o.height);
      const double u0 = o.offset, u1 = o.offset + o.width, y0 = w.base + lo, y1 = w.base + hi;
      const uint32_t hole = out.add(centre_rect(p, u0, u1, y0, y1));
      // A drawn leaf across the centre plane leaves the gaps around it: a sight line crossing the plane
      // within the leaf's extent is inside the leaf, a closed box.
      auto leaf = std::lower_bound(b.leaves.begin(), b.leaves.end(), zo, [](const Leaf& l, const ZoneOpening& z) {
        return std::tie(l.wall, l.opening) < std::tie(z.wall, z.opening);
      });
      const bool closes = leaf != b.leaves.end() && leaf->wall == zo.wall && leaf->opening == zo.opening &&
                          leaf->v0 < 0.0 && leaf->v1 > 0.0 && leaf->u0 < leaf->u1 && leaf->y0 < leaf->y1;
      uint32_t first = hole, count = 1;
      if (closes) {
        first = uint32_t(out.shapes.size());
        if (leaf->u0 > u0) out.add(centre_rect(p, u0, leaf->u0, y0, y1));
        if (leaf->u1 < u1) out.add(centre_rect(p, leaf->u1, u1, y0, y1));
        if (leaf->y1 < y1) out.add(centre_rect(p, u0, u1, leaf->y1, y1));
        if (leaf->y0 > y0) out.add(centre_rect(p, u0, u1, y0, leaf->y0));
        count = uint32_t(out.shapes.size()) - first;
      }
      for (size_t x = 0; x < zone.cells.size(); ++x) {
        for (size_t y = x + 1; y < zone.cells.size(); ++y) {
          out.link(zone.cells[x], zone.cells[y], PortalKind::opening, first, count, hole, closes ? 1 : 0,
                   closes ? leaf->object : no_object);
        }
      }
    }
  }
}

// Where two cells' squares touch (8-neighbours), per tile: a box from the band's floor to its ceiling
// over both squares of every touching pair.
void boundary_portals(const CellsBuild& b, Pending& out) {
  const PlanGrid& grid = b.grid;
  const double m = cell_solid_margin_m;
  for (const BandBuild& band : b.bands) {
    std::map<std::array<uint32_t, 4>, std::array<int, 4>> pieces;  // (a, b, tile i, tile j) -> squares
    const int ni[4] = {1, 0, 1, -1}, nj[4] = {0, 1, 1, 1};
    for (int j = 0; j < grid.nz; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        const uint32_t v = band.value[grid.at(i, j)];
        if (v == blocked_square || (v & zone_bit)) continue;
        for (int k = 0; k < 4; ++k) {
          const int a = i + ni[k], c = j + nj[k];
          if (a < 0 || a >= grid.nx || c >= grid.nz) continue;
          const uint32_t w = band.value[grid.at(a, c)];
          if (w == blocked_square || (w & zone_bit) || w == v) continue;
          // Diagonal neighbours with both squares between them blocked meet inside a wall.
          if (k >= 2 && band.value[grid.at(a, j)] == blocked_square && band.value[grid.at(i, c)] == blocked_square)
            continue;
          const std::array<uint32_t, 4> key{std::min(v, w), std::max(v, w), uint32_t(i / cell_tile),
                                            uint32_t(j / cell_tile)};
          auto [it, fresh] = pieces.try_emplace(key, std::array<int, 4>{i, j, i, j});
          std::array<int, 4>& r = it->second;
          r = {std::min({r[0], i, a}), std::min(r[1], j), std::max({r[2], i, a}), std::max(r[3], c)};
        }
      }
    }
    for (const auto& [key, r] : pieces) {
      const Vec3 lo(grid.x(r[0]) - m, band.y0 - m, grid.z(r[1]) - m);
      const Vec3 hi(grid.x(r[2] + 1) + m, band.y1 + m, grid.z(r[3] + 1) + m);
      out.link(key[0], key[1], PortalKind::boundary, out.add(box(lo, hi)), 1);
    }
  }
}

// Seams of every barrier wall with openings. Its long faces are pieces whose corners beside an
// opening lie inside the edges of the full-height pieces next to them, and its top and bottom faces
// span pieces of the long faces: T-junctions, where vertex snapping may open a crack a sample sees
// through into the wall, whose other faces are seen from behind. Such a sight line can leave through
// any face of the wall: the seams link every cell beside it, and the outside (above and below).
// Thin boxes around the vertical seams; strips at the top and bottom edges, crossed downward and
// upward only (from below a top face is not drawn, so there is no seam there, and the converse).
void seam_portals(const StaticGeometry& g, const CellsBuild& b, const SceneCells& cells, Pending& out) {
  const double m = cell_solid_margin_m, piece = cell_tile * b.grid.square;
  size_t index = 0;
  for (const BandBuild& band : b.bands) {
    for (uint32_t wi : band.walls) {
      const SceneCells::WallCells& wc = cells.walls[index++];
      const Wall& w = g.walls[wi];
      if (w.openings.empty()) continue;
      const WallPlan p = wall_plan(w);
      std::vector<uint32_t> around(cells.wall_cells.begin() + wc.first, cells.wall_cells.begin() + wc.first + wc.count);
      if (around.empty() || around[0] != 0) around.insert(around.begin(), 0);
      const double y0 = w.base, y1 = w.base + w.height;
      const uint32_t vertical_first = uint32_t(out.shapes.size());
      for (const Opening& o : w.openings) {
        for (double u : {o.offset, o.offset + o.width}) {
          for (double v : {-p.half, p.half}) {
            const Vec2 c = p.at(u, v);
            out.add(box({c.x - m, y0 - m, c.y - m}, {c.x + m, y1 + m, c.y + m}));
          }
        }
      }
      const uint32_t vertical_count = uint32_t(out.shapes.size()) - vertical_first;
      // Along the length, past the ends as far as a mitre reaches (7.6 half thicknesses at 15 degrees).
      const double from = -4.0 * w.thickness, to = p.length + 4.0 * w.thickness;
      const int n = std::max(1, int(std::ceil((to - from) / piece)));
      uint32_t strips[2] = {0, 0};
      for (int edge = 0; edge < 2; ++edge) {
        const double y = edge == 0 ? y1 : y0;
        strips[edge] = uint32_t(out.shapes.size());
        for (int k = 0; k < n; ++k) {
          const double u0 = from + (to - from) * k / n, u1 = from + (to - from) * (k + 1) / n;
          for (double v : {-p.half, p.half}) {
            const Vec2 a = p.at(u0, v - m), bb = p.at(u1, v - m), c = p.at(u1, v + m), d = p.at(u0, v + m);
            out.add(quad({a.x, y, a.y}, {bb.x, y, bb.y}, {c.x, y, c.y}, {d.x, y, d.y}, true));
          }
        }
      }
      const uint32_t strip_count = uint32_t(2 * n);
      for (size_t x = 0; x < around.size(); ++x) {
        for (size_t y = x + 1; y < around.size(); ++y) {
          out.link(around[x], around[y], PortalKind::seam, vertical_first, vertical_count);
          out.link(around[x], around[y], PortalKind::seam, strips[0], strip_count);
          out.portals[out.portals.size() - 2].vertical = out.portals.back().vertical = -1;
          out.link(around[x], around[y], PortalKind::seam, strips[1], strip_count);
          out.portals[out.portals.size() - 2].vertical = out.portals.back().vertical = +1;
        }
      }
    }
  }
}

// The squares (i, j) of one cell meeting a condition, as rectangles cut at tiles: horizontal quads at
// y. Returns the number of quads added.
uint32_t add_rects(const PlanGrid& grid, const std::vector<std::pair<int, int>>& squares, double y, Pending& out) {
  const size_t first = out.shapes.size();
  const double m = cell_solid_margin_m;
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> tiles;  // tile -> (row, column)
  for (const auto& [i, j] : squares) tiles[{j / cell_tile, i / cell_tile}].push_back({j, i});
  auto emit = [&](std::pair<int, int> run, int j0, int j1) {
    const double x0 = grid.x(run.first) - m, x1 = grid.x(run.second + 1) + m;
    const double z0 = grid.z(j0) - m, z1 = grid.z(j1 + 1) + m;
    out.add(quad({x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}, true));
  };
  for (auto& [tile, list] : tiles) {
    std::sort(list.begin(), list.end());
    // Each row's runs; a run equal to one of the row before extends that one's rectangle.
    std::map<std::pair<int, int>, int> open;  // run (i0, i1) -> its rectangle's first row
    int previous = 0;
    for (size_t k = 0; k < list.size();) {
      const int j = list[k].first;
      std::map<std::pair<int, int>, int> next;
      for (; k < list.size() && list[k].first == j;) {
        size_t e = k;
        while (e + 1 < list.size() && list[e + 1].first == j && list[e + 1].second == list[e].second + 1) ++e;
        const std::pair<int, int> run{list[k].second, list[e].second};
        const auto it = open.find(run);
        next[run] = it != open.end() && previous == j - 1 ? it->second : j;
        k = e + 1;
      }
      for (const auto& [run, j0] : open) {
        const auto it = next.find(run);
        if (it == next.end() || it->second != j0) emit(run, j0, previous);
      }
      open.swap(next);
      previous = j;
    }
    for (const auto& [run, j0] : open) emit(run, j0, previous);
  }
  return uint32_t(out.shapes.size() - first);
}

void vertical_portals(const CellsBuild& b, const std::vector<Cell>& cells, Pending& out) {
  const PlanGrid& grid = b.grid;
  for (size_t k = 0; k < b.bands.size(); ++k) {
    const BandBuild& band = b.bands[k];
    // Per enclosed cell of the band: its squares (a doorway's count for every cell beside it).
    std::map<uint32_t, std::vector<std::pair<int, int>>> area, floor_gaps, ceiling_gaps;
    for (int j = 0; j < grid.nz; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        const size_t s = grid.at(i, j);
        for_square_cells(band, b.zones, s, [&](uint32_t c) {
          if (cells[c].kind != CellKind::enclosed) return;
          area[c].push_back({i, j});
          if (!band.floor_sealed[s]) floor_gaps[c].push_back({i, j});
          if (!band.ceiling_sealed[s]) ceiling_gaps[c].push_back({i, j});
        });
      }
    }
    for (const auto& [c, squares] : area) {
      // Through the ceiling plane: down into the cell from the outside above always (a ceiling is
      // one-sided), up out of it through the gaps between its drawn ceilings, or anywhere when the
      // band's ceilings are not all drawn.
      const uint32_t all_first = uint32_t(out.shapes.size());
      const uint32_t all_count = add_rects(grid, squares, band.y1, out);
      const uint32_t gap_first = uint32_t(out.shapes.size());
      const auto gaps = ceiling_gaps.find(c);
      const uint32_t gap_count = gaps == ceiling_gaps.end() ? 0 : add_rects(grid, gaps->second, band.y1, out);
      out.link(0, c, PortalKind::ceiling, all_first, all_count);
      out.portals[out.portals.size() - 2].vertical = -1;
      Portal& up = out.portals.back();
      up.vertical = +1;
      up.first = gap_first, up.count = gap_count, up.alt_first = all_first, up.alt_count = all_count;
      up.ceiling_band = int(k);
      // Through the floor plane, both ways where no floor covers it.
      const auto floor = floor_gaps.find(c);
      if (floor == floor_gaps.end()) continue;
      const uint32_t first = uint32_t(out.shapes.size());
      const uint32_t count = add_rects(grid, floor->second, band.y0, out);
      out.link(c, 0, PortalKind::floor, first, count);
      out.portals[out.portals.size() - 2].vertical = -1;
      out.portals.back().vertical = +1;
    }
  }
}

// The cells beside each barrier wall: of the squares around its solid's bounds.
void wall_cells(const CellsBuild& b, SceneCells& out) {
  const PlanGrid& grid = b.grid;
  for (size_t k = 0; k < b.bands.size(); ++k) {
    const BandBuild& band = b.bands[k];
    for (size_t w = 0; w < band.walls.size(); ++w) {
      SceneCells::WallCells wc;
      wc.band = int(k), wc.lo = band.wall_lo[w], wc.hi = band.wall_hi[w];
      wc.first = uint32_t(out.wall_cells.size());
      std::vector<uint32_t> list;
      const int i0 = std::max(0, grid.column(wc.lo.x) - 1), i1 = std::min(grid.nx - 1, grid.column(wc.hi.x) + 1);
      const int j0 = std::max(0, grid.row(wc.lo.y) - 1), j1 = std::min(grid.nz - 1, grid.row(wc.hi.y) + 1);
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i)
          for_square_cells(band, b.zones, grid.at(i, j), [&](uint32_t c) { list.push_back(c); });
      }
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
      out.wall_cells.insert(out.wall_cells.end(), list.begin(), list.end());
      wc.count = uint32_t(list.size());
      out.walls.push_back(wc);
    }
  }
}

}  // namespace

void add_portals(const StaticGeometry& geometry, const CellsBuild& b, SceneCells& out) {
  out.origin = b.grid.origin, out.square = b.grid.square, out.nx = b.grid.nx, out.nz = b.grid.nz;
  for (const BandBuild& band : b.bands) {
    CellBand stored;
    stored.y0 = band.y0, stored.y1 = band.y1;
    encode_runs(b.grid, band.value, stored);
    out.bands.push_back(std::move(stored));
  }
  out.zone_first.push_back(0);
  for (const Zone& z : b.zones) {
    out.zone_cells.insert(out.zone_cells.end(), z.cells.begin(), z.cells.end());
    out.zone_first.push_back(uint32_t(out.zone_cells.size()));
  }
  wall_cells(b, out);
  Pending pending{{}, out.shapes};
  opening_portals(geometry, b, pending);
  boundary_portals(b, pending);
  vertical_portals(b, out.cells, pending);
  seam_portals(geometry, b, out, pending);
  std::stable_sort(pending.portals.begin(), pending.portals.end(),
                   [](const Portal& x, const Portal& y) { return x.from < y.from; });
  out.portals = std::move(pending.portals);
  out.undirected_portals = pending.pairs;
  out.cell_portals.assign(out.cells.size() + 1, 0);
  for (const Portal& p : out.portals) ++out.cell_portals[p.from + 1];
  for (size_t c = 0; c < out.cells.size(); ++c) out.cell_portals[c + 1] += out.cell_portals[c];
}

void assign_polygons(const PolygonSoup& soup, const SceneHierarchy& hierarchy, SceneCells& out) {
  std::map<std::vector<uint32_t>, uint32_t> sets;
  out.set_first.assign(1, 0);
  out.set_cells.clear();
  auto set_of = [&](const std::vector<uint32_t>& cells) {
    auto [it, fresh] = sets.try_emplace(cells, uint32_t(sets.size()));
    if (fresh) {
      out.set_cells.insert(out.set_cells.end(), cells.begin(), cells.end());
      out.set_first.push_back(uint32_t(out.set_cells.size()));
    }
    return it->second;
  };
  std::vector<uint32_t> all(out.cells.size());
  for (uint32_t c = 0; c < all.size(); ++c) all[c] = c;
  out.polygon_set.assign(soup.polygons.size(), 0);
  const double tol = cell_height_tolerance_m;
  std::vector<uint32_t> cells;
  for (size_t p = 0; p < soup.polygons.size(); ++p) {
    cells.clear();
    Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const Vec3& q : soup.points(soup.polygons[p])) lo = glm::min(lo, q), hi = glm::max(hi, q);
    if (out.bands.empty()) {
      out.polygon_set[p] = set_of({0});
      continue;
    }
    // Beyond the bands in height (below, above, or between two levels) is the outside.
    bool outside = lo.y < out.bands.front().y0 - tol || hi.y > out.bands.back().y1 + tol;
    for (size_t k = 0; k + 1 < out.bands.size(); ++k) {
      outside = outside || (hi.y > out.bands[k].y1 + tol && lo.y < out.bands[k + 1].y0 - tol);
    }
    // One square around the polygon's plan bounds: a polygon on a square's edge belongs to both sides.
    const int i0 = int(std::floor((lo.x - out.origin.x) / out.square)) - 1;
    const int i1 = int(std::floor((hi.x - out.origin.x) / out.square)) + 1;
    const int j0 = int(std::floor((lo.z - out.origin.y) / out.square)) - 1;
    const int j1 = int(std::floor((hi.z - out.origin.y) / out.square)) + 1;
    outside = outside || i0 < 0 || j0 < 0 || i1 >= out.nx || j1 >= out.nz;
    if (outside) cells.push_back(0);
    for (const CellBand& band : out.bands) {
      if (hi.y < band.y0 - tol || lo.y > band.y1 + tol) continue;
      for (int j = std::max(0, j0); j <= std::min(out.nz - 1, j1); ++j) {
        const CellBand::Run* first = band.runs.data() + band.row_first[size_t(j)];
        const CellBand::Run* last = band.runs.data() + band.row_first[size_t(j) + 1];
        const uint32_t x0 = uint32_t(std::max(0, i0)), x1 = uint32_t(std::min(out.nx - 1, i1));
        const CellBand::Run* r =
            std::upper_bound(first, last, x0, [](uint32_t x, const CellBand::Run& run) { return x < run.x; }) - 1;
        for (; r != last && r->x <= x1; ++r) {
          if (r->value == blocked_square) continue;
          if (r->value & zone_bit) {
            const uint32_t z = r->value & ~zone_bit;
            cells.insert(cells.end(), out.zone_cells.begin() + out.zone_first[z],
                         out.zone_cells.begin() + out.zone_first[z + 1]);
          } else {
            cells.push_back(r->value);
          }
        }
      }
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    out.polygon_set[p] = set_of(cells.empty() ? all : cells);
  }
  // Node masks bottom-up: a node's children follow it, so a reverse pass sees them first.
  out.node_mask.assign(hierarchy.nodes.size(), 0);
  for (size_t n = hierarchy.nodes.size(); n-- > 0;) {
    const HierarchyNode& node = hierarchy.nodes[n];
    uint64_t mask = 0;
    if (node.leaf()) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        for (uint32_t c : out.cells_of_polygon(hierarchy.polygons[k])) mask |= uint64_t(1) << (c % 64);
      }
    } else {
      mask = out.node_mask[n + 1] | out.node_mask[node.second];
    }
    out.node_mask[n] = mask;
  }
}

}  // namespace rr::detail

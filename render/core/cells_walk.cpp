// The portal walk and what a frame reads of it (see cells.hpp): locating a viewpoint's cells, the
// frame's conditions (which walls, ceilings and door leaves it draws), the walk itself, and the filter
// the occlusion walk applies. One thread; the result does not depend on the thread count.
#include "render/core/cells.hpp"

#include "render/core/cells_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace rr {

namespace {

// A viewpoint this close to a band's floor or ceiling plane (metres) may look through it either way.
constexpr double plane_tolerance_m = 1e-3;
// The walk stops and reaches everything past this many portal crossings (it never comes near on homes).
constexpr size_t max_steps = 200000;

ViewRegion intersect(const ViewRegion& a, const ViewRegion& b) {
  return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}
ViewRegion unite(const ViewRegion& a, const ViewRegion& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}
bool contains(const ViewRegion& outer, const ViewRegion& inner) {
  return outer.x0 <= inner.x0 && outer.y0 <= inner.y0 && inner.x1 <= outer.x1 && inner.y1 <= outer.y1;
}

// Sight lines within this depth of the eye's plane cross portals within a few times this distance of
// the eye, whose cells are all start cells (locate_cells looks one grid square around): the part of a
// shape nearer than this is left out of its image, which then stays bounded.
constexpr double near_depth = 1e-5;

// Where a shape's part at depth >= near_depth meets the view plane; false when it has none. A sight
// line from the eye has depth > 0 past the eye, so the part behind is never crossed.
bool project_shape(const PortalShape& s, const Mat4& clip_from_world, ViewRegion& out) {
  out = {1e300, 1e300, -1e300, -1e300};
  std::array<Vec4, 8> c;
  for (int k = 0; k < s.count; ++k) c[size_t(k)] = clip_from_world * Vec4(s.corners[size_t(k)], 1.0);
  bool any = false;
  auto add = [&](const Vec4& p) {
    const double x = p.x / p.w, y = p.y / p.w;
    out.x0 = std::min(out.x0, x), out.x1 = std::max(out.x1, x);
    out.y0 = std::min(out.y0, y), out.y1 = std::max(out.y1, y);
    any = true;
  };
  auto edge = [&](const Vec4& a, const Vec4& b) {  // where a-b crosses depth near_depth
    if ((a.w >= near_depth) == (b.w >= near_depth)) return;
    add(a + (b - a) * ((near_depth - a.w) / (b.w - a.w)));
  };
  for (int k = 0; k < s.count; ++k) {
    if (c[size_t(k)].w >= near_depth) add(c[size_t(k)]);
  }
  if (s.count == 4) {
    for (size_t k = 0; k < 4; ++k) edge(c[k], c[(k + 1) % 4]);
  } else {  // a box: corners differing in one bit share an edge
    for (size_t k = 0; k < 8; ++k) {
      for (size_t bit : {1u, 2u, 4u}) {
        if (!(k & bit)) edge(c[k], c[k | bit]);
      }
    }
  }
  return any;
}

}  // namespace

size_t SceneCells::bytes() const {
  size_t n = sizeof(SceneCells);
  for (const CellBand& b : bands) n += sizeof(CellBand) + b.row_first.capacity() * 4 + b.runs.capacity() * 8;
  n += cells.capacity() * sizeof(Cell) + portals.capacity() * sizeof(Portal) + cell_portals.capacity() * 4;
  n += shapes.capacity() * sizeof(PortalShape) + (zone_first.capacity() + zone_cells.capacity()) * 4;
  n += (polygon_set.capacity() + set_first.capacity() + set_cells.capacity()) * 4 + node_mask.capacity() * 8;
  n += barrier_objects.capacity() * 4 + walls.capacity() * sizeof(WallCells) + wall_cells.capacity() * 4;
  for (const auto& c : band_ceilings) n += sizeof(c) + c.capacity() * 4;
  return n;
}

std::vector<uint32_t> locate_cells(const SceneCells& cells, Vec3 point, double reach) {
  std::vector<uint32_t> out;
  if (!cells.derived()) return {0};
  const detail::PlanGrid grid{cells.origin, cells.square, cells.nx, cells.nz};
  const double r = reach + cells.square;
  const Vec2 plan(point.x, point.z);
  bool in_band = false;
  for (size_t b = 0; b < cells.bands.size(); ++b) {
    const CellBand& band = cells.bands[b];
    const double tol = std::max(reach, plane_tolerance_m);
    if (point.y < band.y0 - tol || point.y > band.y1 + tol) continue;
    in_band = true;
    if (std::abs(point.y - band.y0) <= tol || std::abs(point.y - band.y1) <= tol) out.push_back(0);
    const int i = grid.column(point.x), j = grid.row(point.z);
    if (point.y >= band.y0 && point.y <= band.y1 && i >= 0 && j >= 0 && i < grid.nx && j < grid.nz &&
        detail::run_value(band, i, j) == blocked_square) {
      return {};  // inside a wall: its faces are seen from behind, so it hides nothing
    }
    for (int y = grid.row(point.z - r); y <= grid.row(point.z + r); ++y) {
      for (int x = grid.column(point.x - r); x <= grid.column(point.x + r); ++x) {
        if (x < 0 || y < 0 || x >= grid.nx || y >= grid.nz) {
          out.push_back(0);
          continue;
        }
        const uint32_t v = detail::run_value(band, x, y);
        if (v == blocked_square) continue;
        if (v & zone_bit) {
          const uint32_t z = v & ~zone_bit;
          out.insert(out.end(), cells.zone_cells.begin() + cells.zone_first[z],
                     cells.zone_cells.begin() + cells.zone_first[z + 1]);
        } else {
          out.push_back(v);
        }
      }
    }
    for (const SceneCells::WallCells& w : cells.walls) {
      if (w.band != int(b)) continue;
      const Vec2 d = glm::max(glm::max(w.lo - plan, plan - w.hi), Vec2(0.0));
      if (glm::length(d) > reach) continue;
      out.insert(out.end(), cells.wall_cells.begin() + w.first, cells.wall_cells.begin() + w.first + w.count);
    }
  }
  if (!in_band) out.push_back(0);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

CellViewpoint cell_viewpoint(const ViewTransform& view) {
  CellViewpoint viewpoint;
  viewpoint.eye = view.eye;
  const double tan_y = 1.0 / view.clip_from_view[1][1], tan_x = 1.0 / view.clip_from_view[0][0];
  viewpoint.reach = view.near * std::sqrt(1.0 + tan_x * tan_x + tan_y * tan_y);
  viewpoint.clip_from_world = view.clip_from_world;
  viewpoint.margin_x = 4.0 / double(view.width), viewpoint.margin_y = 4.0 / double(view.height);
  return viewpoint;
}

CellConditions cell_conditions(const SceneCells& cells, std::vector<uint8_t> object_drawn) {
  CellConditions c;
  c.object_drawn = std::move(object_drawn);
  auto drawn = [&](uint32_t o) { return c.object_drawn.empty() || (o < c.object_drawn.size() && c.object_drawn[o]); };
  for (uint32_t o : cells.barrier_objects) c.valid = c.valid && drawn(o);
  c.ceilings_drawn.assign(cells.band_ceilings.size(), 1);
  for (size_t b = 0; b < cells.band_ceilings.size(); ++b) {
    for (uint32_t o : cells.band_ceilings[b]) c.ceilings_drawn[b] = c.ceilings_drawn[b] && drawn(o);
  }
  return c;
}

ViewRegion bounding_region(const CellWalk& walk, size_t c) {
  const CellRegions& r = walk.regions[c];
  if (r.count == 0) return {-1e30, -1e30, 1e30, 1e30};
  ViewRegion out = r.region[0];
  for (size_t i = 1; i < r.count; ++i) {
    out.x0 = std::min(out.x0, r.region[i].x0), out.y0 = std::min(out.y0, r.region[i].y0);
    out.x1 = std::max(out.x1, r.region[i].x1), out.y1 = std::max(out.y1, r.region[i].y1);
  }
  return out;
}

double area(const ViewRegion& r) { return r.empty() ? 0.0 : (r.x1 - r.x0) * (r.y1 - r.y0); }

void walk_cells(const SceneCells& cells, const CellConditions& conditions, const CellViewpoint& view, CellWalk& out) {
  const size_t n = cells.cells.size();
  out.reached.assign(n, 0);
  out.regions.assign(n, CellRegions{});
  out.cells_visited = out.portals_walked = 0;
  out.everything = false;
  auto reach_all = [&]() {
    out.everything = true;
    out.reached.assign(n, 1);
    CellRegions all;
    all.region[0] = view.region, all.count = 1;
    out.regions.assign(n, all);
    out.cells_visited = n;
  };
  if (!cells.derived()) return reach_all();  // one cell: nothing to walk
  const std::vector<uint32_t> start = locate_cells(cells, view.eye, view.reach);
  if (start.empty()) return reach_all();
  // A sight line's later points lie above every horizontal portal it crossed going up, and below
  // every one it crossed going down: the walk carries that height range with the region.
  struct Item {
    uint32_t cell = 0;
    ViewRegion region;
    double y0 = -std::numeric_limits<double>::infinity(), y1 = std::numeric_limits<double>::infinity();
    bool holds(const Item& o) const { return contains(region, o.region) && y0 <= o.y0 && o.y1 <= y1; }
  };
  struct Explored {
    std::array<Item, cell_regions_max> items;
    size_t count = 0;
  };
  thread_local std::vector<Explored> kept_explored;
  thread_local std::vector<Item> kept_stack;
  std::vector<Explored>& explored = kept_explored;
  std::vector<Item>& stack = kept_stack;
  explored.assign(n, Explored{});
  stack.clear();
  // Reaching a cell: walked on unless an item already walked from it holds this one (a larger region,
  // a wider height range). Past a few items the two whose bounds grow least are merged, and the merged
  // item is walked: every item ever reached stays held by one that is walked.
  auto reach = [&](const Item& item) {
    Explored& e = explored[item.cell];
    for (size_t k = 0; k < e.count; ++k) {
      if (e.items[k].holds(item)) return false;
    }
    if (!out.reached[item.cell]) out.reached[item.cell] = 1, ++out.cells_visited;
    if (e.count < cell_regions_max) {
      e.items[e.count++] = item;
      stack.push_back(item);
      return true;
    }
    std::array<Item, cell_regions_max + 1> all;
    std::copy(e.items.begin(), e.items.end(), all.begin());
    all[cell_regions_max] = item;
    size_t best_a = 0, best_b = 1;
    double best = std::numeric_limits<double>::infinity();
    for (size_t a = 0; a < all.size(); ++a) {
      for (size_t b = a + 1; b < all.size(); ++b) {
        const double growth = area(unite(all[a].region, all[b].region)) - area(all[a].region) - area(all[b].region);
        if (growth < best) best = growth, best_a = a, best_b = b;
      }
    }
    Item merged = all[best_a];
    merged.region = unite(all[best_a].region, all[best_b].region);
    merged.y0 = std::min(all[best_a].y0, all[best_b].y0), merged.y1 = std::max(all[best_a].y1, all[best_b].y1);
    size_t count = 0;
    for (size_t k = 0; k < all.size(); ++k) {
      if (k != best_a && k != best_b) e.items[count++] = all[k];
    }
    e.items[count++] = merged;
    e.count = count;
    stack.push_back(merged);
    return true;
  };
  for (uint32_t c : start) reach(Item{c, view.region});
  auto drawn = [&](uint32_t o) {
    return conditions.object_drawn.empty() || (o < conditions.object_drawn.size() && conditions.object_drawn[o]);
  };
  size_t steps = 0;
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const uint32_t c = item.cell;
    for (uint32_t k = cells.cell_portals[c]; k < cells.cell_portals[c + 1]; ++k) {
      const Portal& p = cells.portals[k];
      if (p.pair == conditions.dropped_pair) continue;
      const bool alternative = (p.leaf_object != no_object && !drawn(p.leaf_object)) ||
                               (p.ceiling_band >= 0 && !conditions.ceilings_drawn[size_t(p.ceiling_band)]);
      const uint32_t first = alternative ? p.alt_first : p.first, count = alternative ? p.alt_count : p.count;
      for (uint32_t s = first; s < first + count; ++s) {
        const PortalShape& shape = cells.shapes[s];
        double lo = shape.corners[0].y, hi = lo;
        for (int q = 1; q < shape.count; ++q) {
          lo = std::min(lo, shape.corners[size_t(q)].y), hi = std::max(hi, shape.corners[size_t(q)].y);
        }
        if (hi < item.y0 - plane_tolerance_m || lo > item.y1 + plane_tolerance_m) continue;
        Item next = item;
        next.cell = p.to;
        if (shape.horizontal) {
          // A straight line crosses a horizontal plane only moving away from the eye's side of it.
          const double y = shape.corners[0].y;
          if (p.vertical > 0 && !(view.eye.y < y + plane_tolerance_m)) continue;
          if (p.vertical < 0 && !(view.eye.y > y - plane_tolerance_m)) continue;
          if (view.eye.y < y - plane_tolerance_m) next.y0 = std::max(next.y0, y - plane_tolerance_m);
          if (view.eye.y > y + plane_tolerance_m) next.y1 = std::min(next.y1, y + plane_tolerance_m);
        }
        ViewRegion image;
        if (!project_shape(shape, view.clip_from_world, image)) continue;
        image.x0 -= view.margin_x, image.x1 += view.margin_x, image.y0 -= view.margin_y, image.y1 += view.margin_y;
        next.region = intersect(item.region, image);
        if (next.region.empty()) continue;
        if (reach(next)) ++out.portals_walked;
        if (++steps > max_steps) return reach_all();
      }
    }
  }
  for (size_t c = 0; c < n; ++c) {
    CellRegions& r = out.regions[c];
    for (size_t k = 0; k < explored[c].count; ++k) r.region[r.count++] = explored[c].items[k].region;
  }
}

void make_cell_filter(const SceneCells& cells, const CellWalk& walk, int width, int height, CellFilter& out) {
  out.cells = &cells, out.walk = &walk;
  out.reached_bits = 0;
  for (auto& r : out.rects) r.count = 0;
  for (size_t c = 0; c < walk.reached.size(); ++c) {
    if (!walk.reached[c]) continue;
    const size_t bit = c % 64;
    CellFilter::Rects& rects = out.rects[bit];
    out.reached_bits |= uint64_t(1) << bit;
    for (size_t k = 0; k < walk.regions[c].count; ++k) {
      const ViewRegion& v = walk.regions[c].region[k];
      // NDC -> pixels (y down), one pixel wider each way.
      const std::array<int, 4> r{
          int(std::floor((v.x0 + 1.0) * 0.5 * width)) - 1, int(std::floor((1.0 - v.y1) * 0.5 * height)) - 1,
          int(std::ceil((v.x1 + 1.0) * 0.5 * width)) + 1, int(std::ceil((1.0 - v.y0) * 0.5 * height)) + 1};
      if (rects.count < cell_regions_max) {
        rects.rect[rects.count++] = r;
        continue;
      }
      // More than a bit holds (cells sharing it): all into the bounds of the first.
      std::array<int, 4>& m = rects.rect[0];
      for (size_t q = 1; q < rects.count; ++q) {
        const std::array<int, 4>& o = rects.rect[q];
        m = {std::min(m[0], o[0]), std::min(m[1], o[1]), std::max(m[2], o[2]), std::max(m[3], o[3])};
      }
      m = {std::min(m[0], r[0]), std::min(m[1], r[1]), std::max(m[2], r[2]), std::max(m[3], r[3])};
      rects.count = 1;
    }
  }
}

bool CellFilter::polygon_reached(uint32_t hierarchy_polygon) const {
  for (uint32_t c : cells->cells_of_polygon(hierarchy_polygon)) {
    if (walk->reached[c]) return true;
  }
  return false;
}

bool CellFilter::node_reached(uint32_t node, bool testable, int x0, int y0, int x1, int y1) const {
  uint64_t bits = cells->node_mask[node] & reached_bits;
  if (!bits || !testable) return bits != 0;
  while (bits) {
    const int bit = __builtin_ctzll(bits);
    bits &= bits - 1;
    const Rects& rs = rects[size_t(bit)];
    for (size_t k = 0; k < rs.count; ++k) {
      const std::array<int, 4>& r = rs.rect[k];
      if (x0 < r[2] && r[0] < x1 && y0 < r[3] && r[1] < y1) return true;
    }
  }
  return false;
}

}  // namespace rr

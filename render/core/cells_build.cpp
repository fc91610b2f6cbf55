// build_cells, first half (see cells.hpp, docs/culling.md "Cells"): bands from the levels, a plan
// grid, and per band each square classified: blocked (wholly inside a wall that spans the band, away
// from its openings), a doorway zone (inside a wall's thickness at an opening), or free. Free squares
// are flooded (4-connected); those that reach the grid's border are the outside, every other region
// is enclosed, split into one cell per room that holds at least 1 m^2 of it (its other squares go to
// the nearest room). Which squares a floor or a ceiling covers whole is noted for the vertical
// portals. cells_portals.cpp makes the portals and assigns the polygons.
#include "render/core/cells_build.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <tuple>

namespace rr {

namespace {

using detail::BandBuild;
using detail::cell_height_tolerance_m;
using detail::cell_solid_margin_m;
using detail::CellsBuild;
using detail::PlanGrid;
using detail::wall_plan;
using detail::WallPlan;
using detail::Zone;

constexpr uint32_t free_square = 0x7FFFFFFEu;  // during the build: not yet given a cell
// Square side: a third of the thinnest barrier wall (3 cm or thicker), so that every barrier holds a
// connected run of blocked squares at any angle, within these bounds. Free squares are flooded
// 4-connected: two free squares that touch only at a corner, the other two squares there blocked,
// meet at a point that lies inside a wall by the margin, so nothing passes between them there. (An
// 8-connected flood leaks through the corner where two walls overlap end to end without a mitre.)
constexpr double min_square_m = 0.01, max_square_m = 0.05, thin_wall_m = 0.03;
constexpr double max_band_squares = 4.0 * 1024.0 * 1024.0;  // beyond it the squares grow (walls may then leak)
constexpr double min_room_area_m2 = 1.0;

std::vector<BandBuild> make_bands(const StaticGeometry& g) {
  std::vector<BandBuild> bands;
  if (!g.levels.empty()) {
    std::vector<int> order;
    for (size_t l = 0; l < g.levels.size(); ++l) {
      if (g.levels[l].viewable && g.levels[l].height > 0.0) order.push_back(int(l));
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return g.levels[size_t(a)].elevation < g.levels[size_t(b)].elevation; });
    for (int l : order) {
      const Level& level = g.levels[size_t(l)];
      const double y0 = level.elevation, y1 = level.elevation + level.height;
      if (!bands.empty() && y0 < bands.back().y1 - cell_height_tolerance_m) {  // overlapping levels: one band
        bands.back().y1 = std::max(bands.back().y1, y1);
        bands.back().levels.push_back(l);
        continue;
      }
      BandBuild band;
      band.y0 = y0, band.y1 = y1, band.levels = {l};
      bands.push_back(std::move(band));
    }
    return bands;
  }
  double y0 = std::numeric_limits<double>::infinity(), y1 = -y0;
  for (const Room& r : g.rooms) y0 = std::min(y0, r.elevation), y1 = std::max(y1, r.elevation + r.ceiling_height);
  if (g.rooms.empty()) {
    for (const Wall& w : g.walls) y0 = std::min(y0, w.base), y1 = std::max(y1, w.base + w.height);
  }
  if (y0 < y1) {
    BandBuild band;
    band.y0 = y0, band.y1 = y1;
    bands.push_back(std::move(band));
  }
  return bands;
}

bool on_band(const BandBuild& band, int level, double y) {
  if (band.levels.empty() || level < 0) return y >= band.y0 - cell_height_tolerance_m && y <= band.y1;
  return std::find(band.levels.begin(), band.levels.end(), level) != band.levels.end();
}

// The rectangle u in [u0, u1], v in [v0, v1] of a wall's frame, in the plan.
std::array<Vec2, 4> wall_rect(const WallPlan& p, double u0, double u1, double v0, double v1) {
  return {p.at(u0, v0), p.at(u1, v0), p.at(u1, v1), p.at(u0, v1)};
}

using Poly = std::vector<Vec2>;

// A convex piece of the plan inside which a wall is solid at every height it spans.
struct SolidPiece {
  Poly corners;
  Vec2 lo, hi;
  double sign = 1.0;  // +1 when the corners turn counter-clockwise in (x, z)
  uint32_t wall = 0;
};

// The part of convex `poly` on the side of the line a -> b where cross(b - a, p - a) * sign >= 0.
Poly clip(const Poly& poly, Vec2 a, Vec2 b, double sign) {
  Poly out;
  auto side = [&](Vec2 p) { return sign * ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)); };
  for (size_t k = 0; k < poly.size(); ++k) {
    const Vec2 p = poly[k], q = poly[(k + 1) % poly.size()];
    const double sp = side(p), sq = side(q);
    if (sp >= 0.0) out.push_back(p);
    if ((sp >= 0.0) != (sq >= 0.0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
  }
  return out;
}

double signed_area(const Poly& p) {
  double a = 0.0;
  for (size_t k = 0; k < p.size(); ++k) {
    const Vec2 u = p[k], v = p[(k + 1) % p.size()];
    a += u.x * v.y - u.y * v.x;
  }
  return 0.5 * a;
}

// Each barrier wall's solid pieces: its top faces as drawn (they follow its mitres and T cuts) less
// the length of every opening, widened by the margin. Where the wall has no opening it is solid from
// its base to its top, which spans the band.
std::vector<SolidPiece> solid_pieces(const StaticGeometry& g, const PolygonSoup& soup,
                                     const std::vector<std::vector<uint32_t>>& tops,
                                     const std::vector<uint32_t>& walls) {
  std::vector<SolidPiece> out;
  const double m = cell_solid_margin_m;
  for (uint32_t wi : walls) {
    const Wall& w = g.walls[wi];
    const WallPlan p = wall_plan(w);
    for (uint32_t poly : tops[wi]) {
      std::vector<Poly> pieces(1);
      for (const Vec3& q : soup.points(soup.polygons[poly])) pieces[0].push_back({q.x, q.z});
      for (const Opening& o : w.openings) {
        // Keep u <= offset - m and u >= offset + width + m: lines across the wall at those u.
        const Vec2 a0 = p.at(o.offset - m, 0.0), b0 = p.at(o.offset - m, 1.0);
        const Vec2 a1 = p.at(o.offset + o.width + m, 0.0), b1 = p.at(o.offset + o.width + m, 1.0);
        std::vector<Poly> next;
        for (const Poly& piece : pieces) {
          // On the line p.at(c, 0) -> p.at(c, 1) (along the wall's left), the side is u - c.
          Poly lower = clip(piece, a0, b0, -1.0);
          Poly upper = clip(piece, a1, b1, 1.0);
          if (lower.size() >= 3) next.push_back(std::move(lower));
          if (upper.size() >= 3) next.push_back(std::move(upper));
        }
        pieces.swap(next);
      }
      for (Poly& piece : pieces) {
        const double area = signed_area(piece);
        if (!(std::abs(area) > 1e-12)) continue;
        SolidPiece sp;
        sp.lo = sp.hi = piece[0];
        for (Vec2 c : piece) sp.lo = glm::min(sp.lo, c), sp.hi = glm::max(sp.hi, c);
        sp.sign = area > 0.0 ? 1.0 : -1.0;
        sp.corners = std::move(piece);
        sp.wall = wi;
        out.push_back(std::move(sp));
      }
    }
  }
  return out;
}

// Two pieces meeting at a mitre or a T share an edge computed twice; their corners may differ by
// rounding (about 1e-15 m), far below the margin. A point this close outside an edge is on it.
constexpr double seam_tolerance_m = 1e-9;

bool inside(const Poly& poly, const SolidPiece& r) {
  const size_t n = r.corners.size();
  for (size_t k = 0; k < n; ++k) {
    const Vec2 a = r.corners[k], b = r.corners[(k + 1) % n];
    const double length = glm::length(b - a);
    if (!(length > 0.0)) continue;
    for (Vec2 p : poly) {
      if (r.sign * ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) < -seam_tolerance_m * length) return false;
    }
  }
  return true;
}

// Whether `poly` lies inside the union of two pieces: what of it is outside `a` lies inside `b`.
bool inside_union(const Poly& poly, const SolidPiece& a, const SolidPiece& b) {
  if (inside(poly, a) || inside(poly, b)) return true;
  Poly rest = poly;  // the part still inside a's half-planes so far
  const size_t n = a.corners.size();
  for (size_t k = 0; k < n && rest.size() >= 3; ++k) {
    const Vec2 p = a.corners[k], q = a.corners[(k + 1) % n];
    const Poly out_piece = clip(rest, p, q, -a.sign);
    if (out_piece.size() >= 3 && std::abs(signed_area(out_piece)) > 0.0 && !inside(out_piece, b)) return false;
    rest = clip(rest, p, q, a.sign);
  }
  return true;
}

// Blocked squares: those whose square widened by the margin lies inside one solid piece, or inside
// the union of two (where walls meet end to end, at a mitre or a T). So a blocked square lies inside
// the drawn walls by the margin.
void block_walls(const PlanGrid& grid, const std::vector<SolidPiece>& pieces, std::vector<uint32_t>& value) {
  const double m = cell_solid_margin_m;
  auto widened = [&](int i, int j) {
    return Poly{{grid.x(i) - m, grid.z(j) - m},
                {grid.x(i + 1) + m, grid.z(j) - m},
                {grid.x(i + 1) + m, grid.z(j + 1) + m},
                {grid.x(i) - m, grid.z(j + 1) + m}};
  };
  auto squares = [&](Vec2 lo, Vec2 hi, auto&& f) {
    for (int j = std::max(0, grid.row(lo.y)); j <= std::min(grid.nz - 1, grid.row(hi.y)); ++j) {
      for (int i = std::max(0, grid.column(lo.x)); i <= std::min(grid.nx - 1, grid.column(hi.x)); ++i) f(i, j);
    }
  };
  for (const SolidPiece& r : pieces) {
    squares(r.lo, r.hi, [&](int i, int j) {
      uint32_t& v = value[grid.at(i, j)];
      if (v != blocked_square && inside(widened(i, j), r)) v = blocked_square;
    });
  }
  for (size_t x = 0; x < pieces.size(); ++x) {
    for (size_t y = x + 1; y < pieces.size(); ++y) {
      const SolidPiece &a = pieces[x], &b = pieces[y];
      const Vec2 lo = glm::max(a.lo, b.lo) - grid.square, hi = glm::min(a.hi, b.hi) + grid.square;
      if (!(lo.x <= hi.x && lo.y <= hi.y)) continue;
      squares(lo, hi, [&](int i, int j) {
        uint32_t& v = value[grid.at(i, j)];
        if (v != blocked_square && inside_union(widened(i, j), a, b)) v = blocked_square;
      });
    }
  }
}

struct UnionFind {
  std::vector<uint32_t> parent;
  uint32_t add() {
    parent.push_back(uint32_t(parent.size()));
    return parent.back();
  }
  uint32_t find(uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Doorway zones: the squares wholly inside a barrier wall's thickness and within its length near an
// opening that are not blocked. A sight line through them crosses the wall's centre plane either in
// the opening's hole or in solid wall (the jambs, head and sill, or a joined wall): the opening's
// portal holds every crossing. Zones that touch merge.
void mark_zones(CellsBuild& b, int band_index, const StaticGeometry& g, UnionFind& zones,
                std::vector<detail::ZoneOpening>& zone_opening) {
  BandBuild& band = b.bands[size_t(band_index)];
  const double m = cell_solid_margin_m, reach = 2.0 * b.grid.square + m;
  for (uint32_t wi : band.walls) {
    const Wall& w = g.walls[wi];
    const WallPlan p = wall_plan(w);
    for (uint32_t k = 0; k < w.openings.size(); ++k) {
      const Opening& o = w.openings[k];
      const double u0 = std::max(0.0, o.offset - reach), u1 = std::min(p.length, o.offset + o.width + reach);
      if (!(u0 < u1)) continue;
      const uint32_t z = zones.add();
      zone_opening.push_back({wi, k});
      const auto rect = wall_rect(p, u0, u1, -p.half, p.half);
      detail::convex_inside_rows(b.grid, rect, [&](int j, int i0, int i1) {
        for (int i = i0; i <= i1; ++i) {
          uint32_t& v = band.value[b.grid.at(i, j)];
          if (v == blocked_square) continue;
          if (v & zone_bit) zones.unite(v & ~zone_bit, z);
          else v = zone_bit | z;
        }
      });
    }
  }
}

// Marks `sealed` where the simple polygon `points` covers a square whole: its centre is inside and
// no edge comes within the margin of it.
void seal_polygon(const PlanGrid& grid, std::span<const Vec2> points, std::vector<uint32_t>& stamp, uint32_t mark,
                  std::vector<uint8_t>& sealed) {
  detail::polygon_centre_rows(grid, points, [&](int j, int i0, int i1) {
    for (int i = i0; i <= i1; ++i) stamp[grid.at(i, j)] = mark;
  });
  for (size_t k = 0; k < points.size(); ++k) {
    detail::segment_rows(grid, points[k], points[(k + 1) % points.size()], cell_solid_margin_m,
                         [&](int j, int i0, int i1) {
                           for (int i = i0; i <= i1; ++i) {
                             if (stamp[grid.at(i, j)] == mark) stamp[grid.at(i, j)] = 0;
                           }
                         });
  }
  detail::polygon_centre_rows(grid, points, [&](int j, int i0, int i1) {
    for (int i = i0; i <= i1; ++i) sealed[grid.at(i, j)] |= uint8_t(stamp[grid.at(i, j)] == mark);
  });
}

struct SoupObjects {
  std::vector<uint32_t> room_floor, room_ceiling;
  uint32_t floor = no_object;
};

void seal_band(const CellsBuild& b, BandBuild& band, const StaticGeometry& g, const SoupObjects& objects,
               std::vector<uint32_t>& stamp, uint32_t& mark) {
  const size_t n = band.value.size();
  band.floor_sealed.assign(n, 0);
  band.ceiling_sealed.assign(n, 0);
  for (uint32_t r : band.rooms) {
    const Room& room = g.rooms[r];
    if (objects.room_floor[r] != no_object && std::abs(room.elevation - band.y0) <= cell_height_tolerance_m) {
      seal_polygon(b.grid, room.points, stamp, ++mark, band.floor_sealed);
      band.floor_objects.push_back(objects.room_floor[r]);
    }
    const double top = room.elevation + room.ceiling_height;
    if (objects.room_ceiling[r] != no_object && std::abs(top - band.y1) <= cell_height_tolerance_m) {
      seal_polygon(b.grid, room.points, stamp, ++mark, band.ceiling_sealed);
      band.ceiling_objects.push_back(objects.room_ceiling[r]);
    }
  }
  if (g.has_floor && objects.floor != no_object && std::abs(g.floor.elevation - band.y0) <= cell_height_tolerance_m &&
      on_band(band, g.floor.level, g.floor.elevation)) {
    const Floor& f = g.floor;
    const Vec2 lo = f.origin, hi = f.origin + Vec2(f.cells_x * f.cell_size, f.cells_z * f.cell_size);
    const std::array<Vec2, 4> rect{lo, Vec2(hi.x, lo.y), hi, Vec2(lo.x, hi.y)};
    detail::convex_inside_rows(b.grid, rect, [&](int j, int i0, int i1) {
      for (int i = i0; i <= i1; ++i) band.floor_sealed[b.grid.at(i, j)] = 1;
    });
    band.floor_objects.push_back(objects.floor);
  }
}

const int di[8] = {1, -1, 0, 0, 1, 1, -1, -1}, dj[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// Free squares -> cells: the regions reaching the border are the outside (cell 0); each enclosed
// region gets a cell per room holding at least min_room_area_m2 of it, or one cell.
void make_cells(const CellsBuild& b, int band_index, BandBuild& band, const StaticGeometry& g, SceneCells& out) {
  const PlanGrid& grid = b.grid;
  const size_t n = band.value.size();
  std::vector<int32_t> region(n, -1);
  std::vector<uint8_t> exterior;
  std::vector<size_t> stack;
  for (size_t s = 0; s < n; ++s) {
    if (band.value[s] != free_square || region[s] >= 0) continue;
    const int32_t id = int32_t(exterior.size());
    exterior.push_back(0);
    region[s] = id;
    stack.assign(1, s);
    while (!stack.empty()) {
      const size_t c = stack.back();
      stack.pop_back();
      const int i = int(c % size_t(grid.nx)), j = int(c / size_t(grid.nx));
      if (i == 0 || j == 0 || i == grid.nx - 1 || j == grid.nz - 1) exterior.back() = 1;
      for (int k = 0; k < 4; ++k) {
        const int a = i + di[k], bj = j + dj[k];
        if (a < 0 || bj < 0 || a >= grid.nx || bj >= grid.nz) continue;
        const size_t t = grid.at(a, bj);
        if (band.value[t] != free_square || region[t] >= 0) continue;
        region[t] = id;
        stack.push_back(t);
      }
    }
  }
  // Room labels by square centre (the first room listed wins), kept where the room holds enough.
  std::vector<int32_t> label(n, -1);
  for (uint32_t r : band.rooms) {
    detail::polygon_centre_rows(grid, g.rooms[r].points, [&](int j, int i0, int i1) {
      for (int i = i0; i <= i1; ++i) {
        const size_t s = grid.at(i, j);
        if (band.value[s] == free_square && label[s] < 0 && !exterior[size_t(region[s])]) label[s] = int32_t(r);
      }
    });
  }
  std::vector<std::pair<std::pair<int32_t, int32_t>, size_t>> area;  // (region, room) -> squares
  for (size_t s = 0; s < n; ++s) {
    if (label[s] >= 0) area.push_back({{region[s], label[s]}, 1});
  }
  std::sort(area.begin(), area.end());
  std::vector<std::pair<std::pair<int32_t, int32_t>, size_t>> kept;
  for (const auto& e : area) {
    if (!kept.empty() && kept.back().first == e.first) ++kept.back().second;
    else kept.push_back(e);
  }
  const double square_area = grid.square * grid.square;
  std::erase_if(kept, [&](const auto& e) { return double(e.second) * square_area < min_room_area_m2; });
  auto keeps = [&](int32_t reg, int32_t room) {
    return std::binary_search(kept.begin(), kept.end(), std::make_pair(std::make_pair(reg, room), size_t(0)),
                              [](const auto& x, const auto& y) { return x.first < y.first; });
  };
  // Cells in order of their first square; the labelled squares seed a breadth-first fill.
  std::vector<uint32_t> cell_of(n, free_square);
  std::vector<std::vector<std::pair<int32_t, uint32_t>>> cells_of_region(exterior.size());
  std::vector<uint8_t> region_has_room(exterior.size(), 0);
  for (const auto& e : kept) region_has_room[size_t(e.first.first)] = 1;
  std::deque<size_t> queue;
  for (size_t s = 0; s < n; ++s) {
    if (band.value[s] != free_square) continue;
    const int32_t reg = region[s];
    if (exterior[size_t(reg)]) {
      cell_of[s] = 0;
      continue;
    }
    const int32_t room = region_has_room[size_t(reg)] ? (label[s] >= 0 && keeps(reg, label[s]) ? label[s] : -2) : -1;
    if (room == -2) continue;  // filled from its neighbours below
    auto& list = cells_of_region[size_t(reg)];
    auto it = std::find_if(list.begin(), list.end(), [&](const auto& e) { return e.first == room; });
    if (it == list.end()) {
      Cell c;
      c.kind = CellKind::enclosed, c.band = band_index, c.room = room;
      out.cells.push_back(c);
      list.push_back({room, uint32_t(out.cells.size() - 1)});
      it = list.end() - 1;
    }
    cell_of[s] = it->second;
    queue.push_back(s);
  }
  while (!queue.empty()) {
    const size_t c = queue.front();
    queue.pop_front();
    const int i = int(c % size_t(grid.nx)), j = int(c / size_t(grid.nx));
    for (int k = 0; k < 8; ++k) {
      const int a = i + di[k], bj = j + dj[k];
      if (a < 0 || bj < 0 || a >= grid.nx || bj >= grid.nz) continue;
      const size_t t = grid.at(a, bj);
      if (band.value[t] != free_square || cell_of[t] != free_square || region[t] != region[c]) continue;
      cell_of[t] = cell_of[c];
      queue.push_back(t);
    }
  }
  for (size_t s = 0; s < n; ++s) {
    if (band.value[s] == free_square) band.value[s] = cell_of[s];
  }
}

void bound_cells(const CellsBuild& b, SceneCells& out) {
  std::vector<uint8_t> seen(out.cells.size(), 0);
  for (const BandBuild& band : b.bands) {
    for (int j = 0; j < b.grid.nz; ++j) {
      for (int i = 0; i < b.grid.nx; ++i) {
        const uint32_t v = band.value[b.grid.at(i, j)];
        if (v == blocked_square || (v & zone_bit) || v == 0) continue;
        Cell& c = out.cells[v];
        const Vec3 lo(b.grid.x(i), band.y0, b.grid.z(j)), hi(b.grid.x(i + 1), band.y1, b.grid.z(j + 1));
        c.lo = seen[v] ? glm::min(c.lo, lo) : lo;
        c.hi = seen[v] ? glm::max(c.hi, hi) : hi;
        seen[v] = 1;
      }
    }
  }
  Cell& outside = out.cells[0];
  outside.lo = Vec3(-std::numeric_limits<double>::infinity());
  outside.hi = Vec3(std::numeric_limits<double>::infinity());
}

// Each leaf's extent in its wall's frame, from the polygons drawn for it.
void measure_leaves(const StaticGeometry& g, const PolygonSoup& soup, std::vector<detail::Leaf>& leaves) {
  std::vector<uint32_t> leaf_of(soup.objects.size(), no_object);
  for (uint32_t k = 0; k < leaves.size(); ++k) {
    leaf_of[leaves[k].object] = k;
    leaves[k].u0 = leaves[k].v0 = leaves[k].y0 = std::numeric_limits<double>::infinity();
    leaves[k].u1 = leaves[k].v1 = leaves[k].y1 = -std::numeric_limits<double>::infinity();
  }
  for (const Polygon& poly : soup.polygons) {
    const uint32_t k = leaf_of[poly.object];
    if (k == no_object) continue;
    detail::Leaf& leaf = leaves[k];
    const WallPlan p = wall_plan(g.walls[leaf.wall]);
    for (const Vec3& q : soup.points(poly)) {
      const Vec2 d = Vec2(q.x, q.z) - p.start;
      const double u = glm::dot(d, p.dir), v = glm::dot(d, p.left);
      leaf.u0 = std::min(leaf.u0, u), leaf.u1 = std::max(leaf.u1, u);
      leaf.v0 = std::min(leaf.v0, v), leaf.v1 = std::max(leaf.v1, v);
      leaf.y0 = std::min(leaf.y0, q.y), leaf.y1 = std::max(leaf.y1, q.y);
    }
  }
}

}  // namespace

SceneCells build_cells(const StaticGeometry& g, const PolygonSoup& soup, const SceneHierarchy& hierarchy) {
  static std::atomic<uint64_t> serials{0};
  SceneCells out;
  out.serial = ++serials;
  out.cells.push_back(Cell{});  // the outside
  CellsBuild b;
  b.wall_object.assign(g.walls.size(), no_object);
  std::vector<std::vector<uint32_t>> tops;  // per wall: its top faces' polygons
  SoupObjects objects;
  objects.room_floor.assign(g.rooms.size(), no_object);
  objects.room_ceiling.assign(g.rooms.size(), no_object);
  {
    std::vector<uint8_t> has_polygons(soup.objects.size(), 0), translucent(soup.objects.size(), 0);
    for (const Polygon& p : soup.polygons) {
      has_polygons[p.object] = 1;
      if (p.flags & polygon_translucent) translucent[p.object] = 1;
    }
    std::vector<uint32_t> wall_of(soup.objects.size(), no_object);
    for (uint32_t o = 0; o < soup.objects.size(); ++o) {
      const ElementRef& e = soup.objects[o].element;
      if (e.kind == ElementKind::wall && e.index < g.walls.size()) wall_of[o] = e.index;
    }
    tops.assign(g.walls.size(), {});
    for (uint32_t k = 0; k < soup.polygons.size(); ++k) {
      const Polygon& p = soup.polygons[k];
      const uint32_t w = wall_of[p.object];
      if (w == no_object || !(p.normal.y > 0.999999)) continue;
      const double top = g.walls[w].base + g.walls[w].height;
      bool at_top = true;
      for (const Vec3& q : soup.points(p)) at_top = at_top && std::abs(q.y - top) <= cell_height_tolerance_m;
      if (at_top) tops[w].push_back(k);
    }
    for (uint32_t o = 0; o < soup.objects.size(); ++o) {
      const SceneObject& obj = soup.objects[o];
      if (!has_polygons[o]) continue;
      const ElementRef& e = obj.element;
      if (e.kind == ElementKind::wall && e.index < g.walls.size()) b.wall_object[e.index] = o;
      if (e.kind == ElementKind::room && e.index < g.rooms.size()) {
        (obj.ceiling ? objects.room_ceiling : objects.room_floor)[e.index] = o;
      }
      if (e.kind == ElementKind::floor) objects.floor = o;
      // A leaf hides what is behind it only when it is opaque (a translucent one is seen through).
      if (e.kind == ElementKind::opening && obj.closed && !translucent[o] && e.index < g.walls.size()) {
        b.leaves.push_back({e.index, e.opening, o});
      }
    }
    std::sort(b.leaves.begin(), b.leaves.end(), [](const detail::Leaf& x, const detail::Leaf& y) {
      return std::tie(x.wall, x.opening) < std::tie(y.wall, y.opening);
    });
    measure_leaves(g, soup, b.leaves);
  }
  b.bands = make_bands(g);
  double thinnest = std::numeric_limits<double>::infinity();
  Vec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (BandBuild& band : b.bands) {
    for (uint32_t w = 0; w < g.walls.size(); ++w) {
      const Wall& wall = g.walls[w];
      if (b.wall_object[w] == no_object || !on_band(band, wall.level, wall.base)) continue;
      if (wall.base > band.y0 + cell_height_tolerance_m || wall.base + wall.height < band.y1 - cell_height_tolerance_m)
        continue;
      if (!(glm::length(wall.end - wall.start) > 1e-9) || !(wall.thickness > 0.0)) continue;
      band.walls.push_back(w);
      if (wall.thickness >= thin_wall_m) thinnest = std::min(thinnest, wall.thickness);
      for (Vec2 p : {wall.start, wall.end})
        lo = glm::min(lo, p - wall.thickness), hi = glm::max(hi, p + wall.thickness);
    }
    for (uint32_t r = 0; r < g.rooms.size(); ++r) {
      if (on_band(band, g.rooms[r].level, g.rooms[r].elevation)) band.rooms.push_back(r);
    }
  }
  std::erase_if(b.bands, [](const BandBuild& band) { return band.walls.empty(); });
  if (b.bands.empty()) {
    detail::assign_polygons(soup, hierarchy, out);
    return out;
  }
  for (const BandBuild& band : b.bands) {
    for (uint32_t r : band.rooms) {
      for (Vec2 p : g.rooms[r].points) lo = glm::min(lo, p), hi = glm::max(hi, p);
    }
  }
  double square = std::isfinite(thinnest) ? std::clamp(thinnest / 3.0, min_square_m, max_square_m) : min_square_m;
  const Vec2 size = hi - lo;
  square = std::max(square, std::sqrt(size.x * size.y / max_band_squares));
  b.grid.square = square;
  b.grid.origin = lo - 3.0 * square;
  b.grid.nx = int(std::ceil(size.x / square)) + 6;
  b.grid.nz = int(std::ceil(size.y / square)) + 6;
  const size_t n = size_t(b.grid.nx) * size_t(b.grid.nz);

  UnionFind zones;
  std::vector<detail::ZoneOpening> zone_opening;
  std::vector<uint32_t> stamp(n, 0);
  uint32_t mark = 0;
  for (size_t k = 0; k < b.bands.size(); ++k) {
    BandBuild& band = b.bands[k];
    band.value.assign(n, free_square);
    const std::vector<SolidPiece> pieces = solid_pieces(g, soup, tops, band.walls);
    block_walls(b.grid, pieces, band.value);
    for (uint32_t w : band.walls) {
      Vec2 wlo(std::numeric_limits<double>::infinity()), whi(-std::numeric_limits<double>::infinity());
      for (uint32_t poly : tops[w]) {
        for (const Vec3& q : soup.points(soup.polygons[poly]))
          wlo = glm::min(wlo, Vec2(q.x, q.z)), whi = glm::max(whi, Vec2(q.x, q.z));
      }
      if (!(wlo.x <= whi.x))
        wlo = glm::min(g.walls[w].start, g.walls[w].end), whi = glm::max(g.walls[w].start, g.walls[w].end);
      band.wall_lo.push_back(wlo), band.wall_hi.push_back(whi);
    }
    mark_zones(b, int(k), g, zones, zone_opening);
    seal_band(b, band, g, objects, stamp, mark);
    make_cells(b, int(k), band, g, out);
  }
  // Zones: one per merged group, numbered in order, with its openings and the cells beside it.
  std::vector<uint32_t> zone_index(zones.parent.size(), no_cell);
  for (uint32_t z = 0; z < zones.parent.size(); ++z) {
    const uint32_t root = zones.find(z);
    if (zone_index[root] == no_cell) {
      zone_index[root] = uint32_t(b.zones.size());
      b.zones.emplace_back();
    }
    zone_index[z] = zone_index[root];
    b.zones[zone_index[z]].openings.push_back(zone_opening[z]);
  }
  for (size_t k = 0; k < b.bands.size(); ++k) {
    BandBuild& band = b.bands[k];
    for (int j = 0; j < b.grid.nz; ++j) {
      for (int i = 0; i < b.grid.nx; ++i) {
        uint32_t& v = band.value[b.grid.at(i, j)];
        if (v == blocked_square || !(v & zone_bit)) continue;
        v = zone_bit | zone_index[v & ~zone_bit];
        Zone& zone = b.zones[v & ~zone_bit];
        zone.band = int(k);
        for (int d = 0; d < 8; ++d) {
          const int a = i + di[d], c = j + dj[d];
          if (a < 0 || c < 0 || a >= b.grid.nx || c >= b.grid.nz) continue;
          const uint32_t w = band.value[b.grid.at(a, c)];
          if (w != blocked_square && !(w & zone_bit)) zone.cells.push_back(w);
        }
      }
    }
  }
  for (Zone& zone : b.zones) {
    std::sort(zone.cells.begin(), zone.cells.end());
    zone.cells.erase(std::unique(zone.cells.begin(), zone.cells.end()), zone.cells.end());
  }
  bound_cells(b, out);
  if (out.cells.size() == 1) {  // nothing enclosed: one cell
    detail::assign_polygons(soup, hierarchy, out);
    return out;
  }
  for (const BandBuild& band : b.bands) {
    for (uint32_t w : band.walls) out.barrier_objects.push_back(b.wall_object[w]);
    out.barrier_objects.insert(out.barrier_objects.end(), band.floor_objects.begin(), band.floor_objects.end());
    out.band_ceilings.push_back(band.ceiling_objects);
  }
  std::sort(out.barrier_objects.begin(), out.barrier_objects.end());
  out.barrier_objects.erase(std::unique(out.barrier_objects.begin(), out.barrier_objects.end()),
                            out.barrier_objects.end());
  detail::add_portals(g, b, out);
  detail::assign_polygons(soup, hierarchy, out);
  return out;
}

}  // namespace rr

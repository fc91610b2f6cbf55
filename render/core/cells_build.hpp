// What the derivation of cells (cells_build.cpp) hands its second half (cells_portals.cpp): the grid,
// each band's squares (a cell, blocked, or a doorway zone) with which of them a floor or a ceiling
// seals, and the doorway zones with their openings. Internal to the cells.
#pragma once

#include "render/core/cells.hpp"
#include "render/core/cells_grid.hpp"

#include <utility>
#include <vector>

namespace rr::detail {

// Lengths within this are equal heights (a wall reaching a band's floor or ceiling, a floor on it).
constexpr double cell_height_tolerance_m = 1e-6;
// A blocked square lies at least this far inside a wall's solid; an opening's hole is widened by it.
constexpr double cell_solid_margin_m = 1e-4;
// Portals along a boundary or over a floor are cut into pieces of at most this many squares a side,
// so each piece projects to a tight rectangle.
constexpr int cell_tile = 32;

// A wall's frame in the plan: u along the centreline from its start, v to its left (as the
// tessellator's), half its thickness.
struct WallPlan {
  Vec2 start, dir, left;
  double length = 0.0, half = 0.0;
  Vec2 at(double u, double v) const { return start + u * dir + v * left; }
};
inline WallPlan wall_plan(const Wall& w) {
  WallPlan p;
  p.start = w.start;
  p.length = glm::length(w.end - w.start);
  p.dir = (w.end - w.start) / p.length;
  p.left = {p.dir.y, -p.dir.x};
  p.half = 0.5 * w.thickness;
  return p;
}

struct BandBuild {
  double y0 = 0.0, y1 = 0.0;
  std::vector<int> levels;                            // the levels it was made of (none without levels)
  std::vector<uint32_t> walls;                        // walls spanning it: the barriers
  std::vector<Vec2> wall_lo, wall_hi;                 // per barrier: the plan bounds of its drawn top faces
  std::vector<uint32_t> rooms;                        // rooms whose floors lie on it
  std::vector<uint32_t> value;                        // per square: a cell, blocked_square or zone_bit | zone
  std::vector<uint8_t> floor_sealed, ceiling_sealed;  // per square: a floor / a ceiling covers it whole
  std::vector<uint32_t> floor_objects, ceiling_objects;
};

struct ZoneOpening {
  uint32_t wall = 0, opening = 0;
};
struct Zone {
  int band = 0;
  std::vector<ZoneOpening> openings;
  std::vector<uint32_t> cells;  // cells next to its squares, ascending
};

// A door leaf as drawn: its object and its extent in its wall's frame (u along the centreline from
// the start, v to the left, y world height).
struct Leaf {
  uint32_t wall = 0, opening = 0;
  uint32_t object = no_object;
  double u0 = 0.0, u1 = 0.0, v0 = 0.0, v1 = 0.0, y0 = 0.0, y1 = 0.0;
};

struct CellsBuild {
  PlanGrid grid;
  std::vector<BandBuild> bands;
  std::vector<Zone> zones;
  std::vector<uint32_t> wall_object;  // per wall, no_object without polygons
  std::vector<Leaf> leaves;           // sorted by (wall, opening)
};

// Portals, the bands' runs, the polygons' cell sets and the hierarchy's masks (cells_portals.cpp).
void add_portals(const StaticGeometry& geometry, const CellsBuild& build, SceneCells& out);
void assign_polygons(const PolygonSoup& soup, const SceneHierarchy& hierarchy, SceneCells& out);

}  // namespace rr::detail

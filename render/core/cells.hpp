// Cells and portals of a static scene, derived from its walls, openings, rooms and levels, and the
// portal walk that finds which cells a viewpoint can see into. World space, metres; plans are (x, z).
// A cell is a region of space: the outside, or a part of one level's floor-to-ceiling band that walls
// reaching from its floor to its ceiling enclose (split further where rooms meet without a wall).
// Every straight line between two cells crosses a portal (an opening, a wall-less boundary, a floor or
// ceiling that does not close) or passes through something the frame draws opaque in between: a wall
// spanning the band, a door leaf, a floor, a ceiling seen from below. So a polygon whose cells the walk
// does not reach cannot be seen, and skipping it keeps the frame's bytes (docs/culling.md, "Cells").
// Derivation is conservative: where closure is not certain, cells merge (at worst into one).
#pragma once

#include "render/core/camera.hpp"
#include "render/core/hierarchy.hpp"
#include "render/core/math.hpp"
#include "render/core/scene.hpp"
#include "render/core/tessellate.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace rr {

constexpr uint32_t no_cell = 0xFFFFFFFFu;
constexpr uint32_t no_object = 0xFFFFFFFFu;

enum class CellKind : uint8_t { outside, enclosed };

struct Cell {
  CellKind kind = CellKind::outside;
  int band = -1;          // index into SceneCells::bands; -1 for the outside
  int room = -1;          // StaticGeometry::rooms index it was labelled with, -1: none
  Vec3 lo{0.0}, hi{0.0};  // bounds of its region
};

// A convex quad (4 corners) or a box (8 corners) that a sight line through a portal crosses.
struct PortalShape {
  std::array<Vec3, 8> corners{};
  uint8_t count = 0;
  bool horizontal = false;  // a quad in the plane y = corners[0].y
};

// seam: where a wall with openings is drawn as pieces that meet at T-junctions (its faces beside an
// opening, its top and bottom faces along its length), the rasterizer may leave a crack a sample can
// see through; such seams connect every cell beside the wall.
enum class PortalKind : uint8_t { opening, boundary, floor, ceiling, seam };

// A directed portal: a sight line from cell `from` may pass into cell `to` through one of its shapes.
// Some portals change with what a frame draws: a door's portal is three thin gaps around its leaf,
// or the whole hole when the leaf is not drawn; a ceiling's, the gaps between the band's ceilings,
// or the whole cell when they are not all drawn. `alt_*` are the shapes used then.
struct Portal {
  uint32_t from = 0, to = 0;
  PortalKind kind = PortalKind::opening;
  uint32_t first = 0, count = 0;          // into SceneCells::shapes
  uint32_t alt_first = 0, alt_count = 0;  // the shapes when the portal's switch is off
  uint32_t leaf_object = no_object;       // opening: the door leaf object that closes it
  int ceiling_band = -1;                  // ceiling: the band whose ceilings must all be drawn
  // +1: only a sight line going up can cross it (horizontal shapes), -1: only down, 0: any.
  int8_t vertical = 0;
  uint32_t pair = 0;  // the undirected portal it belongs to (counts and the tests' mutation)
};

// One level's floor-to-ceiling band of the plan grid, its squares' cells stored as runs per row.
struct CellBand {
  double y0 = 0.0, y1 = 0.0;
  // Row r's runs are runs[row_first[r] .. row_first[r + 1]): each starts at column `x` and lasts
  // until the next run (the last one to the grid's edge). value: a cell, blocked (solid wall), or a
  // doorway zone (zone_bit | index into SceneCells::zone_first).
  struct Run {
    uint32_t x = 0, value = 0;
  };
  std::vector<uint32_t> row_first;
  std::vector<Run> runs;
};
constexpr uint32_t blocked_square = 0xFFFFFFFFu;
constexpr uint32_t zone_bit = 0x80000000u;

struct SceneCells {
  // The plan grid: square (i, j) covers x in origin.x + [i, i + 1] * square, z likewise with j.
  Vec2 origin{0.0};
  double square = 0.0;
  int nx = 0, nz = 0;
  std::vector<CellBand> bands;  // ascending y, disjoint
  std::vector<Cell> cells;      // cells[0] is the outside
  std::vector<Portal> portals;  // grouped by `from`: cell c's are [cell_portals[c], cell_portals[c + 1])
  std::vector<uint32_t> cell_portals;
  std::vector<PortalShape> shapes;
  size_t undirected_portals = 0;
  std::vector<uint32_t> zone_first, zone_cells;  // a doorway zone's cells (CSR)
  // Each barrier wall of each band: its plan bounds and the cells beside it (CSR into wall_cells).
  struct WallCells {
    int band = 0;
    Vec2 lo{0.0}, hi{0.0};
    uint32_t first = 0, count = 0;
  };
  std::vector<WallCells> walls;
  std::vector<uint32_t> wall_cells;
  // Per polygon of the soup it was built for: its cells, as set index into set_first/set_cells.
  std::vector<uint32_t> polygon_set;
  std::vector<uint32_t> set_first, set_cells;
  // Per node of the hierarchy it was built for: bit (c % 64) for every cell c of a polygon below.
  std::vector<uint64_t> node_mask;
  // What must be drawn for the cells to hold: every wall that bounds them, every floor that seals.
  std::vector<uint32_t> barrier_objects;
  // Per band: the ceiling objects whose drawing closes its ceiling portals.
  std::vector<std::vector<uint32_t>> band_ceilings;
  // Unique to one build_cells result (0: none; a copy keeps it, nothing changes cells once built):
  // what a walk over these cells is kept under, so that a kept walk is never taken for another's.
  uint64_t serial = 0;

  // More than the outside: a frame can skip cells. Else the scene is one cell (docs/culling.md).
  bool derived() const { return cells.size() > 1; }
  std::span<const uint32_t> cells_of_polygon(uint32_t polygon) const {
    const uint32_t s = polygon_set[polygon];
    return {set_cells.data() + set_first[s], set_first[s + 1] - set_first[s]};
  }
  size_t bytes() const;  // what it costs against a cache budget
};

// Derives the cells of `geometry`, whose tessellation is `soup` and the hierarchy of that soup
// `hierarchy`. Deterministic. A scene without walls that enclose anything gets the outside only.
SceneCells build_cells(const StaticGeometry& geometry, const PolygonSoup& soup, const SceneHierarchy& hierarchy);

// The cells a viewpoint starts in: those within `reach` plus one grid square of `point` (on a
// boundary, in a doorway: all of them), and when a wall comes within `reach`, every cell beside it (a
// camera's near plane cuts away what lies nearer than its corners, so a sight line may pass through
// such a wall unseen). Empty when the point lies inside a solid wall.
std::vector<uint32_t> locate_cells(const SceneCells& cells, Vec3 point, double reach);

// What one frame draws that the cells depend on: when `valid` is false (a wall that bounds a cell is
// not drawn: its level is left out) the frame must not skip cells.
struct CellConditions {
  bool valid = true;
  std::vector<uint8_t> ceilings_drawn;  // per band
  std::vector<uint8_t> object_drawn;    // per soup object; empty: every object is drawn
  uint32_t dropped_pair = no_object;    // tests only: this undirected portal is ignored (a mutation)
  bool operator==(const CellConditions&) const = default;
};
// `object_drawn` per soup object of the frame (empty: all), the ceilings and walls checked against it.
CellConditions cell_conditions(const SceneCells& cells, std::vector<uint8_t> object_drawn);

// A region of the view plane in normalized device coordinates (x right, y up, [-1, 1] on screen).
struct ViewRegion {
  double x0 = -1.0, y0 = -1.0, x1 = 1.0, y1 = 1.0;
  bool empty() const { return !(x0 <= x1 && y0 <= y1); }
};

// One portal walk: from `eye` (a camera, or a lamp's position with one view per cube face) through
// `clip_from_world` (w: depth along the view direction), starting with `region` of its view plane.
// `margin_x`, `margin_y`: how far (NDC) each projected portal is widened, to cover rasterization.
struct CellViewpoint {
  Vec3 eye{0.0};
  double reach = 0.0;  // how far from the eye what blocks a sight line may be clipped away (a near plane's corners)
  Mat4 clip_from_world{1.0};
  ViewRegion region;
  double margin_x = 0.0, margin_y = 0.0;
};

// The viewpoint of a camera's frame: the whole view plane, `reach` the distance to the near plane's
// corners (nearer than them a wall may be cut away and seen through), and a margin of two pixels each
// way (vertex snapping, and samples anywhere in a pixel).
CellViewpoint cell_viewpoint(const ViewTransform& view);

// Up to this many regions per cell: past it the two whose bounds grow least are merged.
constexpr size_t cell_regions_max = 4;
struct CellRegions {
  std::array<ViewRegion, cell_regions_max> region{};
  size_t count = 0;
};

struct CellWalk {
  std::vector<uint8_t> reached;      // per cell
  std::vector<CellRegions> regions;  // per cell: regions that hold every region it was reached with
  size_t cells_visited = 0;          // cells reached
  size_t portals_walked = 0;         // portal crossings that reached a cell with a new region
  bool everything = false;           // the walk gave up (a viewpoint in a wall, too many steps): all reached
};

// Walks the portals from the cells around `view.eye`, narrowing the region at each portal crossed:
// on return every cell a sight line from the eye within the region can enter is reached, with a
// region that holds where such a sight line meets the view plane. Fills `out` (memory kept).
void walk_cells(const SceneCells& cells, const CellConditions& conditions, const CellViewpoint& view, CellWalk& out);

// The rectangle of the view plane holding every region `walk` reached cell c with (its sight lines
// into c), or the whole plane when it kept none.
ViewRegion bounding_region(const CellWalk& walk, size_t c);

// What the occlusion walk reads of one frame's cell walk: polygons of no reached cell are skipped,
// hierarchy nodes likewise by their masks and by the reached cells' regions in pixels.
struct CellFilter {
  const SceneCells* cells = nullptr;
  const CellWalk* walk = nullptr;
  uint64_t reached_bits = 0;  // bit (c % 64) of every reached cell c
  // Per bit: pixel rectangles [x0, x1) x [y0, y1) that hold its cells' regions.
  struct Rects {
    std::array<std::array<int, 4>, cell_regions_max> rect{};
    size_t count = 0;
  };
  std::array<Rects, 64> rects{};
  bool polygon_reached(uint32_t hierarchy_polygon) const;
  // Whether a node whose pixel rectangle is [x0, x1) x [y0, y1) may hold something a reached cell
  // shows; `testable` false (its box reaches the near plane) checks the mask only.
  bool node_reached(uint32_t node, bool testable, int x0, int y0, int x1, int y1) const;
};
// The filter of `walk` for a view of `width` x `height` pixels.
void make_cell_filter(const SceneCells& cells, const CellWalk& walk, int width, int height, CellFilter& out);

}  // namespace rr

// The part of lamp culling (docs/lighting.md, "Lamps culled by what they see") that depends only on
// the scene and the lamp, not on the camera: a point light's six cube-face portal walks and its
// fixture map. A frame makes them, or takes the ones its prepared scene made once for every frame
// that draws its whole soup.
#pragma once

#include "render/core/cells.hpp"
#include "render/core/math.hpp"
#include "render/core/scene.hpp"
#include "render/core/shadow_rays.hpp"
#include "render/core/tessellate.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace rr {

// Bins per cube face edge of a lamp's fixture map.
constexpr int lamp_fixture_bins = 64;

// One cube face's portal walk from a lamp: whether it gave up, and per cell whether it reached the
// cell and the rectangle of the face's view plane that holds every region it reached the cell with.
struct LampFaceWalk {
  bool everything = false;
  std::vector<uint8_t> reached;     // per cell (empty when the walk gave up)
  std::vector<ViewRegion> regions;  // per cell; meaningful where reached
};

// Cube face `face` (shadow_detail::cube_faces) of a lamp at `position` as its walk sees it: a
// quarter-turn view starting 0.1 mm from the lamp (the walk takes every cell that close as a start),
// its portals widened by 1e-6 of the view plane, far beyond the rounding of a projection, so that
// the walk never misses a cell an exact ray enters.
CellViewpoint lamp_face_view(Vec3 position, size_t face);

// The walks from a lamp at `position`, face by face in cube_faces order, up to and including the
// first that gave up.
std::vector<LampFaceWalk> walk_from_lamp(const SceneCells& cells, const CellConditions& conditions, Vec3 position);

// The tolerance of lamp culling's tests for a soup whose vertices span [lo, hi]: cones that come
// within it of each other count as meeting. 1e-7 of the soup's size, far above the clipping's rounding.
double lamp_tolerance(Vec3 lo, Vec3 hi);

// Per light, its fixture: the polygons of the soup's objects whose bounds hold the light strictly
// (point lights only; others get none).
std::vector<std::vector<uint32_t>> lamp_fixtures(const PolygonSoup& soup, std::span<const Light> lights);

// What a prepared scene's lamps see, for the frames that draw its whole soup: the walks under that
// soup's cell conditions and each point light's fixture map. A frame takes a lamp's entries only
// when they were made from what it would make them from (the same cells, conditions, soup and
// position), so taking them keeps the bytes.
struct PreparedLamps {
  uint64_t cells = 0;         // SceneCells::serial of the cells walked (0: no walks were made)
  CellConditions conditions;  // the conditions they were walked under
  double tolerance = 0.0;     // lamp_tolerance of the soup, which the fixture maps were made with
  struct Lamp {
    bool point = false;  // a point light: the entries below were made
    Vec3 position{0.0};
    std::vector<LampFaceWalk> faces;
    FixtureMap fixture;
  };
  std::vector<Lamp> lamps;  // per scene light
  size_t bytes() const;     // what it costs against a cache budget
};
// One light per task on `threads` threads (the result does not depend on them).
PreparedLamps prepare_lamps(const PolygonSoup& soup, const SceneCells& cells, std::span<const Light> lights,
                            unsigned threads = 1);

}  // namespace rr

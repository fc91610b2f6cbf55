// Placement checks of the room designer the service descends from: solids intersecting walls or each
// other, solids reaching beyond the floor, openings closer than 5 cm to a wall end or to each other.
// They are warnings, not errors: intersecting solids are legitimate scenes (the BSP tests need them).
// Input is the validated scene and its tessellation (world space, metres); output names elements by
// the JSON Pointers the tessellator gave them ("/scene/solids/3"). Work is bounded by PlacementLimits.
#pragma once

#include "render/core/scene.hpp"
#include "render/core/tessellate.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace rr {

struct PlacementWarning {
  std::string pointer;  // the element warned about (the later one of a pair)
  std::string detail;
};

struct PlacementLimits {
  double tolerance_m = 1e-3;       // overlaps up to 1 mm count as touching: furniture flush to a wall
  double opening_clearance_m = 0.05;
  size_t max_warnings = 100;       // further problems are summarised in one last warning
  size_t max_pair_work = 50'000'000;  // vertex projections spent on pair tests before giving up
};

// Footprints are the convex hulls in plan (x, z) of each wall's and solid's polygons, extruded over
// the element's height range, so a pyramid or an L-shaped prism is treated as its hull: the checks
// may warn about a near miss, never stay silent about a real overlap of the hulls.
// `scene_pointer` is where the scene sits in the document the pointers refer to: "/scene" in a
// render request, "" in a stored scene document.
std::vector<PlacementWarning> placement_warnings(const Scene& scene, const PolygonSoup& soup,
                                                 const PlacementLimits& limits = {},
                                                 const std::string& scene_pointer = "/scene");

}  // namespace rr

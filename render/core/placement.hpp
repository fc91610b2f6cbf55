// Placement checks of the room designer the service descends from: solids intersecting walls or each
// other, solids reaching beyond the floor, openings closer than 5 cm to a wall end or to each other.
// They are warnings, not errors: intersecting solids are legitimate scenes (the BSP tests need them).
// Input is the validated scene and its tessellation (world space, metres); output is typed and names
// elements by kind and index. Work is bounded by PlacementLimits. The text a client reads (JSON
// Pointer and detail) is written at the boundary: render/scene_io/element_pointer.hpp.
#pragma once

#include "render/core/element.hpp"
#include "render/core/scene.hpp"
#include "render/core/tessellate.hpp"

#include <cstddef>
#include <vector>

namespace rr {

enum class PlacementIssue : uint8_t {
  opening_near_start,  // `element` (an opening) is distance_m from its wall's start, under limit_m
  opening_near_end,    // ... from its wall's end
  openings_too_close,  // ... from opening `other` of the same wall
  beyond_floor,        // `element` (a solid) reaches distance_m beyond the floor's edge
  intersects,          // `element` (a solid) intersects `other` (a wall or an earlier solid)
  more_problems,       // `count` further warnings were not listed (element: the scene)
  stopped_early,       // the pair checks ran out of work; `count` warnings were not listed
};

struct PlacementWarning {
  PlacementIssue issue = PlacementIssue::more_problems;
  ElementRef element;     // the element warned about (the later one of a pair)
  ElementRef other = {};  // the other element of a pair
  double distance_m = 0.0;
  double limit_m = 0.0;
  size_t count = 0;
  // Its severity: how far the element reaches into the problem (an overlap's depth, the distance
  // beyond the floor, what an opening lacks of its clearance). The list is sorted by it, deepest first.
  double depth_m = 0.0;
};

struct PlacementLimits {
  double tolerance_m = 1e-3;  // overlaps up to 1 mm count as touching: furniture flush to a wall
  double opening_clearance_m = 0.05;
  size_t max_warnings = 100;          // the deepest are listed; the rest are counted in one last warning
  size_t max_pair_work = 50'000'000;  // vertex projections spent on pair tests before giving up
};

// Footprints are the convex hulls in plan (x, z) of each wall's and solid's polygons, extruded over
// the element's height range, so a pyramid or an L-shaped prism is treated as its hull: the checks
// may warn about a near miss, never stay silent about a real overlap of the hulls. A piece is one
// element (one object of the soup): its parts are one body, so a pair of pieces is one warning.
// The warnings come sorted by depth_m, deepest first (ties in element order), at most
// limits.max_warnings of them, then one more_problems (or stopped_early) warning counting the rest.
std::vector<PlacementWarning> placement_warnings(const Scene& scene, const PolygonSoup& soup,
                                                 const PlacementLimits& limits = {});

// How many problems a list from placement_warnings stands for: those listed and those counted.
size_t placement_problem_count(const std::vector<PlacementWarning>& warnings);

}  // namespace rr

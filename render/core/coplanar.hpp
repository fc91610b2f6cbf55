// Coplanar overlaps of a polygon soup. In: a soup. Out: Polygon::plane_group, 1, 2, ... for each
// connected set of polygons that lie in one plane and whose interiors overlap, 0 for every other
// polygon. Where a group's polygons overlap, every exact pipeline and the reference show the lowest
// id (docs/accuracy.md, "Ties"); groups are what makes that a comparison of ids, not of depths.
#pragma once

#include "render/core/tessellate.hpp"

namespace rr {

// Two polygons are in one plane when every vertex of each is within coplanar_tolerance(soup) of the
// other's plane: this fraction of the scene's bounding-box diagonal, and never below what doubles
// resolve at the scene's coordinates.
constexpr double coplanar_fraction = 1e-10;
double coplanar_tolerance(const PolygonSoup& soup);

// Sets plane_group on every polygon of `soup` (deterministic: groups are numbered by their lowest
// polygon index).
void assign_plane_groups(PolygonSoup& soup);

// True when the convex polygons a and b (vertices in one plane with unit normal `normal`) overlap by
// more than `tolerance` (metres) across every separating direction: sharing an edge is no overlap.
bool convex_overlap(std::span<const Vec3> a, std::span<const Vec3> b, Vec3 normal, double tolerance);

}  // namespace rr

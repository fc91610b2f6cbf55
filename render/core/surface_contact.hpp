// Whether two sets of polygons of one soup (world space, metres) cross each other: the narrow phase
// of the placement checks (placement.cpp), after their hulls overlapped. Two convex planar polygons
// cross when each straddles the other's plane by more than `tolerance` on both sides and no axis
// across an edge of each separates them; polygons that only touch (flush faces, a leg standing on a
// carpet's top) or meet within the tolerance do not. So a chair tucked under a table, whose hulls
// overlap, is quiet unless some face of one goes through a face of the other.
#pragma once

#include "render/core/tessellate.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace rr {

enum class ContactResult : uint8_t { apart, cross, out_of_work };

// Tests the polygons of `a` against those of `b` (indices into soup.polygons), only where their
// bounding boxes meet. Adds the vertex projections it spends to `work`
// and answers out_of_work once `work` passes `budget` before a crossing was found.
ContactResult surfaces_cross(const PolygonSoup& soup, std::span<const uint32_t> a, std::span<const uint32_t> b,
                             double tolerance, size_t& work, size_t budget);

}  // namespace rr

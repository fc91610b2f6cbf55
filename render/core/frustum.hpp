// The view frustum as six world-space planes, and the whole-object test that lets the zbuffer and
// painter pipelines skip every polygon of a solid outside the view before any per-polygon work.
// In: a view (clip_from_world) and axis-aligned world boxes; out: whether a box lies wholly
// outside one plane. Conservative: a box is kept whenever any part of it may be inside.
#pragma once

#include "render/core/camera.hpp"
#include "render/core/tessellate.hpp"

#include <cstdint>
#include <vector>

namespace rr {

struct Frustum {
  // Gribb-Hartmann planes of clip_from_world, positive inside: left, right, bottom, top (these four
  // meet at the eye, so together they also reject what lies behind it), near, far.
  Vec4 planes[6];
  explicit Frustum(const ViewTransform& view);
  bool outside(Vec3 lo, Vec3 hi) const;  // the box lies wholly outside one of the planes
};

// Per object of `soup` (index = Polygon::object): 1 when its bounding box may meet the frustum, 0
// when none of its polygons can reach a pixel (they would all be clipped away or land off-image).
struct ObjectsInView {
  std::vector<uint8_t> visible;
  size_t culled = 0;  // objects with at least one polygon that are wholly outside
};
ObjectsInView objects_in_view(const PolygonSoup& soup, const ViewTransform& view);

}  // namespace rr

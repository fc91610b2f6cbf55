// Whether two viewpoints' cones of sight lines (each the lines from a viewpoint's eye through a
// rectangle of its view plane, as a portal walk records them per cell) share a point inside a box.
// World space, doubles. Conservative: it may answer true for cones that only come within a small
// tolerance of each other, never false for cones that meet.
#pragma once

#include "render/core/cells.hpp"
#include "render/core/math.hpp"

#include <span>
#include <vector>

namespace rr {

// The half-space n . p + d >= 0 (n a unit vector, p world).
struct HalfSpace {
  Vec3 n{0.0};
  double d = 0.0;
};

// The cone of `view`'s sight lines through `region` of its view plane: x0 <= x/w <= x1,
// y0 <= y/w <= y1 and w >= 0 in clip coordinates, as five half-spaces through the eye.
void add_sight_cone(const Mat4& clip_from_world, const ViewRegion& region, std::vector<HalfSpace>& out);

// Whether the half-spaces, each moved out by `tolerance` metres, share a point within the box
// [lo, hi] (moved out the same way).
// Whether the box [lo, hi] lies wholly outside one of the half-spaces moved out by `tolerance`
// (then half_spaces_meet_in_box is false too; a quick test before it).
bool box_outside_half_spaces(std::span<const HalfSpace> half_spaces, Vec3 lo, Vec3 hi, double tolerance);

bool half_spaces_meet_in_box(std::span<const HalfSpace> half_spaces, Vec3 lo, Vec3 hi, double tolerance);

}  // namespace rr

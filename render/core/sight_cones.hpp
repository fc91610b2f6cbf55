// Whether two viewpoints' cones of sight lines (each the lines from a viewpoint's eye through a
// rectangle of its view plane, as a portal walk records them per cell) share a point inside a box.
// World space, doubles. Conservative: it may answer true for cones that only come within a small
// tolerance of each other, never false for cones that meet.
#pragma once

#include "render/core/cells.hpp"
#include "render/core/math.hpp"
#include "render/core/shadow_rays.hpp"

#include <cstdint>
#include <span>
#include <utility>
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

// What a lamp can see of the cells a camera's walk reached: per such cell (CSR by `cell_first`), a
// group of half-spaces per cube face of the lamp whose walk reached it: the camera's cone of the cell
// and that face's. A shown point of the cell that the lamp lights unblocked lies within one of the
// cell's groups (docs/lighting.md, "Lamps culled by what they see").
struct LampSight {
  bool everything = true;            // nothing known (a walk gave up, or not a lamp): every point may be lit
  std::vector<uint32_t> cell_first;  // per cell + 1: into groups
  std::vector<std::pair<uint32_t, uint32_t>> groups;  // first, count into planes
  std::vector<HalfSpace> planes;
};

// One frame's lamps against its polygons, for shadow rays: per polygon id a bit per scene light, set
// when the lamp lights no point of the polygon, so that every ray toward it would be blocked.
struct LampsBlocked {
  size_t words = 0;  // 64-bit words per polygon id
  std::vector<uint64_t> bits;
  std::vector<LampSight> sight;      // per scene light, what the bits were derived from
  std::vector<FixtureMap> fixtures;  // per scene light: the directions its own fixture closes

  // Whether the fixture of `light` blocks every shadow ray from p toward it.
  bool fixture_closes(uint32_t light, Vec3 p) const { return light < fixtures.size() && fixtures[light].closes(p); }

  bool blocked(uint32_t id, uint32_t light) const {
    const size_t i = size_t(id) * words + light / 64;
    return i < bits.size() && ((bits[i] >> (light % 64)) & 1u) != 0;
  }
};

}  // namespace rr

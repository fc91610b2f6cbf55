// Geometric rules of the scene format that need more than a range check: openings that overlap along
// their wall, simple prism footprints, valid mesh faces. Pure functions on parsed values (plan or
// object space); scene_json attaches the JSON Pointers and throws.
#pragma once

#include "render/core/scene.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace rr {

// Two openings of one wall whose spans [offset, offset + width] overlap by more than 1e-9 m (touching
// is allowed), as (earlier index, later index); nullopt when none do.
std::optional<std::pair<size_t, size_t>> find_overlapping_openings(std::span<const Opening> openings);

// Why `points` is not a simple polygon (a repeated point, edges folding back, zero area, crossing
// edges), or "" when it is one. Either winding is accepted.
std::string simple_polygon_problem(std::span<const Vec2> points);

// The position in `face` of an index that also appears earlier in it, or nullopt.
std::optional<size_t> find_repeated_index(std::span<const uint32_t> face);

struct BadFace {
  size_t face = 0;
  std::string problem;
};

// The first face (indices already in range) with zero area or not planar within 1e-6 of the bounding
// box diagonal of `vertices`; nullopt when all are fine.
std::optional<BadFace> find_bad_mesh_face(std::span<const Vec3> vertices, std::span<const std::vector<uint32_t>> faces);

}  // namespace rr

// Lighting model shared by every pipeline: ambient + Lambert diffuse from directional and point
// lights (Blinn-Phong specular joins with the lighting issue). Input: world-space position and unit
// normal; output: a display colour in [0, 1]. Open surfaces (not part of a closed object) are lit on
// the side facing the eye, so a single triangle seen from behind is not black.
#pragma once

#include "scene.hpp"
#include "tessellate.hpp"

#include <array>
#include <span>
#include <string_view>

namespace rr {

struct ShadingInfo {
  ShadingMode mode;
  const char* name;
};
std::span<const ShadingInfo> shading_table();
const ShadingInfo* find_shading(std::string_view name);

// Lambert + ambient at one point with normal `n` (unit), already facing the side being lit.
Color shade_lambert(const Scene& scene, const Material& material, Vec3 p_world, Vec3 n);

// Flat shading: one colour per polygon, lighting evaluated once at its centroid with its face
// normal (flipped toward the eye for open surfaces). Lights behind the polygon's plane cost nothing
// beyond the plane test.
Color shade_flat(const Scene& scene, const PolygonSoup& soup, const Polygon& polygon, Vec3 eye);

}  // namespace rr

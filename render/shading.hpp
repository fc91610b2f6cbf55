// Lighting model shared by every pipeline: ambient + Lambert diffuse from directional and point
// lights (Blinn-Phong specular joins with the lighting issue). Input: world-space position and unit
// normal; output: a display colour in [0, 1]. Open surfaces (not part of a closed object) are lit on
// the side facing the eye, so a single triangle seen from behind is not black.
#pragma once

#include "draw.hpp"
#include "pipeline.hpp"
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

// Shading of the polygons of one frame, shared by every pipeline:
//   prepare(i)   once per polygon that may be visible (the "shade" stage): per-polygon lighting;
//   bind(i, s)   after project_polygon, before drawing it: selects the polygon and its clipped vertices;
//   fragment(f, k) per covered pixel: the colour (constant for flat shading).
class SurfaceShader {
 public:
  // `soup` holds the polygons being drawn: input.soup, or fragments made from it (painter splits,
  // BSP fragments) that keep their source's id, material, object and flags.
  SurfaceShader(const FrameInput& input, const PolygonSoup& soup);
  void prepare(uint32_t index);
  void bind(uint32_t index, const DrawScratch& scratch);
  Color fragment(const Fragment&, size_t) const { return current_; }

 private:
  const FrameInput& input_;
  const PolygonSoup& soup_;
  std::vector<Color> flat_;  // per polygon index
  Color current_{0.0f};
};

}  // namespace rr

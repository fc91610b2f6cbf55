// Shadow maps of one frame (docs/lighting.md). Input: the tessellated scene (world space), the
// camera's view, the lights and options.shadow. Output: one depth map per directional light
// (orthographic, fitted to the receivers the camera sees) and up to six per point light (a cube
// map), built once per frame before the pipeline draws. Map texels hold "nearness", larger = nearer
// the light and 0 = nothing: metres before the map's far plane (directional) or 1/w, one over the
// distance along the face axis (cube faces). Both are affine in texel coordinates across a planar
// polygon, so the rasterizer interpolates them exactly and the receiver-plane bias extrapolates
// them exactly.
#pragma once

#include "camera.hpp"
#include "cancel.hpp"
#include "scene.hpp"
#include "tessellate.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace rr {

// Built-in biases, in texel widths at the receiver (docs/lighting.md explains the values);
// options.shadow.bias and slope_bias are added to them.
constexpr double shadow_default_bias = 0.2;
constexpr double shadow_default_slope_bias = 0.1;
// The slope term stops growing past this depth change per texel (in texel widths, ~86 degrees):
// receivers that grazing are lit by cos < 0.07 and a larger bias would only detach shadows.
constexpr double shadow_max_slope = 16.0;
// Memory bound of one frame's maps: 6 x 2048^2 texels (96 MiB of floats), one default cube map.
// When the lights need more, every map's side shrinks by the same factor (docs/lighting.md).
constexpr size_t shadow_max_texels = size_t{6} * 2048 * 2048;

struct ShadowMap {
  ViewTransform view;           // the light's camera: clip_from_world, width == height == side
  std::vector<float> nearness;  // side * side, row-major from the top-left; 0 = nothing there
};

struct ShadowLight {
  uint32_t light = 0;  // index into Scene::lights
  bool directional = true;
  // Directional: light-space axes (forward = the direction the light travels) and the map frame:
  // u = (dot(p, right) - left) / texel_u, v = (top - dot(p, up)) / texel_v, nearness =
  // far_depth - dot(p, forward).
  Vec3 right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0}, forward{0.0, -1.0, 0.0};
  double left = 0.0, top = 0.0, texel_u = 1.0, texel_v = 1.0, far_depth = 0.0;
  Vec3 position{0.0};  // point light
  // Index into ShadowMaps::maps per cube face (+X, -X, +Y, -Y, +Z, -Z), or [0] for a directional
  // map; -1 where nothing was drawn (every lookup there is lit).
  std::array<int32_t, 6> map{-1, -1, -1, -1, -1, -1};
};

struct ShadowMaps {
  int side = 0;  // texels per map side (options.shadow.size, reduced to fit shadow_max_texels)
  int pcf = 1;   // kernel width: 1, 3 or 5
  double bias = shadow_default_bias;  // constant, texel widths
  double slope_bias = shadow_default_slope_bias;
  std::vector<int32_t> slot_of_light;  // per scene light: index into `lights`, -1 = never shadowed
  std::vector<ShadowLight> lights;     // the lights that have at least one map
  std::vector<ShadowMap> maps;
  bool empty() const { return lights.empty(); }
};

// The side of a polygon the shader lights: its front, or for an open surface (not part of a closed
// object) the side the eye sees. Returns +1 or -1, the factor for its normal and plane offset.
inline double lit_side(const Polygon& polygon, Vec3 eye) {
  const bool behind = glm::dot(polygon.normal, eye) - polygon.offset < 0.0;
  return !(polygon.flags & polygon_closed) && behind ? -1.0 : 1.0;
}

// Whether a light can reach the lit side of a plane (unit normal, offset: dot(normal, p) == offset
// on it). A light behind the plane is neither evaluated nor looked up for polygons on it.
inline bool light_reaches(const Light& light, Vec3 lit_normal, double lit_offset) {
  if (light.type == LightType::directional) return glm::dot(lit_normal, light.direction) < 0.0;
  return glm::dot(lit_normal, light.position) - lit_offset > 0.0;
}

// The shadow pass. Returns empty maps (nothing to look up) when no light can cast a shadow onto a
// receiver the camera sees. Checks `cancel` every few thousand polygons.
ShadowMaps build_shadow_maps(const Scene& scene, const PolygonSoup& soup, const ViewTransform& view,
                             const RenderOptions& options, const CancelToken* cancel = nullptr);

// The affine per-light coordinates of a world point that a pipeline interpolates across a polygon:
// directional (u, v, nearness) of its map; point light: p - light position.
Vec3 shadow_coords(const ShadowLight& light, Vec3 p_world);

// Receiver-plane constants of one planar polygon (any normal sign) for one light: the change of
// nearness per texel step in u and v, per cube face (a directional light uses [0]).
struct ShadowReceiver {
  std::array<glm::dvec2, 6> gradient{};
};
ShadowReceiver make_shadow_receiver(const ShadowMaps& maps, const ShadowLight& light, Vec3 normal,
                                    double offset);

// Fraction of the PCF taps around `coords` (from shadow_coords) that see the light, in [0, 1].
// Each tap compares the map with the receiver's own plane extrapolated to that texel's centre,
// moved toward the light by the constant and slope-scaled bias.
float shadow_visibility(const ShadowMaps& maps, const ShadowLight& light,
                        const ShadowReceiver& receiver, Vec3 coords);

// Convenience for tests and reference renderers: the visibility of scene light `light_index` at a
// point of a receiver plane; 1 when that light has no map.
float shadow_visibility_at(const ShadowMaps& maps, size_t light_index, Vec3 p_world, Vec3 normal,
                           double offset);

}  // namespace rr

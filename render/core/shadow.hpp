// Shadow maps of one frame (docs/lighting.md). Input: the tessellated scene (world space), the
// camera's view, the lights and options.shadow. Output: one depth map per directional light
// (orthographic, fitted to the receivers the camera sees) and up to six per point light (a cube
// map), built once per frame before the pipeline draws. Map texels hold "nearness", larger = nearer
// the light and 0 = nothing: metres before the map's far plane (directional) or 1/w, one over the
// distance along the face axis (cube faces). Both are affine in texel coordinates across a planar
// polygon, so the rasterizer interpolates them exactly and the receiver-plane bias extrapolates
// them exactly.
#pragma once

#include "render/core/camera.hpp"
#include "render/core/cancel.hpp"
#include "render/core/scene.hpp"
#include "render/core/tessellate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace rr {

// Built-in biases, in texel widths at the receiver (docs/lighting.md explains the values);
// options.shadow.bias and slope_bias are added to them.
constexpr double shadow_default_bias = 0.2;
constexpr double shadow_default_slope_bias = 0.1;
// A lit face of a closed object is never compared with its own depth: its object casts with its
// faces turned away from the light only, at least its thickness behind it. So it needs no bias
// against acne and no plane extrapolation, and both would light it where it meets another caster
// at a concave joint (a wall's lit face under a ceiling): within a texel of the joint the taps
// read past the caster's edge, or extrapolate the receiver's plane above the caster. Such a
// receiver compares its own nearness, moved this many texel widths away from the light: a caster
// whose nearness changes by at most one texel width per texel step (a ceiling under a sun 45
// degrees or more above the horizon) then still covers the receiver next to the joint, and only
// a closed object thinner than a texel width along the light, or the last texel width of its lit
// face before its silhouette, reads its own far side. options.shadow.bias still adds to it.
constexpr double shadow_closed_receiver_bias = -1.0;
// The slope term stops growing past this depth change per texel (in texel widths, ~86 degrees):
// receivers that grazing are lit by cos < 0.07 and a larger bias would only detach shadows.
constexpr double shadow_max_slope = 16.0;
// Memory bound of one frame's maps: 6 x 2048^2 texels (96 MiB of floats), one default cube map.
// When the lights need more, every map's side shrinks by the same factor (docs/lighting.md).
constexpr size_t shadow_max_texels = size_t{6} * 2048 * 2048;

// The texels of one map, allocated where casters land: pages of 32x32 texels (4 KiB) are made on
// a page's first write, and a page never written reads as 0 (nothing there). A room's casters
// cover a fraction of each map, so a frame zeroes and touches that fraction, not side^2 floats
// (a cube map at 2048^2 would be 96 MiB). Within a page, texels lie in 8x8 tiles (256 bytes), so
// the texels that neighbouring pixels of a receiver read share cache lines whichever way the
// light's view crosses the screen.
class TexelStore {
 public:
  static constexpr int page_side = 32;
  static constexpr size_t page_texels = page_side * page_side;

  TexelStore() = default;
  explicit TexelStore(int side);

  float at(int u, int v) const {
    const uint32_t page = pages_[page_of(u, v)];
    return page ? pool_[size_t(page - 1) * page_texels + offset(u, v)] : 0.0f;
  }
  float& write(int u, int v) {
    uint32_t& page = pages_[page_of(u, v)];
    if (!page) {  // capacity for every page, reserved at the first: this never reallocates
      if (pool_.capacity() == 0) pool_.reserve(pages_.size() * page_texels);
      pool_.resize(pool_.size() + page_texels, 0.0f);
      page = uint32_t(pool_.size() / page_texels);
    }
    return pool_[size_t(page - 1) * page_texels + offset(u, v)];
  }
  // For writers that fill disjoint pages concurrently: gives every page flagged in `written` (one
  // byte per page, row-major; none written so far) its storage in one exact allocation, not zeroed:
  // each page's writer zero-fills it through page_data before drawing, so no writer allocates. A map
  // kept in the shadow cache then holds, and is charged for, those pages only.
  void allocate_pages(std::span<const uint8_t> written);
  float* page_data(size_t row, size_t column) {
    const uint32_t page = pages_[row * pages_per_row_ + column];
    return page ? pool_.data() + size_t(page - 1) * page_texels : nullptr;
  }
  // Where texel (u, v) lies in its page: 8x8 tiles of 64 texels, row-major within each.
  static size_t offset(int u, int v) {
    return (size_t((v & 31) >> 3) * 4 + size_t((u & 31) >> 3)) * 64 + size_t(v & 7) * 8 + size_t(u & 7);
  }
  size_t pages_per_row() const { return pages_per_row_; }
  size_t bytes() const { return pages_.capacity() * sizeof(uint32_t) + pool_.capacity() * sizeof(float); }
  // The 16 tiles of 64 texels of page (row, column), tile (ty, tx) at [(ty * 4 + tx) * 64];
  // null when the page was never written.
  const float* page(size_t row, size_t column) const {
    const uint32_t page = pages_[row * pages_per_row_ + column];
    return page ? pool_.data() + size_t(page - 1) * page_texels : nullptr;
  }

 private:
  // Leaves a resized float uninitialized, so allocate_pages does not zero pages on one thread.
  template <class T>
  struct NoZeroAllocator : std::allocator<T> {
    NoZeroAllocator() = default;
    template <class U>
    NoZeroAllocator(const NoZeroAllocator<U>&) noexcept {}
    template <class U>
    struct rebind {
      using other = NoZeroAllocator<U>;
    };
    template <class U>
    void construct(U* p) noexcept {
      ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  };
  size_t page_of(int u, int v) const { return size_t(v >> 5) * pages_per_row_ + size_t(u >> 5); }
  size_t pages_per_row_ = 0;
  std::vector<uint32_t> pages_;  // per page: 0 = never written, else 1 + its index in pool_
  std::vector<float, NoZeroAllocator<float>> pool_;
};

// Texels per side of the blocks whose nearness range lets most lookups skip the full-resolution
// map: a block wholly nearer or farther than the receiver decides every tap in it.
constexpr int shadow_block = 16;

struct ShadowMap {
  ViewTransform view;   // the light's camera: clip_from_world, width == height == side
  TexelStore nearness;  // texel (u, v) from the top-left; 0 = nothing there
  int blocks_per_row = 0;
  std::vector<float> block_min, block_max;  // per shadow_block^2 block, row-major
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
  int side = 0;                       // texels per map side (options.shadow.size, reduced to fit shadow_max_texels)
  int pcf = 1;                        // kernel width: 1, 3 or 5
  double bias = shadow_default_bias;  // constant, texel widths
  double slope_bias = shadow_default_slope_bias;
  std::vector<int32_t> slot_of_light;  // per scene light: index into `lights`, -1 = never shadowed
  std::vector<ShadowLight> lights;     // the lights that have at least one map
  std::vector<ShadowMap> maps;
  bool empty() const { return lights.empty(); }
  size_t bytes() const;  // what the maps cost against the shadow cache's budget
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
// receiver the camera sees. Checks `cancel` every few thousand polygons. With options.shadow.fit
// == scene the receivers are every polygon of the scene, on each side a camera could see lit, and
// `view` is not read: the maps serve every camera (the shadow cache relies on it). Runs on `threads`
// threads; the maps are the same for any count.
ShadowMaps build_shadow_maps(const Scene& scene, const PolygonSoup& soup, const ViewTransform& view,
                             const RenderOptions& options, const CancelToken* cancel = nullptr, unsigned threads = 1);

// The affine per-light coordinates of a world point that a pipeline interpolates across a polygon:
// directional (u, v, nearness) of its map; point light: p - light position.
Vec3 shadow_coords(const ShadowLight& light, Vec3 p_world);

// Receiver-plane constants of one planar polygon (any normal sign) for one light: the change of
// nearness per texel step in u and v, per cube face (a directional light uses [0]), and the texel
// widths added to the maps' constant bias. A closed object's face (`closed`) has no gradient and
// the shift that makes its bias shadow_closed_receiver_bias.
struct ShadowReceiver {
  std::array<glm::dvec2, 6> gradient{};
  double shift = 0.0;
};
ShadowReceiver make_shadow_receiver(const ShadowMaps& maps, const ShadowLight& light, Vec3 normal, double offset,
                                    bool closed = false);

// Lookups, inline: they run for every shadowed pixel.
namespace shadow_detail {

// Axes of one cube face: the light looks along `forward` with `up` at the top of the map.
struct CubeFace {
  Vec3 forward, up, right;  // right = cross(forward, up)
};
inline const std::array<CubeFace, 6> cube_faces = {{
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
    {{-1, 0, 0}, {0, 1, 0}, {0, 0, -1}},
    {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
    {{0, -1, 0}, {0, 0, 1}, {-1, 0, 0}},
    {{0, 0, 1}, {0, 1, 0}, {-1, 0, 0}},
    {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
}};

// The face whose frustum holds direction d (ties go to the first face listed).
inline int cube_face_of(Vec3 d) {
  const Vec3 a = glm::abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
  if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
  return d.z >= 0.0 ? 4 : 5;
}

// Percentage-closer filter: taps on the pcf x pcf texels around (u, v). `texel` is one texel's width
// in nearness units at the receiver, the unit of both biases and of the receiver's `shift`.
inline float filter_taps(const ShadowMaps& maps, const ShadowMap& map, double u, double v, double nearness,
                         glm::dvec2 g, double texel, double shift = 0.0) {
  const double g_max = shadow_max_slope * texel;
  g = glm::clamp(g, glm::dvec2(-g_max), glm::dvec2(g_max));
  const double slope = std::max(std::abs(g.x), std::abs(g.y)) / texel;
  const double base = nearness + (maps.bias + maps.slope_bias * slope + shift) * texel;
  const int side = maps.side, radius = maps.pcf / 2;
  const int cu = int(std::floor(u)), cv = int(std::floor(v));
  // Every tap's offset from (u, v) is within radius + 1 texels on each axis, so its threshold is
  // within `spread` of `base`: blocks wholly below or above that band decide all the taps.
  {
    auto block_of = [&](int t) { return std::clamp(t, 0, side - 1) / shadow_block; };
    const int u0 = block_of(cu - radius), u1 = block_of(cu + radius);
    const int v0 = block_of(cv - radius), v1 = block_of(cv + radius);
    float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
    for (int bv = v0; bv <= v1; ++bv) {
      for (int bu = u0; bu <= u1; ++bu) {
        lo = std::min(lo, map.block_min[size_t(bv * map.blocks_per_row + bu)]);
        hi = std::max(hi, map.block_max[size_t(bv * map.blocks_per_row + bu)]);
      }
    }
    const double spread = (std::abs(g.x) + std::abs(g.y)) * (radius + 1);
    if (double(hi) <= base - spread) return 1.0f;
    if (double(lo) > base + spread) return 0.0f;
  }
  const TexelStore& texels = map.nearness;
  int lit = 0;
  for (int dv = -radius; dv <= radius; ++dv) {
    const int tv = std::clamp(cv + dv, 0, side - 1);
    const double row = base + g.y * (tv + 0.5 - v);
    for (int du = -radius; du <= radius; ++du) {
      const int tu = std::clamp(cu + du, 0, side - 1);
      lit += double(texels.at(tu, tv)) <= row + g.x * (tu + 0.5 - u);
    }
  }
  return float(lit) / float(maps.pcf * maps.pcf);
}

}  // namespace shadow_detail

// Fraction of the PCF taps around `coords` (from shadow_coords) that see the light, in [0, 1].
// Each tap compares the map with the receiver's own plane extrapolated to that texel's centre,
// moved toward the light by the constant and slope-scaled bias.
inline float shadow_visibility(const ShadowMaps& maps, const ShadowLight& light, const ShadowReceiver& receiver,
                               Vec3 coords) {
  if (light.directional) {
    if (light.map[0] < 0) return 1.0f;
    return shadow_detail::filter_taps(maps, maps.maps[size_t(light.map[0])], coords.x, coords.y, coords.z,
                                      receiver.gradient[0], std::max(light.texel_u, light.texel_v), receiver.shift);
  }
  const int face = shadow_detail::cube_face_of(coords);
  const shadow_detail::CubeFace& f = shadow_detail::cube_faces[size_t(face)];
  const double w = glm::dot(coords, f.forward);
  if (light.map[size_t(face)] < 0 || !(w > 0.0)) return 1.0f;
  const double half = 0.5 * maps.side;
  const double u = (glm::dot(coords, f.right) / w + 1.0) * half, v = (1.0 - glm::dot(coords, f.up) / w) * half;
  // A texel is 2w/side metres wide there; d(1/w) = dw / w^2.
  return shadow_detail::filter_taps(maps, maps.maps[size_t(light.map[size_t(face)])], u, v, 1.0 / w,
                                    receiver.gradient[size_t(face)], 2.0 / (w * maps.side), receiver.shift);
}

// Convenience for tests and reference renderers: the visibility of scene light `light_index` at a
// point of a receiver plane; 1 when that light has no map.
float shadow_visibility_at(const ShadowMaps& maps, size_t light_index, Vec3 p_world, Vec3 normal, double offset);

}  // namespace rr

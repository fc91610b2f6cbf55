// Internal to the reference renderer (reference.cpp, reference_shade.cpp): the per-frame set-up
// (projected polygons, BVHs) and one pixel's hits. Nothing else includes it.
#pragma once

#include "render/core/surface.hpp"
#include "render/pipelines/reference.hpp"

#include <span>
#include <vector>

namespace rr::reference_detail {

struct ReferenceScene {
  explicit ReferenceScene(const FrameInput& frame_input) : input(frame_input) {}
  const FrameInput& input;
  std::vector<uint32_t> screen_begin;  // per polygon + 1: its projected vertices in screen_xy
  std::vector<Vec2> screen_xy;         // clipped and projected as the rasterizer does (pixels)
  Bvh view_bvh;                        // polygons that are not back-facing and survive clipping
  Bvh shadow_bvh;                      // every opaque polygon (shadows on only)
  Bvh glass_bvh;                       // every translucent polygon (shadows on only)
  bool shadows = false;
  double scene_size = 1.0;          // bounding-box diagonal of all vertices
  double scene_magnitude = 0.0;     // largest distance of the box corners from the origin
  double coplanar_tolerance = 0.0;  // coplanar.hpp: how far a plane group's polygons may lie apart
  Mat4 world_from_clip{1.0};
  PixelRays pixel_rays;  // textures: the footprints of pixels
};

struct Hit {
  uint32_t polygon = background_id;  // index into input.soup
  double t = 0.0;                    // along the pixel ray (1 = far plane)
  double depth = 0.0;                // view depth, metres
};

struct PixelHits {
  Hit opaque;  // polygon == background_id: none
  Vec3 ray_origin{0.0}, ray_direction{0.0};
};

ReferenceScene prepare_reference(const FrameInput& input, RenderStats& stats);
// The nearest opaque hit, and in `translucent` the translucent hits in front of it, far to near,
// along the ray through screen point (sx, sy) in pixels (x + 0.5, y + 0.5 is pixel (x, y)'s centre).
PixelHits cast_ray(const ReferenceScene& rs, double sx, double sy, std::vector<Hit>& translucent);
// Colour of `hit` at world point p (ambient + each light reaching its lit side, scaled by an exact
// shadow ray when shadows are on); `lit` (empty: not recorded) gets bit l % 8 of byte l / 8 set for
// each light l that reaches p, and every other bit cleared.
// `sx`, `sy`: the screen point of the ray, whose pixel's footprint a texture is averaged over.
Color shade_hit(const ReferenceScene& rs, const Hit& hit, Vec3 p, double sx, double sy, std::span<uint8_t> lit);

}  // namespace rr::reference_detail

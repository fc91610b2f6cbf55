// The shadow pass's depth-only rasterizer. In: per map, its light's clip matrix, the rule for a
// vertex's nearness and the caster polygons (world space). Out: each map's texels, bit for bit what
// rasterize_convex's fragments would leave (per texel the largest float(inv_w), 0 where nothing
// lands), drawn in map tiles on parallel_for; the set of written pages is the same too. Each tile
// then summarizes its blocks while its texels are in cache.
#pragma once

#include "render/core/camera.hpp"
#include "render/core/cancel.hpp"
#include "render/core/raster.hpp"
#include "render/core/shadow.hpp"
#include "render/core/tessellate.hpp"

#include <span>
#include <vector>

namespace rr {

namespace shadow_detail {

struct ClipBuffers {
  std::vector<ClipVertex> in, out, tmp;
  std::vector<RasterVertex> screen;
};

// Clips world points with a clip matrix; the survivors are in buf.out.
bool clip_points(const Mat4& clip_from_world, std::span<const Vec3> points, ClipBuffers& buf);

// clip_polygon keeps |x|, |y| <= clip_guard_band * w; scaling x and y by the guard band first makes
// that the exact frustum |x|, |y| <= w.
Mat4 exact_frustum(const Mat4& clip_from_world);

}  // namespace shadow_detail

// One map to draw. Casters are clipped to the map's exact frustum, not the guard band: a polygon
// next to a point light spans several faces, and its fan clipped far outside the map would only
// add triangles that cover nothing.
struct ShadowMapJob {
  Mat4 clip{1.0};  // the map's clip_from_world (side x side texels)
  // Directional maps (w = 1) hold far_depth - dot(p, forward); cube faces hold 1/w.
  bool directional = true;
  Vec3 forward{0.0};
  double far_depth = 0.0;
  std::span<const uint32_t> casters;  // polygon indices into the soup
  // Out: whether some caster survived clipping (the map exists, even if it covers no texel centre),
  // the texels and their nearness range per shadow_block^2 block (ShadowMap's fields).
  bool any_caster = false;
  TexelStore texels;
  int blocks_per_row = 0;
  std::vector<float> block_min, block_max;
};

// Draws every job on `threads` threads. Checks `cancel` between stages and throws RenderCancelled
// once the tasks have stopped.
void draw_shadow_jobs(std::span<ShadowMapJob> jobs, int side, const PolygonSoup& soup, unsigned threads,
                      const CancelToken* cancel);

}  // namespace rr

// The z-buffer pipeline's tiled visibility buffer. The front end projects the opaque polygons and
// bins their fan triangles to 64x64-pixel screen tiles; pass 1 resolves, per pixel of a tile, the
// nearest triangle (1/w and the triangle only); pass 2 shades each visible pixel once, recomputing
// its perspective-correct weights from the triangle's integer set-up (raster.hpp), then blends the
// translucent polygons over the tile. A tile is worked on by one thread at a time and its pixels
// depend only on its ordered triangle list, so the output is byte-identical for any thread count.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/raster.hpp"
#include "render/core/shading.hpp"

#include <cstdint>
#include <vector>

namespace rr {

constexpr int tile_size = 64;  // pixels; a tile's depth and triangle buffers (32 KiB) stay in L2

// One fan triangle of a projected polygon, snapped to the sub-pixel grid.
struct BinnedTriangle {
  int32_t X[3], Y[3];  // sub-pixel units; raster.hpp's bound keeps them inside int32
  double inv_w[3];
  uint32_t slot;  // index into VisibilityInput::polygons
  uint32_t k;     // fan triangle (0, k+1, k+2)
};

// The triangle's integer set-up (raster.hpp); false when it has no area.
inline bool setup_binned(const BinnedTriangle& t, TriangleSetup& s) {
  const int64_t X[3] = {t.X[0], t.X[1], t.X[2]}, Y[3] = {t.Y[0], t.Y[1], t.Y[2]};
  return setup_triangle(X, Y, s);
}

struct VisibilityInput {
  std::vector<uint32_t> polygons;     // soup index of each projected opaque polygon, in draw order
  std::vector<uint32_t> slot_groups;  // its plane group (Polygon::plane_group), 0 for none
  std::vector<BinnedTriangle> triangles;
  std::vector<std::vector<uint32_t>> bins;   // per tile, row-major: triangle indices in draw order
  std::vector<uint32_t> translucent;         // soup indices, far to near
  std::vector<PixelRect> translucent_rects;  // bounds of their projections
  int tiles_x = 0, tiles_y = 0;
};

// Pass 2's weights for the n <= tile_size covered pixels from (x, y) along +x of the snapped triangle
// `s` (inv_w in the caller's vertex order): into span.b, bit for bit what pixel_weights gives each
// of those pixels; sets span.x, .y and .count.
void span_weights(const TriangleSetup& s, const double inv_w[3], int x, int y, int n, SurfaceShader::Span& span);

// Front end (binning.cpp): projects input.soup's polygons `opaque` (in draw order) and bins their
// triangles, and bounds the `translucent` ones (far to near), on input.context.threads threads; the
// bins are the same for any thread count. Counts drawn polygons and triangles into stats.
void bin_polygons(const FrameInput& input, const std::vector<uint32_t>& opaque,
                  const std::vector<uint32_t>& translucent, VisibilityInput& out, RenderStats& stats);

// Pass 1 for every tile, then pass 2 and the translucent polygons, on `threads` threads. `shader`
// is prepared for every polygon drawn. Adds to stats.fragments; times pass 1 as raster and pass 2
// with the translucent blend as shade.
void draw_visibility(const FrameInput& input, const VisibilityInput& vis, const SurfaceShader& shader, unsigned threads,
                     Frame& frame, RenderStats& stats, StageTimings& timings);

struct TileTriangle;
// The tile A-buffer's run of pixels x .. x + n - 1 of row y wholly triangle t's, shaded at their
// centres as one span of the bound `shader` (weights from span_weights), into out[0 .. n).
void shade_as_span(const SurfaceShader& shader, const TileTriangle& t, int x, int y, int n, SurfaceShader::Span& span,
                   SurfaceShader::SpanColors& colors, Color* out);

// draw_visibility for options.antialias > 1 (visibility_aa.cpp): the same bins drawn through the
// tile A-buffer (abuffer.hpp), shading each visible surface once per pixel. Times it as raster.
void draw_visibility_aa(const FrameInput& input, const VisibilityInput& vis, const SurfaceShader& shader,
                        unsigned threads, Frame& frame, RenderStats& stats, StageTimings& timings);

}  // namespace rr

// The z-buffer pipeline's front end (see visibility.hpp): projection of the opaque polygons and
// binning of their fan triangles to screen tiles. Projection and triangle set-up, the costly part,
// run on the render pool over fixed chunks of the draw order; the chunks' results are then appended
// in chunk order, so slots, triangle indices and every bin come out as one thread would make them.
#include "render/pipelines/visibility.hpp"

#include "render/core/draw.hpp"
#include "render/core/occlusion.hpp"
#include "render/core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace rr {

namespace {

// Polygons per chunk: a few hundred microseconds of projection, so a 10^6-polygon soup makes ~2,000
// tasks and a room of 2,000 polygons still makes several.
constexpr size_t chunk_polygons = 512;

// What one chunk of the draw order produced; slots in `triangles` count from the chunk's first.
struct Chunk {
  std::vector<uint32_t> polygons;  // soup indices that projected
  std::vector<BinnedTriangle> triangles;
  std::vector<PixelRect> tiles;  // per triangle: its tile range, half-open
  // With occlusion culling, per triangle: no_skip, or where its row-major flags over `tiles` start
  // in `skip` (1: every pixel it could reach in that tile lies behind the depth pyramid).
  std::vector<uint32_t> skip_first;
  std::vector<uint8_t> skip;
  size_t triangles_drawn = 0;  // fan triangles after clipping, empty ones included (stats)
};
constexpr uint32_t no_skip = 0xFFFFFFFFu;

// Flags the tiles of triangle `t` (pixel bounds px0..px1, py0..py1, sub-sample margin included) in
// which it lies wholly behind the frame's depth pyramid: inside a triangle 1/w is a blend of its
// vertices', so the largest of those bounds all of it (docs/culling.md). Returns whether any is.
bool flag_hidden_tiles(const FrameInput& input, const BinnedTriangle& t, int px0, int py0, int px1, int py1,
                       const PixelRect& tiles, Chunk& out) {
  const DepthPyramid& pyramid = *input.occlusion;
  const double widen = 1.0 + occlusion_margin - 2.0 * double(input.context.cull_eager) * occlusion_margin;
  const double near = std::max({t.inv_w[0], t.inv_w[1], t.inv_w[2]}) * widen;
  const size_t first = out.skip.size();
  bool any = false;
  for (int ty = tiles.y0; ty < tiles.y1; ++ty) {
    for (int tx = tiles.x0; tx < tiles.x1; ++tx) {
      const int x0 = std::max(px0, tx * tile_size), x1 = std::min(px1 + 1, (tx + 1) * tile_size);
      const int y0 = std::max(py0, ty * tile_size), y1 = std::min(py1 + 1, (ty + 1) * tile_size);
      const bool hidden = pyramid.hidden(x0 - 1, y0 - 1, x1 + 1, y1 + 1, near);
      out.skip.push_back(uint8_t(hidden));
      any = any || hidden;
    }
  }
  if (!any) out.skip.resize(first);
  out.skip_first.push_back(any ? uint32_t(first) : no_skip);
  return any;
}

void bin_chunk(const FrameInput& input, const std::vector<uint32_t>& opaque, size_t begin, size_t end, int tiles_x,
               int tiles_y, Chunk& out) {
  out.polygons.clear();
  out.triangles.clear();
  out.tiles.clear();
  out.skip_first.clear();
  out.skip.clear();
  out.triangles_drawn = 0;
  const bool occlusion = input.occlusion && !input.occlusion->empty();
  const int width = input.view.width, height = input.view.height;
  const int margin = input.options.antialias > 1 ? 1 : 0;
  thread_local DrawScratch scratch;
  for (size_t n = begin; n < end; ++n) {
    const uint32_t i = opaque[n];
    if (!project_polygon(input.view, input.soup, input.soup.polygons[i], scratch)) continue;
    const uint32_t slot = uint32_t(out.polygons.size());
    out.polygons.push_back(i);
    const size_t corners = scratch.screen.size();
    out.triangles_drawn += corners - 2;
    int32_t sx[64], sy[64];  // clipping a convex polygon adds at most one vertex per plane
    std::vector<int32_t> big_x, big_y;
    int32_t* xs = sx;
    int32_t* ys = sy;
    if (corners > 64) big_x.resize(corners), big_y.resize(corners), xs = big_x.data(), ys = big_y.data();
    for (size_t v = 0; v < corners; ++v) {
      xs[v] = int32_t(snap_to_subpixel(scratch.screen[v].x)), ys[v] = int32_t(snap_to_subpixel(scratch.screen[v].y));
    }
    for (uint32_t k = 0; k + 2 < corners; ++k) {
      const size_t v[3] = {0, k + 1, k + 2};
      BinnedTriangle t{{xs[v[0]], xs[v[1]], xs[v[2]]},
                       {ys[v[0]], ys[v[1]], ys[v[2]]},
                       {scratch.screen[v[0]].inv_w, scratch.screen[v[1]].inv_w, scratch.screen[v[2]].inv_w},
                       slot,
                       k};
      TriangleSetup s;
      if (!setup_binned(t, s)) continue;
      // Sub-samples lie within half a pixel of the centres: with them, one pixel more each way.
      const int px0 = std::max(0, s.px0 - margin), px1 = std::min(width - 1, s.px1 + margin);
      const int py0 = std::max(0, s.py0 - margin), py1 = std::min(height - 1, s.py1 + margin);
      if (px0 > px1 || py0 > py1) continue;
      out.triangles.push_back(t);
      out.tiles.push_back({px0 / tile_size, py0 / tile_size, std::min(tiles_x, px1 / tile_size + 1),
                           std::min(tiles_y, py1 / tile_size + 1)});
      // A triangle within one tile was tested with its hierarchy node; larger ones, tile by tile.
      const PixelRect& r = out.tiles.back();
      if (occlusion && (r.x1 - r.x0) * (r.y1 - r.y0) > 1) flag_hidden_tiles(input, t, px0, py0, px1, py1, r, out);
      else if (occlusion) out.skip_first.push_back(no_skip);
    }
  }
}

// A pixel rectangle holding every pixel centre the projected polygon can cover, clamped to the frame.
PixelRect screen_bounds(const std::vector<RasterVertex>& screen, int width, int height) {
  double x0 = screen[0].x, x1 = x0, y0 = screen[0].y, y1 = y0;
  for (const RasterVertex& v : screen) {
    x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
  }
  auto clamp = [](double v, int hi) { return int(std::clamp(v, 0.0, double(hi))); };
  return {clamp(std::floor(x0) - 1, width), clamp(std::floor(y0) - 1, height), clamp(std::ceil(x1) + 1, width),
          clamp(std::ceil(y1) + 1, height)};
}

// Appends chunk `c`'s polygons and triangles to `out` and its triangles to their tiles' bins.
void append_chunk(const FrameInput& input, const Chunk& c, VisibilityInput& out, RenderStats& stats) {
  const uint32_t slot0 = uint32_t(out.polygons.size());
  for (uint32_t i : c.polygons) {
    out.polygons.push_back(i);
    out.slot_groups.push_back(input.soup.polygons[i].plane_group);
  }
  stats.polygons_drawn += c.polygons.size();
  stats.triangles += c.triangles_drawn;
  for (size_t n = 0; n < c.triangles.size(); ++n) {
    const uint32_t index = uint32_t(out.triangles.size());
    out.triangles.push_back(c.triangles[n]);
    out.triangles.back().slot += slot0;
    const PixelRect& r = c.tiles[n];
    const uint8_t* skip = c.skip_first.empty() || c.skip_first[n] == no_skip ? nullptr : &c.skip[c.skip_first[n]];
    for (int ty = r.y0; ty < r.y1; ++ty) {
      for (int tx = r.x0; tx < r.x1; ++tx) {
        if (skip && *skip++) continue;
        out.bins[size_t(ty * out.tiles_x + tx)].push_back(index);
      }
    }
  }
}

}  // namespace

void bin_polygons(const FrameInput& input, const std::vector<uint32_t>& opaque,
                  const std::vector<uint32_t>& translucent, VisibilityInput& out, RenderStats& stats) {
  const int width = input.view.width, height = input.view.height;
  out.tiles_x = (width + tile_size - 1) / tile_size;
  out.tiles_y = (height + tile_size - 1) / tile_size;
  out.bins.resize(size_t(out.tiles_x) * size_t(out.tiles_y));
  for (auto& bin : out.bins) bin.clear();
  out.polygons.clear();
  out.slot_groups.clear();
  out.triangles.clear();
  out.translucent.clear();
  out.translucent_rects.clear();

  // Kept by this thread for its next frame, so the chunks' memory is not allocated again. A
  // reference, because inside the workers' lambda the name would mean the workers' own thread_local.
  thread_local std::vector<Chunk> kept_chunks;
  std::vector<Chunk>& chunks = kept_chunks;
  const size_t count = (opaque.size() + chunk_polygons - 1) / chunk_polygons;
  if (chunks.size() < count) chunks.resize(count);
  const CancelToken* cancel = input.context.cancel;
  std::atomic<bool> expired{false};
  parallel_for(input.context.threads, count, [&](size_t c, unsigned) {
    // A task cannot throw: an expired deadline skips the remaining chunks and is raised below.
    if (expired.load(std::memory_order_relaxed) || (cancel && cancel->expired())) {
      expired = true;
      return;
    }
    bin_chunk(input, opaque, c * chunk_polygons, std::min(opaque.size(), (c + 1) * chunk_polygons), out.tiles_x,
              out.tiles_y, chunks[c]);
  });
  if (expired) throw RenderCancelled();
  CancelMeter meter(cancel, 64);  // units: chunks appended
  for (size_t c = 0; c < count; ++c) {
    meter.add(1);
    append_chunk(input, chunks[c], out, stats);
  }

  DrawScratch scratch;
  for (uint32_t i : translucent) {
    if (!project_polygon(input.view, input.soup, input.soup.polygons[i], scratch)) continue;
    ++stats.polygons_drawn;
    stats.triangles += scratch.screen.size() - 2;
    out.translucent.push_back(i);
    out.translucent_rects.push_back(screen_bounds(scratch.screen, width, height));
  }
}

}  // namespace rr

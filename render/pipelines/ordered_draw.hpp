// Tiled drawing of polygons in a fixed priority order, shared by the painter and bsp pipelines. In:
// polygons in drawing order, each projected once (ProjectedSet) and binned to screen tiles; out: the
// frame's image and ids. One thread draws a tile at a time, walking its bin in the drawing order, so
// every pixel sees the same sequence of writes as a whole-frame draw with draw_projected (the same
// exact rasterizer restricted to the tile): byte-identical for any thread count.
#pragma once

#include "render/core/draw.hpp"
#include "render/core/frame.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace rr {

class SurfaceShader;

// Where drawn polygons come from: their soup and the shader prepared for them.
struct DrawSource {
  const PolygonSoup* soup = nullptr;
  const SurfaceShader* shader = nullptr;
};

// Polygon `index` of sources[source].soup.
struct OrderedItem {
  uint32_t index = 0;
  uint32_t source = 0;
};

struct ProjectedPolygon {
  OrderedItem item;
  uint32_t id = 0;
  bool translucent = false;
  float alpha = 1.0f;     // material opacity when translucent, else 1
  uint32_t seq = 0;       // the caller's position for it (first-wins drawing compares it with writers)
  uint32_t triangle = 0;  // its first fan triangle's number: numbers grow along the drawing order
  uint32_t first = 0;     // its clipped vertices: ProjectedSet::clipped and ::screen [first, first + count)
  uint32_t count = 0;
  PixelRect bounds;  // holds every pixel centre it can cover, within the frame
};

// Polygons in drawing order, clipped and projected (what draw.hpp's project_polygon leaves).
struct ProjectedSet {
  std::vector<ProjectedPolygon> polygons;
  std::vector<ClipVertex> clipped;
  std::vector<RasterVertex> screen;
  size_t triangles = 0;  // fan triangles of the polygons

  void clear();
  // Frees the arrays when they outgrew a room's frame: a set kept for a thread's next frame should
  // not pin a huge soup's hundreds of megabytes.
  void release_if_large();
  // Appends the polygon last projected into `scratch`.
  void add(const DrawScratch& scratch, const DrawSource& source, OrderedItem item, uint32_t seq, int width, int height);
  std::span<const RasterVertex> screen_of(const ProjectedPolygon& p) const {
    return {screen.data() + p.first, p.count};
  }
};

// Projects `items` in order (in chunks on `threads` threads) into `out`, numbering them by their
// position in `items` (ProjectedPolygon::seq). Returns how many clipping dropped.
size_t project_in_order(const ViewTransform& view, std::span<const DrawSource> sources,
                        std::span<const OrderedItem> items, unsigned threads, ProjectedSet& out);

// Screen tiles and, per tile, the positions in a ProjectedSet of the polygons whose bounds meet it.
struct TileGrid {
  static constexpr int tile = 64;  // pixels
  int width = 0, height = 0, tiles_x = 0, tiles_y = 0;
  std::vector<std::vector<uint32_t>> bins;  // row-major; increasing positions

  PixelRect rect(size_t t) const;
};
void bin_projected(const ProjectedSet& set, int width, int height, TileGrid& grid);

// Last writer wins (DepthMode::none): what draw_projected leaves after drawing the set's polygons
// in order. Returns the covered pixels (draw_projected's sum); adds per-pixel light evaluations to
// *input.lights_evaluated. Unless every polygon has one colour, a tile first finds each pixel's
// last opaque triangle and shades only that one and the translucent polygons drawn after it, so
// Phong evaluates its lights once per pixel instead of once per covered fragment.
size_t draw_last_wins(const FrameInput& input, std::span<const DrawSource> sources, const ProjectedSet& set,
                      const TileGrid& grid, unsigned threads, Frame& frame);

// First opaque writer wins, for a walk that has already decided coverage: frame.ids holds, per
// pixel, the seq of the opaque polygon that claimed it (background_id for none). The set holds the
// opaque polygons in walk order, then the translucent ones back to front. Each pixel takes the
// colour of its claimant (from the claimant's first fan triangle covering it); translucent polygons
// then blend over the pixels whose writer has a larger seq (lies behind them) and take them over;
// finally seqs become ids (id_of[seq]). Returns the translucent polygons' covered pixels.
size_t draw_first_wins(const FrameInput& input, std::span<const DrawSource> sources, const ProjectedSet& set,
                       const std::vector<uint32_t>& id_of, const TileGrid& grid, unsigned threads, Frame& frame);

// draw_last_wins (first_wins = false) or draw_first_wins (true) for options.antialias > 1
// (ordered_draw_aa.cpp): per tile, the polygons' order decides each sub-sample's owner, translucent
// ones composite over the samples they are in front of, and each surface is shaded once per pixel.
// Ids are polygon ids (the surface under the pixel centre); for first wins frame.ids is not read.
size_t draw_ordered_aa(const FrameInput& input, std::span<const DrawSource> sources, const ProjectedSet& set,
                       const TileGrid& grid, bool first_wins, unsigned threads, Frame& frame);

// Calls fn(y, x, n, e) for each row of the triangle's covered pixels in `rect` (x .. x + n - 1 on
// row y, edge values e[] at (x, y)): the pixels rasterize_triangle visits, in its order.
template <class Fn>
void triangle_spans(const TriangleSetup& s, const PixelRect& rect, Fn&& fn) {
  const int px0 = std::max(rect.x0, s.px0), px1 = std::min(rect.x1 - 1, s.px1);
  const int py0 = std::max(rect.y0, s.py0), py1 = std::min(rect.y1 - 1, s.py1);
  if (px0 > px1 || py0 > py1) return;
  int64_t e_row[3] = {s.edge(0, px0, py0), s.edge(1, px0, py0), s.edge(2, px0, py0)};
  for (int y = py0; y <= py1; ++y) {
    int64_t first, last = px1 - px0;
    row_span(s, e_row, first, last);
    if (last >= first) {
      const int64_t e[3] = {e_row[0] + first * s.step_x[0], e_row[1] + first * s.step_x[1],
                            e_row[2] + first * s.step_x[2]};
      fn(y, px0 + int(first), int(last - first + 1), e);
    }
    for (int k = 0; k < 3; ++k) e_row[k] += s.step_y[k];
  }
}

// rasterize_triangle's set-up of screen triangle (a, b, c); false when it covers nothing.
inline bool setup_screen_triangle(const RasterVertex& a, const RasterVertex& b, const RasterVertex& c,
                                  TriangleSetup& s) {
  const int64_t X[3] = {snap_to_subpixel(a.x), snap_to_subpixel(b.x), snap_to_subpixel(c.x)};
  const int64_t Y[3] = {snap_to_subpixel(a.y), snap_to_subpixel(b.y), snap_to_subpixel(c.y)};
  return setup_triangle(X, Y, s);
}

}  // namespace rr

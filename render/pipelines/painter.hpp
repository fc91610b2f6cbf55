// The painter pipeline: no depth buffer, visibility comes only from the drawing order. Polygons that
// cannot be seen (back faces of closed solids, polygons wholly outside the view) are dropped first;
// the rest are sorted back to front by a view-depth key and drawn with DepthMode::none, so the last
// polygon drawn on a pixel owns its colour and its id. Translucent polygons blend in that same order.
//
// Keys (options.painter_key, docs/painter.md): `mean`, `min` (nearest vertex) and `max` (farthest
// vertex) view depth of the polygon's vertices, the classic variants with their classic failures
// (intersecting polygons, cyclic overlap, long polygons spanning the depth range); and `newell`, the
// mean order refined by the Newell-Newell-Sancha tests on pairs that overlap on screen, splitting
// polygons where no order of whole polygons is right, so the order is exact.
//
// Ties: equal keys draw the higher polygon id first, so the lower id is drawn last and wins, which is
// also what the zbuffer pipeline keeps on equal depth; the sort is total, so the order is
// deterministic.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/tessellate.hpp"

#include <cstdint>
#include <vector>

namespace rr {

// One entry of a drawing order: polygon `index` of input.soup, or of PainterOrder::fragments.
struct PainterItem {
  uint32_t index = 0;
  bool fragment = false;
};

struct PainterOrder {
  PolygonSoup fragments;           // pieces cut by Newell splits; they keep their source's id
  std::vector<PainterItem> items;  // back to front: draw in this order
  size_t culled = 0;               // input polygons dropped: back faces of closed solids, outside the view
  size_t projected = 0;            // input polygons clipped and projected
  size_t pairs_tested = 0;         // newell: pair tests that went beyond the depth-extent test
  size_t splits = 0;               // newell: polygons cut in two
  bool budget_exhausted = false;   // newell: a work bound was reached (docs/painter.md)
};

// The drawing order of one frame for `key` (what draw_painter times as sort_ms).
PainterOrder painter_order(const FrameInput& input, PainterKey key);

// The pipeline function of the table's "painter" row: sort_ms = culling + keys + sort (+ Newell),
// shade_ms = per-polygon shading prepare, raster_ms = drawing.
void draw_painter(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings);

}  // namespace rr

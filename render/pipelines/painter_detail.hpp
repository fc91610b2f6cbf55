// Internals shared by painter.cpp (culling, keys, sort, drawing) and newell.cpp (the
// Newell-Newell-Sancha refinement). Not part of the renderer's interface.
#pragma once

#include "render/core/draw.hpp"
#include "render/pipelines/painter.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rr::painter_detail {

// A polygon that survived culling, with what sorting and the Newell tests need.
struct SortItem {
  uint32_t index = 0;  // in input.soup, or in PainterOrder::fragments when `fragment`
  bool fragment = false;
  uint32_t id = 0;    // the polygon id (fragments keep their source's)
  double key = 0.0;   // the sort key's view depth (larger is farther)
  double dmin = 0.0;  // nearest and farthest view depth of the polygon's vertices
  double dmax = 0.0;
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;  // screen box of the visible part (in the viewport)
  uint32_t screen_first = 0;                      // the visible part on screen (clipped to the view volume and the
  uint32_t screen_count = 0;                      // viewport): ItemBuilder::screen[first, first + count); newell only
};

// Projects polygons and fills their SortItems: view depths of the vertices (the keys), and the
// polygon clipped to the view volume (project_polygon) and then to the viewport rectangle.
class ItemBuilder {
 public:
  ItemBuilder(const ViewTransform& view, PainterKey key);
  // False when nothing of the polygon is in the view: clipping leaves nothing, or its projection
  // misses the viewport. Back faces are the caller's business.
  bool build(const PolygonSoup& soup, uint32_t index, bool fragment, SortItem& item);
  std::vector<Vec2> screen;  // visible parts on screen, concatenated (newell only)

 private:
  const ViewTransform& view_;
  PainterKey key_;
  Vec4 depth_row_;  // view depth = -dot(depth_row_, (p, 1))
  DrawScratch scratch_;
  std::vector<Vec2> a_, b_;
};

// Work bounds of the Newell refinement (docs/painter.md), for `n` polygons entering it.
inline size_t newell_max_splits(size_t n) { return std::min(4 * n + 65536, size_t{1} << 20); }
inline size_t newell_max_checks(size_t n) { return 1024 * n + (size_t{1} << 24); }

// Classification band of the Newell tests: a fraction of the scene's bounding-box diagonal, raised
// to cover rounding of coordinates far from the origin.
constexpr double newell_epsilon_fraction = 1e-7;
double newell_epsilon(const PolygonSoup& soup);

// Refines `items` (in the initial back-to-front order) into an exact order, appending it to
// order.items and splitting polygons into order.fragments where needed. Counts order.pairs_tested
// and order.splits.
void newell_order(const FrameInput& input, ItemBuilder& builder, std::vector<SortItem>& items, PainterOrder& order);

}  // namespace rr::painter_detail

// The painter pipeline (see painter.hpp and docs/painter.md): cull, key, sort back to front, draw
// with no depth buffer. The Newell refinement lives in newell.cpp.
#include "render/pipelines/painter.hpp"

#include "render/core/polygon_ops.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/ordered_draw.hpp"
#include "render/pipelines/painter_detail.hpp"

#include <algorithm>
#include <limits>

namespace rr {

namespace painter_detail {

namespace {

// Sutherland-Hodgman against one side of the viewport: keeps points with sign * (p[axis] - value) >= 0.
void clip_2d(const std::vector<Vec2>& in, std::vector<Vec2>& out, int axis, double value, double sign) {
  out.clear();
  const size_t n = in.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = in[i];
    const Vec2& b = in[(i + 1) % n];
    double da = sign * (a[axis] - value), db = sign * (b[axis] - value);
    if (da >= 0.0) out.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) {
      // From the inside endpoint, as camera.cpp does, so shared edges clip identically.
      out.push_back(da >= 0.0 ? a + (b - a) * (da / (da - db)) : b + (a - b) * (db / (db - da)));
    }
  }
}

}  // namespace

ItemBuilder::ItemBuilder(const ViewTransform& view, PainterKey key) : view_(view), key_(key) {
  const Mat4& m = view.view_from_world;  // column-major: m[column][row]; row 2 is view z
  depth_row_ = Vec4(m[0][2], m[1][2], m[2][2], m[3][2]);
}

bool ItemBuilder::build(const PolygonSoup& soup, uint32_t index, bool fragment, SortItem& item) {
  const Polygon& poly = soup.polygons[index];
  if (!project_polygon(view_, soup, poly, scratch_)) return false;
  a_.clear();
  for (const RasterVertex& v : scratch_.screen) a_.push_back({v.x, v.y});
  clip_2d(a_, b_, 0, 0.0, 1.0);
  clip_2d(b_, a_, 0, double(view_.width), -1.0);
  clip_2d(a_, b_, 1, 0.0, 1.0);
  clip_2d(b_, a_, 1, double(view_.height), -1.0);
  if (a_.size() < 3) return false;  // its projection misses the viewport: it covers no pixel

  double x0 = a_[0].x, x1 = a_[0].x, y0 = a_[0].y, y1 = a_[0].y;
  for (const Vec2& p : a_) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  double dmin = std::numeric_limits<double>::infinity(), dmax = -dmin, sum = 0.0;
  for (const Vec3& p : soup.points(poly)) {
    double d = -(depth_row_.x * p.x + depth_row_.y * p.y + depth_row_.z * p.z + depth_row_.w);
    dmin = std::min(dmin, d), dmax = std::max(dmax, d), sum += d;
  }
  item.index = index;
  item.fragment = fragment;
  item.id = poly.id;
  item.dmin = dmin;
  item.dmax = dmax;
  item.key = key_ == PainterKey::min ? dmin : key_ == PainterKey::max ? dmax : sum / double(poly.vertex_count);
  item.x0 = x0, item.y0 = y0, item.x1 = x1, item.y1 = y1;
  if (key_ == PainterKey::newell) {
    item.screen_first = uint32_t(screen.size());
    item.screen_count = uint32_t(a_.size());
    screen.insert(screen.end(), a_.begin(), a_.end());
  }
  return true;
}

}  // namespace painter_detail

using painter_detail::ItemBuilder;
using painter_detail::SortItem;

PainterOrder painter_order(const FrameInput& input, PainterKey key) {
  const PolygonSoup& soup = input.soup;
  PainterOrder order;
  ItemBuilder builder(input.view, key);
  std::vector<SortItem> items;
  items.reserve(soup.polygons.size());
  SortItem item;
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
    if ((i & 4095) == 4095) check_cancel(input.context.cancel);
    const Polygon& poly = soup.polygons[i];
    if (is_back_facing(poly, input.view.eye) || !input.object_may_show(poly)) {
      ++order.culled;
      continue;
    }
    ++order.projected;
    if (!builder.build(soup, i, false, item)) {
      ++order.culled;
      continue;
    }
    items.push_back(item);
  }
  // Back to front: larger key first; equal keys draw the higher id first, so the lower id is drawn
  // last and wins, as on equal depth in the zbuffer pipeline; then the higher index (a total order,
  // so the result does not depend on the sort algorithm). Compact keys are sorted, not the items.
  struct Key {
    double key;
    uint32_t id, pos;
  };
  std::vector<Key> keys(items.size());
  for (uint32_t k = 0; k < items.size(); ++k) keys[k] = {items[k].key, items[k].id, k};
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    if (a.key != b.key) return a.key > b.key;
    if (a.id != b.id) return a.id > b.id;
    return a.pos > b.pos;
  });
  if (key == PainterKey::newell) {
    std::vector<SortItem> sorted(items.size());
    for (size_t k = 0; k < keys.size(); ++k) sorted[k] = items[keys[k].pos];
    items.swap(sorted);
    order.fragments = make_fragment_soup(soup);
    painter_detail::newell_order(input, builder, items, order);
  } else {
    order.items.reserve(items.size());
    for (const Key& k : keys) order.items.push_back({items[k.pos].index, false});
  }
  return order;
}

void draw_painter(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings) {
  Stopwatch clock;
  PainterOrder order = painter_order(input, input.options.painter_key);
  stats.polygons_culled = order.culled;
  stats.polygons_projected += order.projected;
  stats.painter_pairs_tested = order.pairs_tested;
  stats.painter_splits = order.splits;
  stats.painter_budget_exhausted = order.budget_exhausted;
  timings.sort_ms += clock.lap_ms();

  // Fragments are shaded as polygons of their own soup (they keep material, object, flags, plane).
  SurfaceShader shader(input, input.soup), fragment_shader(input, order.fragments);
  for (const PainterItem& it : order.items) (it.fragment ? fragment_shader : shader).prepare(it.index);
  timings.shade_ms += clock.lap_ms();

  const DrawSource sources[2] = {{&input.soup, &shader}, {&order.fragments, &fragment_shader}};
  std::vector<OrderedItem> items(order.items.size());
  for (size_t k = 0; k < items.size(); ++k) items[k] = {order.items[k].index, order.items[k].fragment ? 1u : 0u};
  // Kept by this thread for its next frame, so their memory is not allocated again.
  thread_local ProjectedSet projected;
  thread_local TileGrid grid;
  const unsigned threads = std::max(1u, input.context.threads);
  project_in_order(input.view, sources, items, threads, projected);
  stats.polygons_drawn += projected.polygons.size();
  stats.triangles += projected.triangles;
  bin_projected(projected, frame.image.width, frame.image.height, grid);
  check_cancel(input.context.cancel);
  stats.fragments += draw_last_wins(input, sources, projected, grid, threads, frame);
  projected.release_if_large();
  timings.raster_ms += clock.lap_ms();
}

}  // namespace rr

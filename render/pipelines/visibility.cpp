// The tiled visibility buffer of the z-buffer pipeline (see visibility.hpp). Depth is 1/w in float,
// as before: at the first pixel of each span it is the same sum as raster.hpp's weights, and along
// the span it steps by the plane's exact x slope (1/w is affine in screen space), so a float only
// changes where the two roundings straddle a float boundary.
#include "render/pipelines/visibility.hpp"

#include "render/core/draw.hpp"
#include "render/core/kernels.hpp"
#include "render/core/parallel.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"

#include <algorithm>
#include <cassert>
#include <limits>
#include <memory>

namespace rr {

namespace {

constexpr uint32_t no_triangle = no_visible;

PixelRect tile_rect(const VisibilityInput& vis, size_t tile, int width, int height) {
  const int tx = int(tile % size_t(vis.tiles_x)), ty = int(tile / size_t(vis.tiles_x));
  return {tx * tile_size, ty * tile_size, std::min(width, (tx + 1) * tile_size),
          std::min(height, (ty + 1) * tile_size)};
}

// The frame-wide per-pixel buffers of pass 1; each tile touches only its own pixels.
struct Buffers {
  int width = 0;
  float* depth = nullptr;       // 1/w of the nearest opaque triangle, 0 where none
  uint32_t* visible = nullptr;  // its position in the tile's bin, or no_triangle
};

// Pass 1 for one triangle (position j in the tile's bin): depth test and write, no shading. A pixel
// whose visible triangle lies in the same plane group keeps it whatever the depths say, because it
// was drawn earlier and so has the lower id (docs/accuracy.md, "Ties"); group_of[] holds the plane
// group of each bin position.
size_t resolve_triangle(const BinnedTriangle& t, uint32_t group, const uint32_t* group_of, uint32_t j,
                        const PixelRect& r, const Buffers& b) {
  TriangleSetup s;
  if (!setup_binned(t, s)) return 0;
  const int px0 = std::max(r.x0, s.px0), px1 = std::min(r.x1 - 1, s.px1);
  const int py0 = std::max(r.y0, s.py0), py1 = std::min(r.y1 - 1, s.py1);
  if (px0 > px1 || py0 > py1) return 0;
  double w[3], dz_dx = 0.0;  // per edge: the weight of its vertex's 1/w
  for (int k = 0; k < 3; ++k) {
    w[k] = t.inv_w[s.order[k]];
    dz_dx += double(s.step_x[k]) * s.inv_area * w[k];
  }
  int64_t e_row[3] = {s.edge(0, px0, py0), s.edge(1, px0, py0), s.edge(2, px0, py0)};
  const Kernels& simd = kernels();
  size_t covered = 0;
  for (int y = py0; y <= py1; ++y) {
    int64_t first, last = px1 - px0;
    row_span(s, e_row, first, last);
    if (last >= first) {
      double z0 = 0.0;
      for (int k = 0; k < 3; ++k) z0 += double(e_row[k] + first * s.step_x[k] + s.bias[k]) * s.inv_area * w[k];
      const size_t at = size_t(y) * size_t(b.width) + size_t(px0 + first);
      float* depth = b.depth + at;
      uint32_t* visible = b.visible + at;
      const int n = int(last - first + 1);
      if (group != 0) {
        simd.grouped_depth_span(z0, dz_dx, n, j, group, group_of, depth, visible);
      } else {
        simd.depth_span(z0, dz_dx, n, j, depth, visible);
      }
      covered += size_t(n);
    }
    for (int k = 0; k < 3; ++k) e_row[k] += s.step_y[k];
  }
  return covered;
}

size_t resolve_tile(const VisibilityInput& vis, size_t tile, const PixelRect& r, const Buffers& b) {
  for (int y = r.y0; y < r.y1; ++y) {
    const size_t at = size_t(y) * size_t(b.width) + size_t(r.x0);
    std::fill_n(b.depth + at, r.x1 - r.x0, 0.0f);
    std::fill_n(b.visible + at, r.x1 - r.x0, no_triangle);
  }
  size_t covered = 0;
  const std::vector<uint32_t>& bin = vis.bins[tile];
  thread_local std::vector<uint32_t> group_of;
  group_of.resize(bin.size());
  // A bin lists triangles scattered over the frame's array (each a cache line or two): fetched a
  // few triangles ahead, their loads overlap instead of each waiting on memory in turn.
  constexpr uint32_t ahead = 8;
  const auto prefetch = [&](uint32_t j) {
    if (j >= bin.size()) return;
    const char* t = reinterpret_cast<const char*>(&vis.triangles[bin[j]]);
    __builtin_prefetch(t), __builtin_prefetch(t + sizeof(BinnedTriangle) - 1);
  };
  for (uint32_t j = 0; j < bin.size(); ++j) {
    prefetch(j + ahead);
    group_of[j] = vis.slot_groups[vis.triangles[bin[j]].slot];
  }
  for (uint32_t j = 0; j < bin.size(); ++j) {
    prefetch(j + ahead);
    covered += resolve_triangle(vis.triangles[bin[j]], group_of[j], group_of.data(), j, r, b);
  }
  return covered;
}

// A run of pixels of one tile row that show the same triangle (position j in the tile's bin).
struct Run {
  uint32_t j;
  int32_t x, y, n;
};

// What one thread of pass 2 keeps between tiles.
struct ShadeWorker {
  std::unique_ptr<SurfaceShader> shader;  // a binding copy of the prepared shader
  DrawScratch scratch;
  uint32_t bound = no_triangle;  // the slot bound in `shader`, if any
  std::vector<uint32_t> start, cursor;
  std::vector<Run> runs, sorted;
  SurfaceShader::Span span;
  SurfaceShader::SpanColors colors;
  size_t lights = 0, fragments = 0;
};

// Runs shorter than this are shaded pixel by pixel: a span's fixed cost (a dozen short loops) is
// more than what its loops save on one to three pixels, the common case in dense triangle soups.
constexpr int min_span = 4;

// Shades the visible pixels of triangle `t`: `count` runs, each shaded as one span.
void shade_triangle(const FrameInput& input, const VisibilityInput& vis, const BinnedTriangle& t, const Run* runs,
                    size_t count, ShadeWorker& w, Frame& frame) {
  const uint32_t index = vis.polygons[t.slot];
  const Polygon& poly = input.soup.polygons[index];
  if (w.bound != t.slot) {
    [[maybe_unused]] const bool projected = project_polygon(input.view, input.soup, poly, w.scratch);
    assert(projected && "pass 1 drew this polygon from the same projection");
    w.shader->bind(index, w.scratch);
    w.bound = t.slot;
  }
  TriangleSetup s;
  setup_binned(t, s);
  uint32_t* ids = frame.ids.ids.data();
  uint8_t* rgb = frame.image.rgb.data();
  const size_t width = size_t(frame.image.width);
  w.span.k = t.k;
  Fragment f;
  for (size_t r = 0; r < count; ++r) {
    const Run& run = runs[r];
    if (run.n < min_span) {  // fragment() gives the same colours (see shade_span)
      const size_t at = size_t(run.y) * width + size_t(run.x);
      f.y = run.y;
      for (int i = 0; i < run.n; ++i) {
        f.x = run.x + i;
        const int64_t e[3] = {s.edge(0, f.x, f.y), s.edge(1, f.x, f.y), s.edge(2, f.x, f.y)};
        pixel_weights(s, t.inv_w, e, f);
        const Color c = w.shader->fragment(f, t.k);
        uint8_t* px = rgb + (at + size_t(i)) * 3;
        ids[at + size_t(i)] = poly.id;
        px[0] = to_byte(c.r), px[1] = to_byte(c.g), px[2] = to_byte(c.b);
      }
      continue;
    }
    span_weights(s, t.inv_w, run.x, run.y, run.n, w.span);
    w.shader->shade_span(w.span, w.colors);
    const size_t at = size_t(run.y) * width + size_t(run.x);
    std::fill_n(ids + at, run.n, poly.id);
    SurfaceShader::write_bytes(w.colors, size_t(run.n), rgb + at * 3);
  }
}

// Pass 2 for one tile when every polygon has one colour: a table lookup per pixel, no sorting.
void fill_tile_constant(const FrameInput& input, const VisibilityInput& vis, const SurfaceShader& prepared, size_t tile,
                        const PixelRect& r, const Buffers& b, ShadeWorker& w, Frame& frame) {
  const std::vector<uint32_t>& bin = vis.bins[tile];
  w.start.resize(bin.size());  // bin position -> the triangle's polygon slot
  for (size_t j = 0; j < bin.size(); ++j) w.start[j] = vis.triangles[bin[j]].slot;
  // Locals, not members read through references: the byte stores below may alias anything, so a
  // pointer or size held in memory would be loaded again after each of them.
  const uint32_t* const slot_of = w.start.data();
  const uint32_t* const visible = b.visible;
  uint32_t* const ids = frame.ids.ids.data();
  uint8_t* const rgb = frame.image.rgb.data();
  const size_t width = size_t(b.width), x0 = size_t(r.x0), x1 = size_t(r.x1);
  uint32_t last_slot = no_triangle, id = background_id;
  uint8_t red = 0, green = 0, blue = 0;
  for (int y = r.y0; y < r.y1; ++y) {
    const size_t row = size_t(y) * width;
    for (size_t i = row + x0; i < row + x1; ++i) {
      const uint32_t v = visible[i];
      if (v == no_triangle) continue;
      const uint32_t slot = slot_of[v];
      if (slot != last_slot) {  // neighbouring pixels mostly show the same polygon
        const uint32_t index = vis.polygons[slot];
        const Color c = prepared.polygon_color(index);
        red = to_byte(c.r), green = to_byte(c.g), blue = to_byte(c.b);
        id = input.soup.polygons[index].id;
        last_slot = slot;
      }
      ids[i] = id;
      uint8_t* px = rgb + i * 3;
      px[0] = red, px[1] = green, px[2] = blue;
    }
  }
}

// The runs of one tile's rows that show one triangle each, grouped by triangle: a counting sort by
// bin position, so the triangles come in draw order and each run keeps its row order.
void collect_runs(size_t bin_size, const PixelRect& r, const Buffers& b, ShadeWorker& w) {
  w.start.assign(bin_size + 1, 0);
  w.runs.clear();
  for (int y = r.y0; y < r.y1; ++y) {
    const uint32_t* v = b.visible + size_t(y) * size_t(b.width);
    for (int x = r.x0; x < r.x1;) {
      const uint32_t j = v[x];
      int end = x + 1;
      // Most runs are long (walls, floors): compare four pixels per branch.
      while (end + 4 <= r.x1 && (v[end] == j) & (v[end + 1] == j) & (v[end + 2] == j) & (v[end + 3] == j)) end += 4;
      while (end < r.x1 && v[end] == j) ++end;
      if (j != no_triangle) {
        w.runs.push_back({j, x, y, end - x});
        ++w.start[j + 1];
      }
      x = end;
    }
  }
  for (size_t j = 0; j < bin_size; ++j) w.start[j + 1] += w.start[j];
  w.cursor.assign(w.start.begin(), w.start.end());
  w.sorted.resize(w.runs.size());
  for (const Run& run : w.runs) w.sorted[w.cursor[run.j]++] = run;
}

// Pass 2 for one tile: each triangle with visible pixels shaded run by run, its polygon bound once.
void shade_tile(const FrameInput& input, const VisibilityInput& vis, size_t tile, const PixelRect& r, const Buffers& b,
                ShadeWorker& w, Frame& frame) {
  const std::vector<uint32_t>& bin = vis.bins[tile];
  collect_runs(bin.size(), r, b, w);
  for (size_t j = 0; j < bin.size(); ++j) {
    if (w.start[j] == w.start[j + 1]) continue;
    shade_triangle(input, vis, vis.triangles[bin[j]], &w.sorted[w.start[j]], w.start[j + 1] - w.start[j], w, frame);
  }
}

// Translucent polygons over one tile, far to near, depth-tested against pass 1 and not written.
void blend_tile(const FrameInput& input, const VisibilityInput& vis, const PixelRect& r, std::vector<float>& depth,
                ShadeWorker& w, Frame& frame) {
  FrameTarget target{frame.image, frame.ids, &depth, r};
  for (size_t n = 0; n < vis.translucent.size(); ++n) {
    const PixelRect& q = vis.translucent_rects[n];
    if (q.x1 <= r.x0 || q.x0 >= r.x1 || q.y1 <= r.y0 || q.y0 >= r.y1) continue;
    const uint32_t index = vis.translucent[n];
    const Polygon& poly = input.soup.polygons[index];
    if (!project_polygon(input.view, input.soup, poly, w.scratch)) continue;
    w.bound = no_triangle;
    w.shader->bind(index, w.scratch);
    const float alpha = input.soup.materials[poly.material].opacity;
    w.fragments += draw_projected(target, w.scratch, poly.id, alpha, DepthMode::test_only,
                                  [&](const Fragment& f, size_t k) { return w.shader->fragment(f, k); });
  }
}

}  // namespace

static_assert(SurfaceShader::span_capacity >= size_t(tile_size), "a run of a tile row fits in one span");

// The edge values are exact integers: stepped in doubles where every value on the run is
// below 2^52 in magnitude (each step's product and sum are then exact, and the loop vectorizes),
// else in int64; either way each weight is the same double as pixel_weights computes.
void span_weights(const TriangleSetup& s, const double inv_w[3], int x, int y, int n, SurfaceShader::Span& span) {
  const int64_t first[3] = {s.edge(0, x, y) + s.bias[0], s.edge(1, x, y) + s.bias[1], s.edge(2, x, y) + s.bias[2]};
  const double w[3] = {inv_w[s.order[0]], inv_w[s.order[1]], inv_w[s.order[2]]};
  // Edge k weighs vertex order[k]: its weights go straight to that vertex's array.
  double* const b[3] = {span.b[s.order[0]], span.b[s.order[1]], span.b[s.order[2]]};
  kernels().span_weights(first, s.step_x, w, s.inv_area, n, b);
  span.x = x, span.y = y, span.count = size_t(n);
}

void draw_visibility(const FrameInput& input, const VisibilityInput& vis, const SurfaceShader& shader, unsigned threads,
                     Frame& frame, RenderStats& stats, StageTimings& timings) {
  if (input.options.antialias > 1) return draw_visibility_aa(input, vis, shader, threads, frame, stats, timings);
  Stopwatch clock;
  const int width = frame.image.width, height = frame.image.height;
  // Reused by this thread's next frame: no fresh pages (and page faults) per frame. References,
  // because inside the workers' lambdas the names would mean the workers' own thread_locals.
  thread_local std::vector<float> frame_depth;
  thread_local std::vector<uint32_t> frame_visible;
  std::vector<float>& depth = frame_depth;
  std::vector<uint32_t>& visible = frame_visible;
  depth.resize(size_t(width) * size_t(height));
  visible.resize(depth.size());
  const Buffers b{width, depth.data(), visible.data()};
  const size_t tiles = vis.bins.size();
  threads = std::max(1u, threads);
  std::vector<size_t> covered(threads, 0);
  parallel_for(threads, tiles, [&](size_t tile, unsigned worker) {
    covered[worker] += resolve_tile(vis, tile, tile_rect(vis, tile, width, height), b);
  });
  timings.raster_ms += clock.lap_ms();
  // The tile workers do not throw; the deadline is checked between the two passes over the tiles.
  check_cancel(input.context.cancel);

  std::vector<ShadeWorker> workers(threads);
  for (ShadeWorker& w : workers) w.shader = std::make_unique<SurfaceShader>(shader, &w.lights);
  parallel_for(threads, tiles, [&](size_t tile, unsigned worker) {
    const PixelRect r = tile_rect(vis, tile, width, height);
    if (shader.constant_per_polygon()) {
      fill_tile_constant(input, vis, shader, tile, r, b, workers[worker], frame);
    } else {
      shade_tile(input, vis, tile, r, b, workers[worker], frame);
    }
    if (!vis.translucent.empty()) blend_tile(input, vis, r, depth, workers[worker], frame);
  });
  for (size_t w = 0; w < threads; ++w) {
    workers[w].shader.reset();  // adds its per-pixel light evaluations to workers[w].lights
    stats.fragments += covered[w] + workers[w].fragments;
    if (input.lights_evaluated) *input.lights_evaluated += workers[w].lights;
  }
  timings.shade_ms += clock.lap_ms();
}

}  // namespace rr

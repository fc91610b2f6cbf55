// The z-buffer pipeline's tiles through the A-buffer (options.antialias > 1; docs/antialiasing.md).
// In: the same bins as the one-sample path (visibility.hpp); out: the frame's pixels and ids. Per
// tile, its opaque triangles take the samples where their 1/w is nearest (the plane-group rule of
// pass 1 applies per sample), the translucent polygons far to near become layers over the samples
// they are in front of, and the resolve shades each surface once per pixel. Tiles are independent,
// so the output is byte-identical for any thread count.
#include "render/pipelines/visibility.hpp"

#include "render/core/abuffer.hpp"
#include "render/core/draw.hpp"
#include "render/core/parallel.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/ordered_draw.hpp"

#include <algorithm>
#include <memory>

namespace rr {

namespace {

struct AaWorker {
  TileABuffer* buffer_ptr = nullptr;  // the calling thread's, kept for its next frame
  TileABuffer& buffer() { return *buffer_ptr; }
  std::unique_ptr<SurfaceShader> shader;  // a binding copy of the prepared shader
  DrawScratch scratch;
  uint32_t bound = no_owner;  // the item bound in `shader`
  SurfaceShader::Span span;
  SurfaceShader::SpanColors colors;
  size_t lights = 0, fragments = 0;
};

// Items: opaque slots 0 .. P-1 (VisibilityInput::polygons), then translucent polygon n as P + n.
class ZShading final : public TileShading {
 public:
  ZShading(const FrameInput& input, const VisibilityInput& vis, const SurfaceShader& prepared, AaWorker& w)
      : input_(input), vis_(vis), prepared_(prepared), w_(w), constant_(prepared.constant_per_polygon()) {}

  Color shade(const TileTriangle& t, const Fragment& f) override {
    const uint32_t index = soup_index(t.item);
    if (constant_) return prepared_.polygon_color(index);
    return bound(t.item).fragment(f, t.k);
  }
  void shade_run(const TileTriangle& t, int x, int y, int n, Color* out) override {
    shade_as_span(bound(t.item), t, x, y, n, w_.span, w_.colors, out);
  }
  uint32_t id(uint32_t item) const override { return input_.soup.polygons[soup_index(item)].id; }
  float alpha(uint32_t item) const override {
    return input_.soup.materials[input_.soup.polygons[soup_index(item)].material].opacity;
  }
  bool constant() const override { return constant_; }

 private:
  SurfaceShader& bound(uint32_t item) {
    if (w_.bound != item) {
      const uint32_t index = soup_index(item);
      project_polygon(input_.view, input_.soup, input_.soup.polygons[index], w_.scratch);
      w_.shader->bind(index, w_.scratch);
      w_.bound = item;
    }
    return *w_.shader;
  }
  uint32_t soup_index(uint32_t item) const {
    const size_t opaque = vis_.polygons.size();
    return item < opaque ? vis_.polygons[item] : vis_.translucent[item - opaque];
  }
  const FrameInput& input_;
  const VisibilityInput& vis_;
  const SurfaceShader& prepared_;
  AaWorker& w_;
  const bool constant_;
};

// The translucent polygons meeting the tile, far to near, as layers over its opaque samples.
void cover_translucent(const FrameInput& input, const VisibilityInput& vis, const PixelRect& r, AaWorker& w) {
  const uint32_t opaque = uint32_t(vis.polygons.size());
  for (size_t n = 0; n < vis.translucent.size(); ++n) {
    const PixelRect& q = vis.translucent_rects[n];
    if (q.x1 <= r.x0 || q.x0 >= r.x1 || q.y1 <= r.y0 || q.y0 >= r.y1) continue;
    if (!project_polygon(input.view, input.soup, input.soup.polygons[vis.translucent[n]], w.scratch)) continue;
    w.bound = no_owner;  // the scratch now holds another polygon's projection
    const std::vector<RasterVertex>& v = w.scratch.screen;
    for (uint32_t k = 0; k + 2 < v.size(); ++k) {
      TriangleSetup s;
      if (!setup_screen_triangle(v[0], v[k + 1], v[k + 2], s)) continue;
      const double inv_w[3] = {v[0].inv_w, v[k + 1].inv_w, v[k + 2].inv_w};
      if (w.buffer().add(s, inv_w, opaque + uint32_t(n), k))
        w.fragments += w.buffer().cover_translucent(true, 0, uint32_t(n));
    }
  }
}

void draw_tile(const FrameInput& input, const VisibilityInput& vis, const SurfaceShader& prepared, const SampleSet& set,
               const PixelRect& r, size_t tile, AaWorker& w, Frame& frame) {
  w.buffer().begin(r, set);
  for (uint32_t j : vis.bins[tile]) {
    const BinnedTriangle& t = vis.triangles[j];
    TriangleSetup s;
    if (!setup_binned(t, s)) continue;
    if (w.buffer().add(s, t.inv_w, t.slot, t.k, vis.slot_groups[t.slot]))
      w.fragments += w.buffer().cover_opaque(true, 0);
  }
  if (!vis.translucent.empty()) cover_translucent(input, vis, r, w);
  ZShading shading(input, vis, prepared, w);
  w.buffer().resolve(shading, input.scene.background, frame.image.rgb.data(), frame.ids.ids.data(),
                     size_t(frame.image.width));
}

}  // namespace

void shade_as_span(const SurfaceShader& shader, const TileTriangle& t, int x, int y, int n, SurfaceShader::Span& span,
                   SurfaceShader::SpanColors& colors, Color* out) {
  span_weights(t.setup, t.inv_w, x, y, n, span);
  span.k = t.k;
  shader.shade_span(span, colors);
  for (int i = 0; i < n; ++i) out[i] = Color(colors.r[i], colors.g[i], colors.b[i]);
}

void draw_visibility_aa(const FrameInput& input, const VisibilityInput& vis, const SurfaceShader& shader,
                        unsigned threads, Frame& frame, RenderStats& stats, StageTimings& timings) {
  Stopwatch clock;
  const SampleSet set = make_sample_set(input.options.antialias);
  threads = std::max(1u, threads);
  std::vector<TileABuffer>& buffers = kept_tile_buffers(threads);  // one per worker
  std::vector<AaWorker> workers(threads);
  for (unsigned t = 0; t < threads; ++t) {
    workers[t].buffer_ptr = &buffers[t];
    workers[t].shader = std::make_unique<SurfaceShader>(shader, &workers[t].lights);
  }
  const int width = frame.image.width, height = frame.image.height;
  parallel_for(threads, vis.bins.size(), [&](size_t tile, unsigned worker) {
    const int tx = int(tile % size_t(vis.tiles_x)), ty = int(tile / size_t(vis.tiles_x));
    const PixelRect r{tx * tile_size, ty * tile_size, std::min(width, (tx + 1) * tile_size),
                      std::min(height, (ty + 1) * tile_size)};
    draw_tile(input, vis, shader, set, r, tile, workers[worker], frame);
  });
  for (unsigned t = 0; t < threads; ++t) {
    workers[t].shader.reset();  // adds its per-pixel light evaluations to .lights
    stats.fragments += workers[t].fragments;
    if (input.lights_evaluated) *input.lights_evaluated += workers[t].lights;
  }
  timings.raster_ms += clock.lap_ms();
}

}  // namespace rr

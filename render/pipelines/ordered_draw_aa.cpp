// Tiled in-order drawing through the A-buffer (options.antialias > 1; see ordered_draw.hpp and
// docs/antialiasing.md). A polygon's key is its place in the order: last wins takes position + 1
// (a later polygon is nearer), first wins takes ~seq (an earlier walk position is nearer), so in
// both the tile buffer's rule "a larger key takes the sample" is the order's own. Opaque polygons
// claim samples first; translucent ones then become layers over the samples whose owner they are
// in front of, composited in drawing order.
#include "render/pipelines/ordered_draw.hpp"

#include "render/core/abuffer.hpp"
#include "render/core/parallel.hpp"
#include "render/core/shading.hpp"
#include "render/pipelines/visibility.hpp"

#include <algorithm>
#include <memory>

namespace rr {

namespace {

struct AaWorker {
  TileABuffer* buffer_ptr = nullptr;  // the calling thread's, kept for its next frame
  TileABuffer& buffer() { return *buffer_ptr; }
  std::vector<std::unique_ptr<SurfaceShader>> shaders;  // binding copies, one per source
  DrawScratch scratch;
  uint32_t bound = no_owner;  // the set position bound, if any
  SurfaceShader::Span span;
  SurfaceShader::SpanColors colors;
  size_t lights = 0, fragments = 0;
};

// Items are positions in the ProjectedSet.
class OrderedShading final : public TileShading {
 public:
  OrderedShading(std::span<const DrawSource> sources, const ProjectedSet& set, AaWorker& w)
      : sources_(sources), set_(set), w_(w), constant_(!sources.empty() && sources[0].shader->constant_per_polygon()) {}

  Color shade(const TileTriangle& t, const Fragment& f) override {
    const ProjectedPolygon& p = set_.polygons[t.item];
    if (constant_) return sources_[p.item.source].shader->polygon_color(p.item.index);
    return bound(t.item).fragment(f, t.k);
  }
  void shade_run(const TileTriangle& t, int x, int y, int n, Color* out) override {
    shade_as_span(bound(t.item), t, x, y, n, w_.span, w_.colors, out);
  }
  uint32_t id(uint32_t item) const override { return set_.polygons[item].id; }
  float alpha(uint32_t item) const override { return set_.polygons[item].alpha; }
  bool constant() const override { return constant_; }

 private:
  SurfaceShader& bound(uint32_t item) {
    const ProjectedPolygon& p = set_.polygons[item];
    SurfaceShader& shader = *w_.shaders[p.item.source];
    if (w_.bound != item) {
      w_.scratch.clipped.assign(set_.clipped.begin() + p.first, set_.clipped.begin() + p.first + p.count);
      w_.scratch.screen.assign(set_.screen.begin() + p.first, set_.screen.begin() + p.first + p.count);
      shader.bind(p.item.index, w_.scratch);
      w_.bound = item;
    }
    return shader;
  }
  std::span<const DrawSource> sources_;
  const ProjectedSet& set_;
  AaWorker& w_;
  const bool constant_;
};

// Covers the tile with the bin's opaque polygons (translucent = false) or its translucent ones.
void cover(const ProjectedSet& set, const std::vector<uint32_t>& bin, bool first_wins, bool translucent, AaWorker& w) {
  for (uint32_t pos : bin) {
    const ProjectedPolygon& p = set.polygons[pos];
    if (p.translucent != translucent) continue;
    const uint32_t key = first_wins ? ~p.seq : pos + 1;
    const std::span<const RasterVertex> v = set.screen_of(p);
    for (uint32_t k = 0; k + 2 < v.size(); ++k) {
      TriangleSetup s;
      if (!setup_screen_triangle(v[0], v[k + 1], v[k + 2], s)) continue;
      const double inv_w[3] = {v[0].inv_w, v[k + 1].inv_w, v[k + 2].inv_w};
      if (!w.buffer().add(s, inv_w, pos, k)) continue;
      const size_t covered =
          translucent ? w.buffer().cover_translucent(false, key, pos) : w.buffer().cover_opaque(false, key);
      // First wins: the walk counted the opaque polygons' pixels already.
      if (translucent || !first_wins) w.fragments += covered;
    }
  }
}

}  // namespace

size_t draw_ordered_aa(const FrameInput& input, std::span<const DrawSource> sources, const ProjectedSet& set,
                       const TileGrid& grid, bool first_wins, unsigned threads, Frame& frame) {
  const SampleSet samples = make_sample_set(input.options.antialias);
  threads = std::max(1u, threads);
  std::vector<TileABuffer>& buffers = kept_tile_buffers(threads);  // one per worker
  std::vector<AaWorker> workers(threads);
  for (unsigned t = 0; t < threads; ++t) {
    workers[t].buffer_ptr = &buffers[t];
    for (const DrawSource& s : sources)
      workers[t].shaders.push_back(std::make_unique<SurfaceShader>(*s.shader, &workers[t].lights));
  }
  parallel_for(threads, grid.bins.size(), [&](size_t tile, unsigned worker) {
    AaWorker& w = workers[worker];
    const std::vector<uint32_t>& bin = grid.bins[tile];
    w.buffer().begin(grid.rect(tile), samples);
    cover(set, bin, first_wins, false, w);
    cover(set, bin, first_wins, true, w);
    OrderedShading shading(sources, set, w);
    w.buffer().resolve(shading, input.scene.background, frame.image.rgb.data(), frame.ids.ids.data(),
                       size_t(frame.image.width));
  });
  size_t fragments = 0;
  for (AaWorker& w : workers) {
    w.shaders.clear();  // they add their per-pixel light evaluations to w.lights
    fragments += w.fragments;
    if (input.lights_evaluated) *input.lights_evaluated += w.lights;
  }
  return fragments;
}

}  // namespace rr

// Tiled in-order drawing (see ordered_draw.hpp). Each tile re-runs rasterize_triangle's exact
// integer set-up and spans restricted to its rectangle, so its fragments, weights and write order
// are those of the whole-frame draw; per tile, a worker binds its own copy of the prepared shader.
#include "render/pipelines/ordered_draw.hpp"

#include "render/core/parallel.hpp"
#include "render/core/shading.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

namespace rr {

void ProjectedSet::clear() {
  polygons.clear();
  clipped.clear();
  screen.clear();
  triangles = 0;
}

void ProjectedSet::release_if_large() {
  constexpr size_t kept_vertices = size_t{1} << 16;  // about 6 MB of vertices
  if (clipped.capacity() <= kept_vertices) return;
  *this = ProjectedSet{};
}

void ProjectedSet::add(const DrawScratch& scratch, const DrawSource& source, OrderedItem item, uint32_t seq, int width,
                       int height) {
  const Polygon& poly = source.soup->polygons[item.index];
  ProjectedPolygon p;
  p.item = item;
  p.id = poly.id;
  p.translucent = (poly.flags & polygon_translucent) != 0;
  p.alpha = p.translucent ? source.soup->materials[poly.material].opacity : 1.0f;
  p.seq = seq;
  p.triangle = uint32_t(triangles);
  p.first = uint32_t(screen.size());
  p.count = uint32_t(scratch.screen.size());
  double x0 = scratch.screen[0].x, x1 = x0, y0 = scratch.screen[0].y, y1 = y0;
  for (const RasterVertex& v : scratch.screen) {
    x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
  }
  // A covered pixel's centre lies within half a sub-pixel unit (the snapping) of the vertices' box.
  auto clamp = [](double v, int hi) { return int(std::clamp(v, 0.0, double(hi))); };
  p.bounds = {clamp(std::floor(x0) - 1, width), clamp(std::floor(y0) - 1, height), clamp(std::ceil(x1) + 1, width),
              clamp(std::ceil(y1) + 1, height)};
  polygons.push_back(p);
  clipped.insert(clipped.end(), scratch.clipped.begin(), scratch.clipped.end());
  screen.insert(screen.end(), scratch.screen.begin(), scratch.screen.end());
  triangles += scratch.screen.size() - 2;
}

size_t project_in_order(const ViewTransform& view, std::span<const DrawSource> sources,
                        std::span<const OrderedItem> items, unsigned threads, ProjectedSet& out) {
  constexpr size_t chunk = 512;  // polygons per task: a few hundred microseconds of clipping
  const size_t chunks = (items.size() + chunk - 1) / chunk;
  std::vector<ProjectedSet> parts(chunks);
  std::vector<size_t> dropped(chunks, 0);
  std::vector<DrawScratch> scratch(std::max(1u, threads));
  parallel_for(threads, chunks, [&](size_t c, unsigned worker) {
    for (size_t n = c * chunk; n < std::min(items.size(), (c + 1) * chunk); ++n) {
      const DrawSource& source = sources[items[n].source];
      if (!project_polygon(view, *source.soup, source.soup->polygons[items[n].index], scratch[worker])) {
        ++dropped[c];
        continue;
      }
      parts[c].add(scratch[worker], source, items[n], uint32_t(n), view.width, view.height);
    }
  });
  out.clear();
  size_t total_dropped = 0;
  for (size_t c = 0; c < chunks; ++c) {
    const uint32_t offset = uint32_t(out.screen.size());
    const uint32_t triangle_offset = uint32_t(out.triangles);
    for (ProjectedPolygon p : parts[c].polygons) {
      p.first += offset;
      p.triangle += triangle_offset;
      out.polygons.push_back(p);
    }
    out.clipped.insert(out.clipped.end(), parts[c].clipped.begin(), parts[c].clipped.end());
    out.screen.insert(out.screen.end(), parts[c].screen.begin(), parts[c].screen.end());
    out.triangles += parts[c].triangles;
    total_dropped += dropped[c];
  }
  return total_dropped;
}

PixelRect TileGrid::rect(size_t t) const {
  const int tx = int(t % size_t(tiles_x)), ty = int(t / size_t(tiles_x));
  return {tx * tile, ty * tile, std::min(width, (tx + 1) * tile), std::min(height, (ty + 1) * tile)};
}

void bin_projected(const ProjectedSet& set, int width, int height, TileGrid& grid) {
  grid.width = width, grid.height = height;
  grid.tiles_x = (width + TileGrid::tile - 1) / TileGrid::tile;
  grid.tiles_y = (height + TileGrid::tile - 1) / TileGrid::tile;
  grid.bins.resize(size_t(grid.tiles_x) * size_t(grid.tiles_y));
  for (auto& bin : grid.bins) bin.clear();
  for (uint32_t pos = 0; pos < set.polygons.size(); ++pos) {
    const PixelRect& b = set.polygons[pos].bounds;
    if (b.x0 >= b.x1 || b.y0 >= b.y1) continue;
    for (int ty = b.y0 / TileGrid::tile; ty <= (b.y1 - 1) / TileGrid::tile; ++ty) {
      for (int tx = b.x0 / TileGrid::tile; tx <= (b.x1 - 1) / TileGrid::tile; ++tx) {
        grid.bins[size_t(ty) * size_t(grid.tiles_x) + size_t(tx)].push_back(pos);
      }
    }
  }
}

namespace {

// What one thread keeps between tiles.
struct Worker {
  std::vector<std::unique_ptr<SurfaceShader>> shaders;  // binding copies, one per source
  DrawScratch scratch;
  std::vector<uint32_t> stamp;  // per tile pixel: first wins, 1 + the position that shaded it;
                                // last wins, 1 + the number of its last opaque triangle
  size_t lights = 0, fragments = 0;
};

// The frame-wide state a tile's drawing reads.
struct Context {
  std::span<const DrawSource> sources;
  const ProjectedSet& set;
  Frame& frame;
  size_t width;
};

std::vector<Worker> make_workers(std::span<const DrawSource> sources, unsigned threads) {
  std::vector<Worker> workers(threads);
  for (Worker& w : workers) {
    for (const DrawSource& s : sources) w.shaders.push_back(std::make_unique<SurfaceShader>(*s.shader, &w.lights));
  }
  return workers;
}

// Destroys the copies (they add their per-pixel light evaluations), then sums in worker order.
size_t finish_workers(std::vector<Worker>& workers, const FrameInput& input) {
  size_t fragments = 0;
  for (Worker& w : workers) {
    w.shaders.clear();
    fragments += w.fragments;
    if (input.lights_evaluated) *input.lights_evaluated += w.lights;
  }
  return fragments;
}

SurfaceShader& bind(const Context& c, const ProjectedPolygon& p, Worker& w) {
  w.scratch.clipped.assign(c.set.clipped.begin() + p.first, c.set.clipped.begin() + p.first + p.count);
  w.scratch.screen.assign(c.set.screen.begin() + p.first, c.set.screen.begin() + p.first + p.count);
  SurfaceShader& shader = *w.shaders[p.item.source];
  shader.bind(p.item.index, w.scratch);
  return shader;
}

// draw_projected's pixel write: opaque colours replace, translucent ones blend over.
inline void put(uint8_t* px, Color c, float alpha) {
  if (alpha >= 1.0f) {
    px[0] = to_byte(c.r), px[1] = to_byte(c.g), px[2] = to_byte(c.b);
  } else {
    for (int ch = 0; ch < 3; ++ch) px[ch] = to_byte(alpha * c[ch] + (1.0f - alpha) * float(px[ch]) / 255.0f);
  }
}

// Calls fn(s, k, inv_w) for each fan triangle (0, k+1, k+2) of p that covers anything.
template <class Fn>
void for_each_triangle(const Context& c, const ProjectedPolygon& p, Fn&& fn) {
  const std::span<const RasterVertex> v = c.set.screen_of(p);
  for (size_t k = 0; k + 2 < v.size(); ++k) {
    TriangleSetup s;
    if (!setup_screen_triangle(v[0], v[k + 1], v[k + 2], s)) continue;
    const double inv_w[3] = {v[0].inv_w, v[k + 1].inv_w, v[k + 2].inv_w};
    fn(s, k, inv_w);
  }
}

// The colour of a prepared polygon when every polygon has one colour (no bind, no weights), else null.
const Color* constant_color(const Context& c, const ProjectedPolygon& p, Color& storage) {
  const SurfaceShader& prepared = *c.sources[p.item.source].shader;
  if (!prepared.constant_per_polygon()) return nullptr;
  storage = prepared.polygon_color(p.item.index);
  return &storage;
}

// Shades pixels x .. x + n - 1 of row y where accept(pixel index, x, y) holds: with `constant`
// when not null, else with the shader, bound on first use.
template <class Accept>
void shade_span(const Context& c, const ProjectedPolygon& p, Worker& w, SurfaceShader*& shader, const Color* constant,
                const TriangleSetup& s, size_t k, const double inv_w[3], int y, int x, int n, const int64_t e0[3],
                Accept&& accept) {
  uint8_t* const rgb = c.frame.image.rgb.data();
  const size_t row = size_t(y) * c.width;
  if (constant) {
    for (int j = 0; j < n; ++j) {
      const size_t i = row + size_t(x + j);
      if (accept(i, x + j, y)) put(rgb + i * 3, *constant, p.alpha);
    }
    return;
  }
  int64_t e[3] = {e0[0], e0[1], e0[2]};
  Fragment f;
  f.y = y;
  for (int j = 0; j < n; ++j, e[0] += s.step_x[0], e[1] += s.step_x[1], e[2] += s.step_x[2]) {
    const size_t i = row + size_t(x + j);
    if (!accept(i, x + j, y)) continue;
    if (!shader) shader = &bind(c, p, w);
    f.x = x + j;
    pixel_weights(s, inv_w, e, f);
    put(rgb + i * 3, shader->fragment(f, k), p.alpha);
  }
}

// Every polygon one colour: each polygon's spans are filled in order, the last one staying.
void last_wins_constant_tile(const Context& c, const PixelRect& r, const std::vector<uint32_t>& bin, Worker& w) {
  uint32_t* const ids = c.frame.ids.ids.data();
  uint8_t* const rgb = c.frame.image.rgb.data();
  for (uint32_t pos : bin) {
    const ProjectedPolygon& p = c.set.polygons[pos];
    Color color;
    const Color* constant = constant_color(c, p, color);
    const uint8_t bytes[3] = {to_byte(color.r), to_byte(color.g), to_byte(color.b)};
    SurfaceShader* shader = nullptr;  // never bound: the colour is constant
    for_each_triangle(c, p, [&](const TriangleSetup& s, size_t k, const double inv_w[3]) {
      triangle_spans(s, r, [&](int y, int x, int n, const int64_t e[3]) {
        w.fragments += size_t(n);
        const size_t i0 = size_t(y) * c.width + size_t(x);
        std::fill_n(ids + i0, n, p.id);
        if (p.alpha < 1.0f) {
          shade_span(c, p, w, shader, constant, s, k, inv_w, y, x, n, e, [](size_t, int, int) { return true; });
          return;
        }
        for (uint8_t* px = rgb + i0 * 3; px < rgb + (i0 + size_t(n)) * 3; px += 3) {
          px[0] = bytes[0], px[1] = bytes[1], px[2] = bytes[2];
        }
      });
    });
  }
}

// Shaded polygons: pass 1 keeps, per pixel, the last opaque triangle covering it (in the stamp);
// pass 2 shades each pixel by that triangle, then blends the translucent polygons drawn after it,
// in order, so each pixel sees the writes that last (those draw_projected would leave there).
void last_wins_shaded_tile(const Context& c, const PixelRect& r, const std::vector<uint32_t>& bin, Worker& w) {
  constexpr int tile = TileGrid::tile;
  w.stamp.assign(size_t(tile) * tile, 0);
  for (uint32_t pos : bin) {
    const ProjectedPolygon& p = c.set.polygons[pos];
    if (p.translucent) continue;
    for_each_triangle(c, p, [&](const TriangleSetup& s, size_t k, const double*) {
      triangle_spans(s, r, [&](int y, int x, int n, const int64_t*) {
        w.fragments += size_t(n);
        std::fill_n(&w.stamp[size_t(y - r.y0) * tile + size_t(x - r.x0)], n, p.triangle + uint32_t(k) + 1);
      });
    });
  }
  uint32_t* const ids = c.frame.ids.ids.data();
  for (uint32_t pos : bin) {
    const ProjectedPolygon& p = c.set.polygons[pos];
    SurfaceShader* shader = nullptr;
    Color storage;
    const Color* constant = constant_color(c, p, storage);
    for_each_triangle(c, p, [&](const TriangleSetup& s, size_t k, const double inv_w[3]) {
      const uint32_t mine = p.triangle + uint32_t(k) + 1;
      auto accept = [&](size_t i, int x, int y) {
        const uint32_t last = w.stamp[size_t(y - r.y0) * tile + size_t(x - r.x0)];
        if (p.translucent ? last > p.triangle : last != mine) return false;  // overwritten later
        ids[i] = p.id;
        return true;
      };
      triangle_spans(s, r, [&](int y, int x, int n, const int64_t e[3]) {
        if (p.translucent) w.fragments += size_t(n);
        shade_span(c, p, w, shader, constant, s, k, inv_w, y, x, n, e, accept);
      });
    });
  }
}

}  // namespace

size_t draw_last_wins(const FrameInput& input, std::span<const DrawSource> sources, const ProjectedSet& set,
                      const TileGrid& grid, unsigned threads, Frame& frame) {
  if (input.options.antialias > 1) return draw_ordered_aa(input, sources, set, grid, false, threads, frame);
  threads = std::max(1u, threads);
  std::vector<Worker> workers = make_workers(sources, threads);
  const Context c{sources, set, frame, size_t(frame.image.width)};
  const bool constant = !sources.empty() && sources[0].shader->constant_per_polygon();
  parallel_for(threads, grid.bins.size(), [&](size_t tile, unsigned worker) {
    if (constant) {
      last_wins_constant_tile(c, grid.rect(tile), grid.bins[tile], workers[worker]);
    } else {
      last_wins_shaded_tile(c, grid.rect(tile), grid.bins[tile], workers[worker]);
    }
  });
  return finish_workers(workers, input);
}

namespace {

using Bytes = std::array<uint8_t, 3>;

// Each claimed pixel of the tile takes its claimant's colour, from the claimant's first fan
// triangle covering it (the stamp keeps a later triangle of the same polygon off the pixel).
void claimants_tile(const Context& c, const PixelRect& r, const std::vector<uint32_t>& bin,
                    const std::vector<Bytes>* colors, Worker& w) {
  const uint32_t* const ids = c.frame.ids.ids.data();
  if (colors) {  // one colour per polygon: a table lookup per pixel
    uint8_t* const rgb = c.frame.image.rgb.data();
    for (int y = r.y0; y < r.y1; ++y) {
      for (size_t i = size_t(y) * c.width + size_t(r.x0); i < size_t(y) * c.width + size_t(r.x1); ++i) {
        if (ids[i] == background_id) continue;
        const Bytes& b = (*colors)[ids[i]];
        rgb[i * 3] = b[0], rgb[i * 3 + 1] = b[1], rgb[i * 3 + 2] = b[2];
      }
    }
    return;
  }
  w.stamp.assign(size_t(TileGrid::tile) * TileGrid::tile, 0);
  for (uint32_t pos : bin) {
    const ProjectedPolygon& p = c.set.polygons[pos];
    if (p.translucent) continue;
    SurfaceShader* shader = nullptr;
    Color storage;
    const Color* constant = constant_color(c, p, storage);
    auto accept = [&](size_t i, int x, int y) {
      if (ids[i] != p.seq) return false;
      uint32_t& stamp = w.stamp[size_t(y - r.y0) * TileGrid::tile + size_t(x - r.x0)];
      if (stamp == pos + 1) return false;
      stamp = pos + 1;
      return true;
    };
    for_each_triangle(c, p, [&](const TriangleSetup& s, size_t k, const double inv_w[3]) {
      triangle_spans(s, r, [&](int y, int x, int n, const int64_t e[3]) {
        shade_span(c, p, w, shader, constant, s, k, inv_w, y, x, n, e, accept);
      });
    });
  }
}

// Translucent polygons (back to front) over the pixels whose writer lies behind them.
void translucent_tile(const Context& c, const PixelRect& r, const std::vector<uint32_t>& bin, Worker& w) {
  uint32_t* const ids = c.frame.ids.ids.data();
  for (uint32_t pos : bin) {
    const ProjectedPolygon& p = c.set.polygons[pos];
    if (!p.translucent) continue;
    SurfaceShader* shader = nullptr;
    Color storage;
    const Color* constant = constant_color(c, p, storage);
    auto accept = [&](size_t i, int, int) {
      if (ids[i] < p.seq) return false;
      ids[i] = p.seq;  // nearer translucent polygons compare with this one
      return true;
    };
    for_each_triangle(c, p, [&](const TriangleSetup& s, size_t k, const double inv_w[3]) {
      triangle_spans(s, r, [&](int y, int x, int n, const int64_t e[3]) {
        w.fragments += size_t(n);
        shade_span(c, p, w, shader, constant, s, k, inv_w, y, x, n, e, accept);
      });
    });
  }
}

}  // namespace

size_t draw_first_wins(const FrameInput& input, std::span<const DrawSource> sources, const ProjectedSet& set,
                       const std::vector<uint32_t>& id_of, const TileGrid& grid, unsigned threads, Frame& frame) {
  if (input.options.antialias > 1) return draw_ordered_aa(input, sources, set, grid, true, threads, frame);
  threads = std::max(1u, threads);
  std::vector<Worker> workers = make_workers(sources, threads);
  const Context c{sources, set, frame, size_t(frame.image.width)};
  std::vector<Bytes> colors;
  const bool constant = !sources.empty() && sources[0].shader->constant_per_polygon();
  if (constant) {
    colors.resize(id_of.size(), Bytes{0, 0, 0});
    for (const ProjectedPolygon& p : set.polygons) {
      const Color col = sources[p.item.source].shader->polygon_color(p.item.index);
      if (!p.translucent) colors[p.seq] = {to_byte(col.r), to_byte(col.g), to_byte(col.b)};
    }
  }
  uint32_t* const ids = frame.ids.ids.data();
  parallel_for(threads, grid.bins.size(), [&](size_t tile, unsigned worker) {
    const PixelRect r = grid.rect(tile);
    const std::vector<uint32_t>& bin = grid.bins[tile];
    const bool translucent =
        std::any_of(bin.begin(), bin.end(), [&](uint32_t pos) { return set.polygons[pos].translucent; });
    if (!constant || translucent) {
      claimants_tile(c, r, bin, constant ? &colors : nullptr, workers[worker]);
      translucent_tile(c, r, bin, workers[worker]);
    }
    uint8_t* const rgb = frame.image.rgb.data();
    for (int y = r.y0; y < r.y1; ++y) {
      for (size_t i = size_t(y) * c.width + size_t(r.x0); i < size_t(y) * c.width + size_t(r.x1); ++i) {
        if (ids[i] == background_id) continue;
        if (constant && !translucent) {  // claimants_tile's table lookup, fused with the id pass
          const Bytes& b = colors[ids[i]];
          rgb[i * 3] = b[0], rgb[i * 3 + 1] = b[1], rgb[i * 3 + 2] = b[2];
        }
        ids[i] = id_of[ids[i]];
      }
    }
  });
  return finish_workers(workers, input);
}

}  // namespace rr

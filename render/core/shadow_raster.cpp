// The shadow pass's depth-only rasterizer (see shadow_raster.hpp). Four stages on parallel_for:
// clip, project and snap the casters in chunks, counting their triangles per map tile; bin them
// (a counting sort: the result does not depend on the thread count); flag the pages each tile covers
// and give them storage in one allocation; draw each tile's bin, nearest first, with span loops into
// pages only that tile writes, then summarize its blocks.
#include "render/core/shadow_raster.hpp"

#include "render/core/parallel.hpp"
#include "render/core/raster.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace rr {

namespace shadow_detail {

bool clip_points(const Mat4& clip_from_world, std::span<const Vec3> points, ClipBuffers& buf) {
  buf.in.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) buf.in[i] = {clip_from_world * Vec4(points[i], 1.0), points[i], {}};
  return clip_polygon(buf.in, buf.out, buf.tmp);
}

Mat4 exact_frustum(const Mat4& clip_from_world) {
  Mat4 scale(1.0);
  scale[0][0] = scale[1][1] = clip_guard_band;
  return scale * clip_from_world;
}

}  // namespace shadow_detail

namespace {

using shadow_detail::ClipBuffers;

// 64 texels: 2x2 pages, 16 KiB of texels that stay in the L1 cache while a tile's bin is drawn, and
// at a 2048 side 1024 tiles per map, plenty to balance the workers.
constexpr int tile_side = 64;
static_assert(tile_side % TexelStore::page_side == 0, "a tile is whole pages");
// Casters per front-end task, and at most this many tasks per map (each keeps a count per tile).
constexpr size_t chunk_casters = 256, max_chunks = 64;

// A fan triangle in snapped sub-texel coordinates, with its vertices' nearness; set up again in each
// tile it touches (cheap beside its texels), so a million-triangle soup keeps 96 bytes a triangle.
struct ShadowTriangle {
  int64_t X[3], Y[3];
  double inv_w[3];
  double nearest;                          // the largest inv_w: tiles draw their nearest triangles first
  int tile_x0, tile_y0, tile_x1, tile_y1;  // tiles its bounding box of texel centres meets
};

struct Chunk {
  size_t job = 0, begin = 0, end = 0;  // casters [begin, end) of jobs[job]
  bool any_caster = false;
  std::vector<ShadowTriangle> triangles;
  std::vector<uint32_t> cursor;  // per tile: its triangles here, then where the next one is binned
};

struct Bins {
  int tiles_per_row = 0;
  std::vector<uint32_t> start;  // bin of tile t: entries[start[t], start[t + 1])
  std::vector<const ShadowTriangle*> entries;
  std::vector<uint8_t> written;  // per page: some texel centre of it is covered
};

PixelRect tile_rect(int tile, int tiles_per_row, int side) {
  const int x0 = (tile % tiles_per_row) * tile_side, y0 = (tile / tiles_per_row) * tile_side;
  return {x0, y0, std::min(side, x0 + tile_side), std::min(side, y0 + tile_side)};
}

// False when one edge is negative at every corner of the rect's texel centres (inclusive bounds):
// the triangle covers none of them. Edges are affine, so the corners hold their maxima.
bool may_cover(const TriangleSetup& s, int x0, int y0, int x1, int y1) {
  for (int k = 0; k < 3; ++k) {
    const int64_t best =
        s.c[k] + std::max(x0 * s.step_x[k], x1 * s.step_x[k]) + std::max(y0 * s.step_y[k], y1 * s.step_y[k]);
    if (best < 0) return false;
  }
  return true;
}

template <class Fn>
void for_each_tile(const ShadowTriangle& t, const TriangleSetup& s, int tiles_per_row, int side, Fn&& fn) {
  if (t.tile_x0 == t.tile_x1 && t.tile_y0 == t.tile_y1) return fn(size_t(t.tile_y0 * tiles_per_row + t.tile_x0));
  for (int ty = t.tile_y0; ty <= t.tile_y1; ++ty) {
    for (int tx = t.tile_x0; tx <= t.tile_x1; ++tx) {
      const PixelRect r = tile_rect(ty * tiles_per_row + tx, tiles_per_row, side);
      if (may_cover(s, r.x0, r.y0, r.x1 - 1, r.y1 - 1)) fn(size_t(ty * tiles_per_row + tx));
    }
  }
}

// Projects one clipped caster exactly as the per-fragment path did and keeps its fan triangles whose
// texel-centre bounds meet the map, counted in the tiles they may cover.
void add_triangles(const ShadowMapJob& job, const ViewTransform& view, ClipBuffers& buf, int tiles_per_row,
                   Chunk& chunk) {
  const int side = view.width;
  buf.screen.resize(buf.out.size());
  RasterVertex* v = buf.screen.data();
  for (size_t i = 0; i < buf.out.size(); ++i) {
    const ClipVertex& c = buf.out[i];
    const Vec4 p_clip(c.p_clip.x / clip_guard_band, c.p_clip.y / clip_guard_band, c.p_clip.z, c.p_clip.w);
    const Vec2 s = screen_from_clip(view, p_clip);
    // An orthographic map has w = 1: the rasterizer's "1/w" then interpolates any affine value
    // exactly, here the nearness itself.
    const double value = job.directional ? job.far_depth - glm::dot(c.p_world, job.forward) : 1.0 / c.p_clip.w;
    v[i] = {s.x, s.y, value};
  }
  for (size_t k = 0; k + 2 < buf.out.size(); ++k) {
    const RasterVertex* abc[3] = {&v[0], &v[k + 1], &v[k + 2]};
    ShadowTriangle t;
    for (int j = 0; j < 3; ++j) {
      t.X[j] = snap_to_subpixel(abc[j]->x), t.Y[j] = snap_to_subpixel(abc[j]->y), t.inv_w[j] = abc[j]->inv_w;
    }
    t.nearest = std::max({t.inv_w[0], t.inv_w[1], t.inv_w[2]});
    if (std::isnan(t.nearest)) t.nearest = -std::numeric_limits<double>::infinity();  // a sortable key
    TriangleSetup s;
    if (!setup_triangle(t.X, t.Y, s)) continue;
    const int px0 = std::max(0, s.px0), px1 = std::min(side - 1, s.px1);
    const int py0 = std::max(0, s.py0), py1 = std::min(side - 1, s.py1);
    if (px0 > px1 || py0 > py1) continue;
    t.tile_x0 = px0 / tile_side, t.tile_x1 = px1 / tile_side, t.tile_y0 = py0 / tile_side, t.tile_y1 = py1 / tile_side;
    for_each_tile(t, s, tiles_per_row, side, [&](size_t tile) { ++chunk.cursor[tile]; });
    chunk.triangles.push_back(t);
  }
}

void run_front_end(std::span<ShadowMapJob> jobs, int side, const PolygonSoup& soup, int tiles_per_row, Chunk& chunk,
                   ClipBuffers& buf) {
  const ShadowMapJob& job = jobs[chunk.job];
  const Mat4 exact = shadow_detail::exact_frustum(job.clip);
  ViewTransform view;
  view.clip_from_world = job.clip;
  view.width = view.height = side;
  chunk.cursor.assign(size_t(tiles_per_row) * size_t(tiles_per_row), 0);
  chunk.triangles.reserve(2 * (chunk.end - chunk.begin));  // a quad's fan, the common case
  for (size_t k = chunk.begin; k < chunk.end; ++k) {
    if (!shadow_detail::clip_points(exact, soup.points(soup.polygons[job.casters[k]]), buf)) continue;
    chunk.any_caster = true;
    add_triangles(job, view, buf, tiles_per_row, chunk);
  }
}

// Turns the chunks' per-tile counts into bin offsets: tile-major, then chunk order, so each bin
// lists its triangles in the order the casters were given.
void lay_out_bins(std::span<Chunk> chunks, Bins& bins) {
  const size_t tiles = size_t(bins.tiles_per_row) * size_t(bins.tiles_per_row);
  bins.start.assign(tiles + 1, 0);
  uint32_t next = 0;
  for (size_t t = 0; t < tiles; ++t) {
    bins.start[t] = next;
    for (Chunk& c : chunks) {
      const uint32_t count = c.cursor[t];
      c.cursor[t] = next;
      next += count;
    }
  }
  bins.start[tiles] = next;
  bins.entries.resize(next);
}

void fill_bins(const Chunk& chunk, int side, Bins& bins) {
  std::vector<uint32_t> cursor = chunk.cursor;
  for (const ShadowTriangle& t : chunk.triangles) {
    TriangleSetup s;
    // One tile, the most common case, needs no set-up: for_each_tile then does not test coverage.
    if (t.tile_x0 != t.tile_x1 || t.tile_y0 != t.tile_y1) setup_triangle(t.X, t.Y, s);
    for_each_tile(t, s, bins.tiles_per_row, side, [&](size_t tile) { bins.entries[cursor[tile]++] = &t; });
  }
}

// Flags the pages of one tile that some triangle of its bin covers at a texel centre: exactly the
// pages the per-fragment path wrote to. A page stops being tested once flagged.
void flag_pages(const Bins& bins, int tile, int side, size_t pages_per_row, std::vector<uint8_t>& written) {
  const PixelRect r = tile_rect(tile, bins.tiles_per_row, side);
  for (uint32_t i = bins.start[size_t(tile)]; i < bins.start[size_t(tile) + 1]; ++i) {
    TriangleSetup s;
    setup_triangle(bins.entries[i]->X, bins.entries[i]->Y, s);
    bool all = true;
    for (int py = r.y0; py < r.y1; py += TexelStore::page_side) {
      for (int px = r.x0; px < r.x1; px += TexelStore::page_side) {
        uint8_t& flag =
            written[size_t(py / TexelStore::page_side) * pages_per_row + size_t(px / TexelStore::page_side)];
        if (flag) continue;
        const int x0 = std::max(px, s.px0), x1 = std::min({px + TexelStore::page_side, r.x1, s.px1 + 1}) - 1;
        const int y0 = std::max(py, s.py0), y1 = std::min({py + TexelStore::page_side, r.y1, s.py1 + 1}) - 1;
        for (int y = y0; x0 <= x1 && y <= y1 && !flag; ++y) {
          const int64_t e[3] = {s.edge(0, x0, y), s.edge(1, x0, y), s.edge(2, x0, y)};
          int64_t first, last = x1 - x0;
          row_span(s, e, first, last);
          flag = first <= last;
        }
        all = all && flag;
      }
    }
    if (all) return;
  }
}

// One row's covered texels [first, last] (offsets from x) of a triangle: each value computed as
// pixel_weights computes f.inv_w. The edge values stay exact in double (integers below 2^53), so
// the three terms and their sum round exactly as there; runs of 8 texels are contiguous in a page.
// Whether every texel of row y in [xa, xb] already holds at least `bound`.
bool span_hidden(const TexelStore& texels, int y, int xa, int xb, float bound) {
  for (int u = xa; u <= xb;) {
    const int end = std::min(xb, u | 7);
    const float* run = texels.page(size_t(y >> 5), size_t(u >> 5)) + TexelStore::offset(u & ~7, y);
    for (int j = u & 7; j <= (end & 7); ++j) {
      if (run[j] < bound) return false;
    }
    u = end + 1;
  }
  return true;
}

void draw_span(TexelStore& texels, int x, int y, const int64_t e[3], int64_t first, int64_t last,
               const TriangleSetup& s, const double w[3]) {
  double d[3], step[3];
  for (int k = 0; k < 3; ++k) d[k] = double(e[k] + first * s.step_x[k] + s.bias[k]), step[k] = double(s.step_x[k]);
  const double inv_area = s.inv_area;
  const int xa = x + int(first), xb = x + int(last);
  // Casters are drawn nearest first, so a span is often hidden behind what is there. Its values
  // are affine along the row: the larger end value bounds them, plus the rounding of the three
  // products and two sums (under 6 units in the last place of max |w|, as the weights sum to 1).
  // float() rounds monotonically, so a span whose bound no texel exceeds changes nothing.
  {
    auto value = [&](double i) {
      return (d[0] + i * step[0]) * inv_area * w[0] + (d[1] + i * step[1]) * inv_area * w[1] +
             (d[2] + i * step[2]) * inv_area * w[2];
    };
    const double slop = 1e-12 * std::max({std::abs(w[0]), std::abs(w[1]), std::abs(w[2])});
    const double bound = std::max(value(0.0), value(double(xb - xa))) + slop;
    if (std::isfinite(bound) && span_hidden(texels, y, xa, xb, float(bound))) return;
  }
  for (int u = xa; u <= xb;) {
    const int end = std::min(xb, u | 7);
    float* run = texels.page_data(size_t(y >> 5), size_t(u >> 5)) + TexelStore::offset(u & ~7, y);
    const double i0 = double(u - xa);
    const int j0 = u & 7, j1 = end & 7;
    for (int j = j0; j <= j1; ++j) {
      const double i = i0 + double(j - j0);
      const double l0 = (d[0] + i * step[0]) * inv_area * w[0];
      const double l1 = (d[1] + i * step[1]) * inv_area * w[1];
      const double l2 = (d[2] + i * step[2]) * inv_area * w[2];
      const float value = float(l0 + l1 + l2);
      run[j] = run[j] < value ? value : run[j];  // std::max(texel, value), as the fragment path
    }
    u = end + 1;
  }
}

void draw_triangle(const ShadowTriangle& t, const PixelRect& r, TexelStore& texels) {
  TriangleSetup s;
  setup_triangle(t.X, t.Y, s);
  const int px0 = std::max(r.x0, s.px0), px1 = std::min(r.x1 - 1, s.px1);
  const int py0 = std::max(r.y0, s.py0), py1 = std::min(r.y1 - 1, s.py1);
  if (px0 > px1 || py0 > py1) return;
  const double w[3] = {t.inv_w[s.order[0]], t.inv_w[s.order[1]], t.inv_w[s.order[2]]};
  int64_t e[3] = {s.edge(0, px0, py0), s.edge(1, px0, py0), s.edge(2, px0, py0)};
  const int64_t width = px1 - px0;
  for (int y = py0; y <= py1; ++y) {
    int64_t first = 0, last = width;
    // Edges are affine along the row: inside at both ends means the whole row is covered, with no
    // divisions (most rows of a large caster's inner tiles).
    bool whole = true;
    for (int k = 0; k < 3; ++k) whole = whole && e[k] >= 0 && e[k] + width * s.step_x[k] >= 0;
    if (!whole) row_span(s, e, first, last);
    if (first <= last) draw_span(texels, px0, y, e, first, last, s, w);
    for (int k = 0; k < 3; ++k) e[k] += s.step_y[k];
  }
}

// The nearness range of the shadow_block^2 blocks of one page, for lookups that skip the map
// (0 for pages never written, as assigned). Texels past the map's side hold 0, which can only widen
// a block's range: the summary stays conservative. Texels are never NaN or negative (the max
// starts from +0 and a comparison with NaN keeps the texel), and non-negative floats order like
// their bit patterns: the integer reduction vectorizes where a float min/max (NaN rules) would not.
void summarize_page(const float* page, size_t row, size_t column, ShadowMapJob& job) {
  static_assert(TexelStore::page_side % shadow_block == 0 && shadow_block % 8 == 0, "blocks are whole tiles in a page");
  constexpr size_t blocks_per_page = TexelStore::page_side / shadow_block, tiles_per_block = shadow_block / 8;
  const size_t n = size_t(job.blocks_per_row);
  for (size_t by = 0; by < blocks_per_page; ++by) {
    for (size_t bx = 0; bx < blocks_per_page; ++bx) {
      uint32_t lo = UINT32_MAX, hi = 0;
      for (size_t ty = by * tiles_per_block; ty < (by + 1) * tiles_per_block; ++ty) {
        for (size_t tx = bx * tiles_per_block; tx < (bx + 1) * tiles_per_block; ++tx) {
          uint32_t bits[64];
          std::memcpy(bits, page + (ty * 4 + tx) * 64, sizeof(bits));
          for (uint32_t b : bits) lo = std::min(lo, b), hi = std::max(hi, b);
        }
      }
      const size_t block = (row * blocks_per_page + by) * n + column * blocks_per_page + bx;
      job.block_min[block] = std::bit_cast<float>(lo);
      job.block_max[block] = std::bit_cast<float>(hi);
    }
  }
}

void size_summary(ShadowMapJob& job) {
  const size_t n = job.texels.pages_per_row() * (TexelStore::page_side / shadow_block);
  job.blocks_per_row = int(n);
  job.block_min.assign(n * n, 0.0f);
  job.block_max.assign(n * n, 0.0f);
}

// Max is order-free, so the bin is drawn nearest first, which lets draw_span skip hidden spans.
void draw_tile(const Bins& bins, int tile, int side, ShadowMapJob& job, std::vector<const ShadowTriangle*>& order) {
  TexelStore& texels = job.texels;
  const PixelRect r = tile_rect(tile, bins.tiles_per_row, side);
  for (int py = r.y0; py < r.y1; py += TexelStore::page_side) {
    for (int px = r.x0; px < r.x1; px += TexelStore::page_side) {
      float* page = texels.page_data(size_t(py / TexelStore::page_side), size_t(px / TexelStore::page_side));
      if (page) std::fill(page, page + TexelStore::page_texels, 0.0f);
    }
  }
  order.assign(bins.entries.begin() + bins.start[size_t(tile)], bins.entries.begin() + bins.start[size_t(tile) + 1]);
  std::sort(order.begin(), order.end(),
            [](const ShadowTriangle* a, const ShadowTriangle* b) { return a->nearest > b->nearest; });
  for (const ShadowTriangle* t : order) draw_triangle(*t, r, texels);
  for (int py = r.y0; py < r.y1; py += TexelStore::page_side) {
    for (int px = r.x0; px < r.x1; px += TexelStore::page_side) {
      const size_t row = size_t(py / TexelStore::page_side), column = size_t(px / TexelStore::page_side);
      if (const float* page = texels.page_data(row, column)) summarize_page(page, row, column, job);
    }
  }
}

std::vector<Chunk> make_chunks(std::span<const ShadowMapJob> jobs) {
  std::vector<Chunk> chunks;
  for (size_t j = 0; j < jobs.size(); ++j) {
    const size_t n = jobs[j].casters.size();
    const size_t count = std::min(max_chunks, (n + chunk_casters - 1) / chunk_casters);
    for (size_t c = 0; c < count; ++c) {
      Chunk chunk;
      chunk.job = j, chunk.begin = n * c / count, chunk.end = n * (c + 1) / count;
      chunks.push_back(std::move(chunk));
    }
  }
  return chunks;
}

bool expired(const CancelToken* cancel) { return cancel && cancel->expired(); }

}  // namespace

void draw_shadow_jobs(std::span<ShadowMapJob> jobs, int side, const PolygonSoup& soup, unsigned threads,
                      const CancelToken* cancel) {
  threads = std::max(1u, threads);
  const int tiles_per_row = (side + tile_side - 1) / tile_side;
  const size_t tiles = size_t(tiles_per_row) * size_t(tiles_per_row);
  std::vector<Chunk> chunks = make_chunks(jobs);
  std::vector<ClipBuffers> buffers(threads);
  // A task that finds the render cancelled stops; the check after the stage then throws (expiry
  // never reverts).
  parallel_for(threads, chunks.size(), [&](size_t c, unsigned worker) {
    if (!expired(cancel)) run_front_end(jobs, side, soup, tiles_per_row, chunks[c], buffers[worker]);
  });
  check_cancel(cancel);
  std::vector<Bins> bins(jobs.size());
  for (size_t j = 0, c = 0; j < jobs.size(); ++j) {
    const size_t c0 = c;
    while (c < chunks.size() && chunks[c].job == j) jobs[j].any_caster |= chunks[c++].any_caster;
    bins[j].tiles_per_row = tiles_per_row;
    lay_out_bins(std::span(chunks).subspan(c0, c - c0), bins[j]);
    jobs[j].texels = TexelStore(side);
    size_summary(jobs[j]);
    bins[j].written.assign(jobs[j].texels.pages_per_row() * jobs[j].texels.pages_per_row(), 0);
  }
  parallel_for(threads, chunks.size(), [&](size_t c, unsigned) { fill_bins(chunks[c], side, bins[chunks[c].job]); });
  // The (map, tile) pairs with something to draw.
  std::vector<std::pair<uint32_t, uint32_t>> work;
  for (size_t j = 0; j < jobs.size(); ++j) {
    for (size_t t = 0; t < tiles; ++t) {
      if (bins[j].start[t] < bins[j].start[t + 1]) work.emplace_back(uint32_t(j), uint32_t(t));
    }
  }
  parallel_for(threads, work.size(), [&](size_t w, unsigned) {
    const auto [j, t] = work[w];
    flag_pages(bins[j], int(t), side, jobs[j].texels.pages_per_row(), bins[j].written);
  });
  for (size_t j = 0; j < jobs.size(); ++j) jobs[j].texels.allocate_pages(bins[j].written);
  check_cancel(cancel);
  std::vector<std::vector<const ShadowTriangle*>> order(threads);
  parallel_for(threads, work.size(), [&](size_t w, unsigned worker) {
    const auto [j, t] = work[w];
    if (!expired(cancel)) draw_tile(bins[j], int(t), side, jobs[j], order[worker]);
  });
  check_cancel(cancel);
}

}  // namespace rr

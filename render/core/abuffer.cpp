// The tile A-buffer (see abuffer.hpp). Opaque surfaces keep one owner and key per sample (S + 1 per
// pixel: the pattern and the centre), so a pixel's opaque list is at most S fragments by
// construction; translucent layers keep a mask, a composite position and a colour, at most
// max_translucent_layers per pixel. The resolve, which shades each (surface, pixel) once, is in
// abuffer_resolve.cpp.
#include "render/core/abuffer.hpp"

#include "render/core/parallel.hpp"
#include "render/core/sample_pattern.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace rr {

SampleSet make_sample_set(int samples) {
  SampleSet set;
  const std::span<const glm::vec2> pattern = sample_pattern(samples);
  assert(pattern.size() <= 16);
  set.count = int(pattern.size());
  set.colour_bits = (uint32_t{1} << set.count) - 1;
  for (int i = 0; i < set.count; ++i) {
    // Offsets are whole sixteenths of a pixel: exact in sub-pixel units.
    set.dx[i] = int32_t(std::lround((double(pattern[size_t(i)].x) - 0.5) * double(subpixel_one)));
    set.dy[i] = int32_t(std::lround((double(pattern[size_t(i)].y) - 0.5) * double(subpixel_one)));
    set.nearest[i] = i;
  }
  set.dx[set.count] = set.dy[set.count] = 0;
  auto d2 = [&](int i) { return int64_t(set.dx[i]) * set.dx[i] + int64_t(set.dy[i]) * set.dy[i]; };
  std::stable_sort(set.nearest, set.nearest + set.count, [&](int a, int b) { return d2(a) < d2(b); });
  return set;
}

void setup_sample_edges(const TriangleSetup& s, const double inv_w[3], const SampleSet& set, SampleEdges& out) {
  out.n = set.count + 1;
  out.dz_dx = 0.0;
  for (int k = 0; k < 3; ++k) {
    const int64_t ex = s.step_x[k] / subpixel_one, ey = s.step_y[k] / subpixel_one;
    out.reach[k] = INT64_MIN;
    out.inner[k] = INT64_MAX;
    for (int i = 0; i < out.n; ++i) {
      out.de[k][i] = ex * set.dx[i] + ey * set.dy[i];
      out.reach[k] = std::max(out.reach[k], out.de[k][i]);
      out.inner[k] = std::min(out.inner[k], out.de[k][i]);
    }
    out.dz_dx += double(s.step_x[k]) * s.inv_area * inv_w[s.order[k]];
  }
  for (int i = 0; i < out.n; ++i) {
    double dz = 0.0;
    for (int k = 0; k < 3; ++k) dz += double(out.de[k][i]) * s.inv_area * inv_w[s.order[k]];
    out.dz[i] = dz;
  }
}

void TileABuffer::begin(const PixelRect& rect, const SampleSet& set) {
  rect_ = rect;
  set_ = set;
  stride_ = set.count + 1;
  const size_t pixels = size_t(abuffer_tile) * abuffer_tile;
  tris_.clear();
  key_.assign(pixels * size_t(stride_), 0u);
  owner_.assign(pixels * size_t(stride_), no_owner);
  if (has_layers_ || layer_count_.empty()) layer_count_.assign(pixels, 0);
  has_layers_ = false;
}

bool TileABuffer::add(const TriangleSetup& s, const double inv_w[3], uint32_t item, uint32_t k, uint32_t group) {
  if (s.px1 < s.px0 - 2 || s.py1 < s.py0 - 2) return false;
  TileTriangle t;
  t.setup = s;
  t.inv_w[0] = inv_w[0], t.inv_w[1] = inv_w[1], t.inv_w[2] = inv_w[2];
  t.item = item, t.k = k, t.group = group;
  tris_.push_back(t);
  setup_sample_edges(s, inv_w, set_, edges_);
  return true;
}

namespace {

// A pixel whose samples are all inside: every sample compared, branch-free, so the loop vectorizes.
template <bool DepthKeyed>
void take_all(int n, const double* dz, double z, uint32_t key, uint32_t tri, uint32_t* keys, uint32_t* owners) {
  for (int s = 0; s < n; ++s) {
    const uint32_t k = DepthKeyed ? depth_key(z + dz[s]) : key;
    const bool nearer = k > keys[s];
    keys[s] = nearer ? k : keys[s];
    owners[s] = nearer ? tri : owners[s];
  }
}

}  // namespace

size_t TileABuffer::cover_opaque(bool depth_keyed, uint32_t key) {
  const uint32_t tri = uint32_t(tris_.size() - 1);
  const TileTriangle& t = tris_.back();
  const TriangleSetup& ts = t.setup;
  const uint32_t group = t.group;
  size_t covered = 0;
  sample_spans(ts, edges_, rect_, [&](int y, int x, int n, const int64_t e0[3]) {
    int zx = x;  // where 1/w is summed; stepped from there along the row
    const double z0 = depth_keyed ? centre_row_inv_w(t, x, e0, zx) : 0.0;
    uint32_t* const keys_row =
        key_.data() + (size_t(y - rect_.y0) * abuffer_tile + size_t(x - rect_.x0)) * size_t(stride_);
    uint32_t* const owners_row = owner_.data() + (keys_row - key_.data());
    // The pixels whose samples are all inside form one run (the triangle is convex): found exactly
    // from the edges less each one's farthest-in sample offset.
    int64_t full_first = n, full_last = -1;
    if (group == 0) {
      const int64_t inner[3] = {e0[0] + edges_.inner[0], e0[1] + edges_.inner[1], e0[2] + edges_.inner[2]};
      full_last = n - 1;
      row_span(ts, inner, full_first, full_last);
      if (full_last < full_first) full_first = n, full_last = -1;
    }
    int64_t e[3] = {e0[0], e0[1], e0[2]};
    for (int i = 0; i < n; ++i, e[0] += ts.step_x[0], e[1] += ts.step_x[1], e[2] += ts.step_x[2]) {
      uint32_t* keys = keys_row + size_t(i) * size_t(stride_);
      uint32_t* owners = owners_row + size_t(i) * size_t(stride_);
      const double z = z0 + double(x + i - zx) * edges_.dz_dx;
      if (i >= full_first && i <= full_last) {
        if (depth_keyed) {
          take_all<true>(edges_.n, edges_.dz, z, key, tri, keys, owners);
        } else {
          take_all<false>(edges_.n, edges_.dz, z, key, tri, keys, owners);
        }
        ++covered;
        continue;
      }
      const uint32_t m = sample_mask(edges_, e);
      if (m == 0) continue;
      ++covered;
      for (uint32_t bits = m; bits; bits &= bits - 1) {
        const int s = std::countr_zero(bits);
        const uint32_t k = depth_keyed ? depth_key(z + edges_.dz[s]) : key;
        if (k <= keys[s]) continue;
        if (group != 0 && owners[s] != no_owner && tris_[owners[s]].group == group) continue;
        keys[s] = k;
        owners[s] = tri;
      }
    }
  });
  return covered;
}

// 1/w at the centre of the first pixel of row y whose centre the triangle covers within the tile
// (its start `zx`), summed as the one-sample z-buffer sums it there (visibility.cpp's pass 1): the
// centre sample's depths along the row are then those of that pass, bit for bit, and so are its ids.
double TileABuffer::centre_row_inv_w(const TileTriangle& t, int x, const int64_t e[3], int& zx) const {
  const TriangleSetup& s = t.setup;
  const int start = std::max(rect_.x0, s.px0);
  int64_t at[3];
  for (int k = 0; k < 3; ++k) at[k] = e[k] + int64_t(start - x) * s.step_x[k];
  int64_t first, last = int64_t(rect_.x1) - start;
  row_span(s, at, first, last);
  zx = start + int(first);
  for (int k = 0; k < 3; ++k) at[k] += first * s.step_x[k];
  return centre_inv_w(s, t.inv_w, at);
}

uint8_t TileABuffer::shading_sample(uint32_t inside) const {
  if (inside >> set_.count & 1u) return uint8_t(set_.count);
  for (int j = 0; j < set_.count; ++j) {
    if (inside >> set_.nearest[j] & 1u) return uint8_t(set_.nearest[j]);
  }
  return uint8_t(set_.count);
}

size_t TileABuffer::cover_translucent(bool depth_keyed, uint32_t key, uint32_t order) {
  const size_t pixels = size_t(abuffer_tile) * abuffer_tile;
  if (layers_.size() < pixels * max_translucent_layers) layers_.resize(pixels * max_translucent_layers);
  has_layers_ = true;
  const uint32_t tri = uint32_t(tris_.size() - 1);
  const TileTriangle& t = tris_.back();
  size_t covered = 0;
  sample_spans(t.setup, edges_, rect_, [&](int y, int x, int n, const int64_t e0[3]) {
    int64_t e[3] = {e0[0], e0[1], e0[2]};
    const size_t row = size_t(y - rect_.y0) * abuffer_tile;
    for (int i = 0; i < n; ++i, e[0] += t.setup.step_x[0], e[1] += t.setup.step_x[1], e[2] += t.setup.step_x[2]) {
      const uint32_t m = sample_mask(edges_, e);
      if (m == 0) continue;
      ++covered;
      const size_t pixel = row + size_t(x + i - rect_.x0);
      const uint32_t* keys = key_.data() + pixel * size_t(stride_);
      // Summed at each pixel, as draw_projected's weights are for a translucent polygon.
      const double z = depth_keyed ? centre_inv_w(t.setup, t.inv_w, e) : 0.0;
      uint32_t visible = 0;
      for (uint32_t bits = m; bits; bits &= bits - 1) {
        const int s = std::countr_zero(bits);
        const uint32_t k = depth_keyed ? depth_key(z + edges_.dz[s]) : key;
        visible |= uint32_t(k > keys[s]) << s;
      }
      if (visible == 0) continue;
      Layer* list = layers_.data() + pixel * max_translucent_layers;
      uint8_t& count = layer_count_[pixel];
      if (count > 0 && list[count - 1].order == order) {  // another fan triangle of the same pane
        list[count - 1].mask |= visible;
        continue;
      }
      if (count == max_translucent_layers) {  // the cap: drop the first composited (farthest) layer
        std::move(list + 1, list + count, list);
        --count;
      }
      list[count++] = {tri, order, visible, shading_sample(m), 1.0f, Color(0.0f)};
    }
  });
  return covered;
}

size_t TileABuffer::bytes(int samples) {
  const size_t pixels = size_t(abuffer_tile) * abuffer_tile;
  return pixels * (size_t(samples + 1) * 2 * sizeof(uint32_t) + max_translucent_layers * sizeof(Layer) + 1 +
                   size_t(samples) * (sizeof(Record) + sizeof(uint32_t)) + sizeof(uint32_t));
}

long long render_bytes(int width, int height, int samples) {
  const long long pixels = 1LL * width * height;
  if (samples <= 1) return pixels * 15;
  const long long tiles =
      1LL * ((width + abuffer_tile - 1) / abuffer_tile) * ((height + abuffer_tile - 1) / abuffer_tile);
  const long long workers = std::min<long long>(tiles, max_pool_threads + 1);
  return pixels * 19 + workers * (long long)TileABuffer::bytes(samples);
}

std::vector<TileABuffer>& kept_tile_buffers(unsigned count) {
  thread_local std::vector<TileABuffer> kept;
  if (kept.size() < count) kept.resize(count);
  return kept;
}

}  // namespace rr

// The tile A-buffer (see abuffer.hpp). Opaque surfaces keep one owner and key per sample (S + 1 per
// pixel: the pattern and the centre), so a pixel's opaque list is at most S fragments by
// construction; translucent layers keep a mask, a composite position and a colour, at most
// max_translucent_layers per pixel. The resolve shades each (surface, pixel) once.
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
    // Offsets are whole sixteenths of a pixel: exact in 1/256.
    set.dx[i] = int32_t(std::lround((double(pattern[size_t(i)].x) - 0.5) * double(subpixel_one)));
    set.dy[i] = int32_t(std::lround((double(pattern[size_t(i)].y) - 0.5) * double(subpixel_one)));
    set.nearest[i] = i;
  }
  set.dx[set.count] = set.dy[set.count] = 0;
  std::stable_sort(set.nearest, set.nearest + set.count, [&](int a, int b) {
    return set.dx[a] * set.dx[a] + set.dy[a] * set.dy[a] < set.dx[b] * set.dx[b] + set.dy[b] * set.dy[b];
  });
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
    uint32_t* const keys_row = key_.data() + (size_t(y - rect_.y0) * abuffer_tile + size_t(x - rect_.x0)) * size_t(stride_);
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

Fragment TileABuffer::fragment_at(const TileTriangle& t, int x, int y, int sample) const {
  const TriangleSetup& s = t.setup;
  int64_t e[3];
  for (int k = 0; k < 3; ++k) {
    e[k] = s.edge(k, x, y) + (s.step_x[k] / subpixel_one) * set_.dx[sample] + (s.step_y[k] / subpixel_one) * set_.dy[sample];
  }
  Fragment f;
  f.x = x, f.y = y;
  pixel_weights(s, t.inv_w, e, f);
  return f;
}

// Per pixel, one record per opaque item owning colour samples: its mask and where it is shaded
// (the centre when it owns it, else its sample nearest the centre, so no attribute extrapolates).
void TileABuffer::collect_records() {
  const int w = rect_.x1 - rect_.x0, h = rect_.y1 - rect_.y0;
  records_.clear();
  record_begin_.assign(size_t(abuffer_tile) * abuffer_tile + 1, 0);
  const int S = set_.count;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t pixel = size_t(y) * abuffer_tile + size_t(x);
      const uint32_t* own = owner_.data() + pixel * size_t(stride_);
      const size_t begin = records_.size();
      bool one_owner = own[S] != no_owner;
      for (int s = 0; s < S; ++s) one_owner &= own[s] == own[S];
      if (one_owner) {  // the common interior pixel: one triangle owns every sample and the centre
        records_.push_back({own[S], set_.colour_bits, uint16_t(pixel), uint8_t(S), Color(0.0f)});
        record_begin_[pixel + 1] = uint32_t(records_.size());
        continue;
      }
      for (int s = 0; s < S; ++s) {
        if (own[s] == no_owner) continue;
        const uint32_t item = tris_[own[s]].item;
        Record* r = records_.data() + begin;
        while (r != records_.data() + records_.size() && tris_[r->tri].item != item) ++r;
        if (r == records_.data() + records_.size()) {
          records_.push_back({own[s], 0u, uint16_t(pixel), uint8_t(s), Color(0.0f)});
          r = &records_.back();
        }
        r->mask |= uint32_t{1} << s;
      }
      for (size_t n = begin; n < records_.size(); ++n) {
        Record& r = records_[n];
        const uint32_t item = tris_[r.tri].item;
        if (own[S] != no_owner && tris_[own[S]].item == item) {
          r.tri = own[S], r.sample = uint8_t(S);
          continue;
        }
        for (int j = 0; j < S; ++j) {
          const int s = set_.nearest[j];
          if (r.mask >> s & 1u) {
            r.tri = own[s], r.sample = uint8_t(s);
            break;
          }
        }
      }
      record_begin_[pixel + 1] = uint32_t(records_.size());
    }
    for (int x = w; x < abuffer_tile; ++x) record_begin_[size_t(y) * abuffer_tile + size_t(x) + 1] = uint32_t(records_.size());
  }
}

// The colour of a pixel with translucent layers: per sample, its opaque owner's colour (or the
// background) with the layers covering it composited over in order, averaged over the samples.
Color TileABuffer::composite(size_t pixel, const Record* first, const Record* last, Color background) const {
  const Layer* list = layers_.data() + pixel * max_translucent_layers;
  const int count = layer_count_[pixel];
  Color sum(0.0f);
  for (int s = 0; s < set_.count; ++s) {
    Color c = background;
    for (const Record* r = first; r != last; ++r) {
      if (r->mask >> s & 1u) c = r->colour;
    }
    for (int l = 0; l < count; ++l) {
      if (list[l].mask >> s & 1u) {
        c = list[l].alpha * list[l].colour + (1.0f - list[l].alpha) * c;
      }
    }
    sum += c;
  }
  return sum / float(set_.count);
}

// resolve() when every surface has one colour and no layer is in the tile: no records, the colours
// looked up per triangle and summed per item in the order and grouping resolve() uses, so the bytes
// are the same.
void TileABuffer::resolve_constant(TileShading& shading, Color background, uint8_t* rgb, uint32_t* ids, size_t width) {
  tri_colour_.resize(tris_.size());
  tri_id_.resize(tris_.size());
  tri_bytes_.resize(tris_.size());
  const int S = set_.count;
  const float share = 1.0f / float(S);
  for (size_t t = 0; t < tris_.size(); ++t) {
    tri_colour_[t] = shading.shade(tris_[t], Fragment{});
    tri_id_[t] = shading.id(tris_[t].item);
    // A pixel wholly one triangle's: the generic sum, colour x (S x 1/S) + background x 0, is the
    // colour itself (S is a power of two), so its bytes are the colour's.
    const Color c = tri_colour_[t] * (float(S) * share) + background * 0.0f;
    tri_bytes_[t] = {to_byte(c.r), to_byte(c.g), to_byte(c.b)};
  }
  if (has_layers_) shade_layers(shading, true);
  const int w = rect_.x1 - rect_.x0, h = rect_.y1 - rect_.y0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t pixel = size_t(y) * abuffer_tile + size_t(x);
      const uint32_t* own = owner_.data() + pixel * size_t(stride_);
      const size_t i = size_t(rect_.y0 + y) * width + size_t(rect_.x0 + x);
      if (has_layers_ && layer_count_[pixel] > 0) {
        const Color c = composite_constant(pixel, own, background);
        rgb[i * 3] = to_byte(c.r), rgb[i * 3 + 1] = to_byte(c.g), rgb[i * 3 + 2] = to_byte(c.b);
        const uint32_t top = top_at_centre(pixel, own[S]);
        if (top != no_owner) ids[i] = tri_id_[top];
        continue;
      }
      bool one_owner = true;
      for (int s = 0; s < S; ++s) one_owner &= own[s] == own[S];
      if (one_owner) {
        if (own[S] == no_owner) continue;
        const std::array<uint8_t, 3>& b = tri_bytes_[own[S]];
        rgb[i * 3] = b[0], rgb[i * 3 + 1] = b[1], rgb[i * 3 + 2] = b[2];
        ids[i] = tri_id_[own[S]];
        continue;
      }
      uint32_t items[16], counts[16], first_tri[16];
      int distinct = 0, covered = 0;
      for (int s = 0; s < S; ++s) {
        if (own[s] == no_owner) continue;
        ++covered;
        const uint32_t item = tris_[own[s]].item;
        int d = 0;
        while (d < distinct && items[d] != item) ++d;
        if (d == distinct) items[distinct] = item, counts[distinct] = 0, first_tri[distinct++] = own[s];
        ++counts[d];
      }
      Color c(0.0f);
      for (int d = 0; d < distinct; ++d) c += tri_colour_[first_tri[d]] * (float(counts[d]) * share);
      c += background * (float(S - covered) * share);
      rgb[i * 3] = to_byte(c.r), rgb[i * 3 + 1] = to_byte(c.g), rgb[i * 3 + 2] = to_byte(c.b);
      if (own[S] != no_owner) ids[i] = tri_id_[own[S]];
    }
  }
}

// Shades every layer once, grouped by triangle; `constant`: no weights needed.
void TileABuffer::shade_layers(TileShading& shading, bool constant) {
  layer_order_.clear();
  for (size_t pixel = 0; pixel < layer_count_.size(); ++pixel) {
    for (uint32_t l = 0; l < layer_count_[pixel]; ++l) {
      layer_order_.push_back({layers_[pixel * max_translucent_layers + l].tri, uint32_t(pixel * max_translucent_layers + l)});
    }
  }
  std::sort(layer_order_.begin(), layer_order_.end());
  for (const auto& [tri, at] : layer_order_) {
    Layer& l = layers_[at];
    const TileTriangle& t = tris_[tri];
    const size_t pixel = at / max_translucent_layers;
    l.colour = shading.shade(t, constant ? Fragment{} : fragment_at(t, rect_.x0 + int(pixel % abuffer_tile),
                                                                   rect_.y0 + int(pixel / abuffer_tile), l.sample));
    l.alpha = shading.alpha(t.item);
  }
}

// The nearest layer over the pixel centre, else its opaque owner (`centre`): the id's triangle.
uint32_t TileABuffer::top_at_centre(size_t pixel, uint32_t centre) const {
  const Layer* list = layers_.data() + pixel * max_translucent_layers;
  for (int l = int(layer_count_[pixel]) - 1; l >= 0; --l) {
    if (list[l].mask >> set_.count & 1u) return list[l].tri;
  }
  return centre;
}

// composite() with one colour per triangle (tri_colour_): the same colours, in the same order.
Color TileABuffer::composite_constant(size_t pixel, const uint32_t* own, Color background) const {
  const Layer* list = layers_.data() + pixel * max_translucent_layers;
  const int count = layer_count_[pixel];
  Color sum(0.0f);
  for (int s = 0; s < set_.count; ++s) {
    Color c = own[s] == no_owner ? background : tri_colour_[own[s]];
    for (int l = 0; l < count; ++l) {
      if (list[l].mask >> s & 1u) c = list[l].alpha * list[l].colour + (1.0f - list[l].alpha) * c;
    }
    sum += c;
  }
  return sum / float(set_.count);
}

void TileABuffer::resolve(TileShading& shading, Color background, uint8_t* rgb, uint32_t* ids, size_t width) {
  if (shading.constant()) return resolve_constant(shading, background, rgb, ids, width);
  collect_records();
  const int w = rect_.x1 - rect_.x0, h = rect_.y1 - rect_.y0;
  auto shade_record = [&](Record& r) {
    const TileTriangle& t = tris_[r.tri];
    r.colour = shading.shade(t, fragment_at(t, rect_.x0 + r.pixel % abuffer_tile, rect_.y0 + r.pixel / abuffer_tile, r.sample));
  };
  // Grouped by triangle (a counting sort), so each polygon is bound once per tile.
  std::vector<uint32_t>& start = tri_start_;
  start.assign(tris_.size() + 1, 0);
  for (const Record& r : records_) ++start[r.tri + 1];
  for (size_t t = 0; t < tris_.size(); ++t) start[t + 1] += start[t];
  order_.resize(records_.size());
  for (uint32_t n = 0; n < records_.size(); ++n) order_[start[records_[n].tri]++] = n;
  for (uint32_t n : order_) shade_record(records_[n]);
  if (has_layers_) shade_layers(shading, false);
  const float share = 1.0f / float(set_.count);
  const int S = set_.count;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t pixel = size_t(y) * abuffer_tile + size_t(x);
      const Record* first = records_.data() + record_begin_[pixel];
      const Record* last = records_.data() + record_begin_[pixel + 1];
      const int layers = has_layers_ ? layer_count_[pixel] : 0;
      const uint32_t centre = owner_[pixel * size_t(stride_) + size_t(S)];
      if (first == last && layers == 0 && centre == no_owner) continue;
      Color c;
      if (layers > 0) {
        c = composite(pixel, first, last, background);
      } else {
        int covered = 0;
        c = Color(0.0f);
        for (const Record* r = first; r != last; ++r) {
          const int n = std::popcount(r->mask);
          covered += n;
          c += r->colour * (float(n) * share);
        }
        c += background * (float(S - covered) * share);
      }
      const size_t i = size_t(rect_.y0 + y) * width + size_t(rect_.x0 + x);
      rgb[i * 3] = to_byte(c.r), rgb[i * 3 + 1] = to_byte(c.g), rgb[i * 3 + 2] = to_byte(c.b);
      // The id: the nearest layer over the centre, else the opaque surface there.
      const uint32_t top = layers > 0 ? top_at_centre(pixel, centre) : centre;
      if (top != no_owner) ids[i] = shading.id(tris_[top].item);
    }
  }
}

size_t TileABuffer::bytes(int samples) {
  const size_t pixels = size_t(abuffer_tile) * abuffer_tile;
  return pixels * (size_t(samples + 1) * 2 * sizeof(uint32_t) + max_translucent_layers * sizeof(Layer) + 1 +
                   size_t(samples) * (sizeof(Record) + sizeof(uint32_t)) + sizeof(uint32_t));
}

long long render_bytes(int width, int height, int samples) {
  const long long pixels = 1LL * width * height;
  if (samples <= 1) return pixels * 15;
  const long long tiles = 1LL * ((width + abuffer_tile - 1) / abuffer_tile) * ((height + abuffer_tile - 1) / abuffer_tile);
  const long long workers = std::min<long long>(tiles, max_pool_threads + 1);
  return pixels * 19 + workers * (long long)TileABuffer::bytes(samples);
}

}  // namespace rr

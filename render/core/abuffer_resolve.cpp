// The tile A-buffer's resolve (see abuffer.hpp): per pixel, a record per opaque surface owning
// colour samples, each shaded once at the centre or its covered sample nearest the centre; layers
// shaded once each; colours blended by coverage, layers composited per sample; ids from the centre.
// One colour per polygon takes resolve_constant, which does the same arithmetic without records.
#include "render/core/abuffer.hpp"

#include <algorithm>
#include <array>
#include <bit>

namespace rr {

namespace {

// Runs shorter than this are shaded pixel by pixel, as in the one-sample z-buffer (visibility.cpp).
constexpr int min_run = 4;

}  // namespace

Fragment centre_fragment(const TileTriangle& t, int x, int y) {
  const int64_t e[3] = {t.setup.edge(0, x, y), t.setup.edge(1, x, y), t.setup.edge(2, x, y)};
  Fragment f;
  f.x = x, f.y = y;
  pixel_weights(t.setup, t.inv_w, e, f);
  return f;
}

void TileShading::shade_run(const TileTriangle& t, int x, int y, int n, Color* out) {
  for (int i = 0; i < n; ++i) out[i] = shade(t, centre_fragment(t, x + i, y));
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
  const int w = rect_.x1 - rect_.x0, h = rect_.y1 - rect_.y0, S = set_.count;
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
  // A triangle's records come in pixel order: pixels wholly its own and shaded at the centre that
  // follow each other on a row are shaded as one run.
  Color run_colours[abuffer_tile];
  for (size_t a = 0; a < order_.size();) {
    const Record& r = records_[order_[a]];
    size_t b = a + 1;
    if (r.mask == set_.colour_bits && r.sample == S) {
      while (b < order_.size()) {
        const Record& q = records_[order_[b]];
        if (q.tri != r.tri || q.mask != r.mask || q.sample != S || q.pixel != r.pixel + (b - a) ||
            q.pixel / abuffer_tile != r.pixel / abuffer_tile) {
          break;
        }
        ++b;
      }
    }
    if (b - a < size_t(min_run)) {
      for (size_t n = a; n < b; ++n) shade_record(records_[order_[n]]);
    } else {
      shading.shade_run(tris_[r.tri], rect_.x0 + r.pixel % abuffer_tile, rect_.y0 + r.pixel / abuffer_tile, int(b - a),
                        run_colours);
      for (size_t n = a; n < b; ++n) records_[order_[n]].colour = run_colours[n - a];
    }
    a = b;
  }
  if (has_layers_) shade_layers(shading, false);
  const float share = 1.0f / float(set_.count);
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

}  // namespace rr

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
    e[k] = s.edge(k, x, y) + (s.step_x[k] / subpixel_one) * set_.dx[sample] +
           (s.step_y[k] / subpixel_one) * set_.dy[sample];
  }
  Fragment f;
  f.x = x, f.y = y;
  pixel_weights(s, t.inv_w, e, f);
  return f;
}

// Per pixel, one record per opaque item owning colour samples: its mask and where it is shaded
// (the centre when it owns it, else its sample nearest the centre, so no attribute extrapolates).
// A pixel whose samples and centre are all one triangle's takes no record: it is `solo`, and
// neighbouring solo pixels of one triangle on a row form a run.
void TileABuffer::collect_records() {
  const int w = rect_.x1 - rect_.x0, h = rect_.y1 - rect_.y0;
  records_.clear();
  runs_.clear();
  record_begin_.assign(size_t(abuffer_tile) * abuffer_tile + 1, 0);
  solo_.assign(size_t(abuffer_tile) * abuffer_tile, no_owner);
  const int S = set_.count;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t pixel = size_t(y) * abuffer_tile + size_t(x);
      const uint32_t* own = owner_.data() + pixel * size_t(stride_);
      const size_t begin = records_.size();
      bool one_owner = own[S] != no_owner;
      for (int s = 0; s < S; ++s) one_owner &= own[s] == own[S];
      solo_[pixel] = one_owner ? own[S] : no_owner;
      record_begin_[pixel + 1] = uint32_t(begin);
      if (one_owner) {  // the common interior pixel, one triangle's: no record, a run of the row
        if (x > 0 && solo_[pixel - 1] == own[S] && !runs_.empty() && runs_.back().pixel + runs_.back().n == pixel) {
          ++runs_.back().n;
        } else {
          runs_.push_back({own[S], uint16_t(pixel), 1});
        }
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
    for (int x = w; x < abuffer_tile; ++x)
      record_begin_[size_t(y) * abuffer_tile + size_t(x) + 1] = uint32_t(records_.size());
  }
}

// The colour of a pixel with translucent layers: per sample, its opaque owner's colour (or the
// background) with the layers covering it composited over in order, averaged over the samples.
Color TileABuffer::composite(size_t pixel, const Color* sample_colour) const {
  const Layer* list = layers_.data() + pixel * max_translucent_layers;
  const int count = layer_count_[pixel];
  Color sum(0.0f);
  for (int s = 0; s < set_.count; ++s) {
    Color c = sample_colour[s];
    for (int l = 0; l < count; ++l) {
      if (list[l].mask >> s & 1u) c = list[l].alpha * list[l].colour + (1.0f - list[l].alpha) * c;
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
      layer_order_.push_back(
          {layers_[pixel * max_translucent_layers + l].tri, uint32_t(pixel * max_translucent_layers + l)});
    }
  }
  std::sort(layer_order_.begin(), layer_order_.end());
  for (const auto& [tri, at] : layer_order_) {
    Layer& l = layers_[at];
    const TileTriangle& t = tris_[tri];
    const size_t pixel = at / max_translucent_layers;
    l.colour = shading.shade(t, constant ? Fragment{}
                                         : fragment_at(t, rect_.x0 + int(pixel % abuffer_tile),
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

// composite() with one colour per triangle (tri_colour_).
Color TileABuffer::composite_constant(size_t pixel, const uint32_t* own, Color background) const {
  Color sample_colour[16];
  for (int s = 0; s < set_.count; ++s) sample_colour[s] = own[s] == no_owner ? background : tri_colour_[own[s]];
  return composite(pixel, sample_colour);
}

void TileABuffer::resolve(TileShading& shading, Color background, uint8_t* rgb, uint32_t* ids, size_t width) {
  if (shading.constant()) return resolve_constant(shading, background, rgb, ids, width);
  collect_records();
  shade_opaque(shading);
  if (has_layers_) shade_layers(shading, false);
  const int w = rect_.x1 - rect_.x0, h = rect_.y1 - rect_.y0, S = set_.count;
  const float share = 1.0f / float(S);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t pixel = size_t(y) * abuffer_tile + size_t(x);
      const Record* first = records_.data() + record_begin_[pixel];
      const Record* last = records_.data() + record_begin_[pixel + 1];
      const int layers = has_layers_ ? layer_count_[pixel] : 0;
      const uint32_t centre = owner_[pixel * size_t(stride_) + size_t(S)];
      const bool solo = solo_[pixel] != no_owner;
      if (!solo && first == last && layers == 0 && centre == no_owner) continue;
      Color c;
      if (layers > 0) {
        Color sample_colour[16];
        for (int s = 0; s < S; ++s) sample_colour[s] = solo ? solo_colour_[pixel] : background;
        for (const Record* r = first; r != last; ++r) {
          for (int s = 0; s < S; ++s) sample_colour[s] = r->mask >> s & 1u ? r->colour : sample_colour[s];
        }
        c = composite(pixel, sample_colour);
      } else if (solo) {
        c = solo_colour_[pixel];  // colour x (S x 1/S) + background x 0, exactly
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

// Shades the runs and records triangle by triangle (counting sorts), so each polygon is bound once
// per tile: runs of at least min_run pixels as one span, the rest per fragment.
void TileABuffer::shade_opaque(TileShading& shading) {
  std::vector<uint32_t>& start = tri_start_;
  start.assign(tris_.size() + 1, 0);
  for (const Record& r : records_) ++start[r.tri + 1];
  for (size_t t = 0; t < tris_.size(); ++t) start[t + 1] += start[t];
  order_.resize(records_.size());
  for (uint32_t n = 0; n < records_.size(); ++n) order_[start[records_[n].tri]++] = n;
  run_start_.assign(tris_.size() + 1, 0);
  for (const Run& r : runs_) ++run_start_[r.tri + 1];
  for (size_t t = 0; t < tris_.size(); ++t) run_start_[t + 1] += run_start_[t];
  run_order_.resize(runs_.size());
  for (uint32_t n = 0; n < runs_.size(); ++n) run_order_[run_start_[runs_[n].tri]++] = n;
  solo_colour_.resize(size_t(abuffer_tile) * abuffer_tile);
  size_t next_record = 0, next_run = 0;
  for (uint32_t t = 0; t < tris_.size(); ++t) {
    const TileTriangle& tri = tris_[t];
    for (; next_run < run_order_.size() && runs_[run_order_[next_run]].tri == t; ++next_run) {
      const Run& run = runs_[run_order_[next_run]];
      const int x = rect_.x0 + run.pixel % abuffer_tile, y = rect_.y0 + run.pixel / abuffer_tile;
      if (run.n >= min_run) {
        shading.shade_run(tri, x, y, run.n, solo_colour_.data() + run.pixel);
        continue;
      }
      for (int i = 0; i < run.n; ++i)
        solo_colour_[run.pixel + size_t(i)] = shading.shade(tri, centre_fragment(tri, x + i, y));
    }
    for (; next_record < order_.size() && records_[order_[next_record]].tri == t; ++next_record) {
      Record& r = records_[order_[next_record]];
      r.colour = shading.shade(
          tri, fragment_at(tri, rect_.x0 + r.pixel % abuffer_tile, rect_.y0 + r.pixel / abuffer_tile, r.sample));
    }
  }
}

}  // namespace rr

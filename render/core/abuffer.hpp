// The A-buffer of one 64x64 screen tile (docs/antialiasing.md). In: fan triangles in screen space
// (raster.hpp's integer set-up) with a visibility key per sub-sample; out: per pixel the fragments
// visible in at least one sub-sample (coverage mask, one colour each), resolved into RGB8 and the id
// of the surface under the pixel centre. Sub-sample inside tests are raster.hpp's exact edge
// functions with the top-left rule evaluated at each sample point, so polygons sharing an edge cover
// each sub-sample once. Keys: larger is nearer; ties keep the first writer.
#pragma once

#include "render/core/image.hpp"
#include "render/core/math.hpp"
#include "render/core/raster.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

namespace rr {

constexpr int abuffer_tile = 64;           // pixels per tile side, as the pipelines' screen tiles
constexpr int max_translucent_layers = 8;  // per pixel; past it the first-composited layer is dropped
constexpr uint32_t no_owner = 0xFFFFFFFFu;

// A pattern's samples in sub-pixel units (raster.hpp) from the pixel centre; sample `count` is the centre itself,
// which decides the id buffer and the shading point but carries no colour weight.
struct SampleSet {
  int count = 1;             // S, colour samples
  uint32_t colour_bits = 1;  // bits 0 .. S-1
  int32_t dx[17] = {}, dy[17] = {};
  int nearest[17] = {};  // sample indices by distance from the centre (ties by index)
};
SampleSet make_sample_set(int samples);

// One triangle's edge-function offsets at each sample (exact integers: the sample offsets are whole
// sub-pixel units and step_x, step_y multiples of subpixel_one).
struct SampleEdges {
  int n = 1;  // samples tested: S + 1
  int64_t de[3][17] = {};
  int64_t reach[3] = {};  // max of de[k]: no sample of a pixel is inside where e[k] + reach[k] < 0
  int64_t inner[3] = {};  // min of de[k]: every sample is inside where all e[k] + inner[k] >= 0
  double dz[17] = {};     // 1/w at each sample less 1/w at the centre
  double dz_dx = 0.0;     // 1/w step per pixel along x
};
void setup_sample_edges(const TriangleSetup& s, const double inv_w[3], const SampleSet& set, SampleEdges& out);

// Bit i set when sample i lies inside the triangle whose edge values at the pixel centre are e[].
inline uint32_t sample_mask(const SampleEdges& se, const int64_t e[3]) {
  uint32_t m = 0;
  for (int i = 0; i < se.n; ++i) {
    // All three are >= 0 exactly when their bitwise OR is.
    m |= uint32_t(((e[0] + se.de[0][i]) | (e[1] + se.de[1][i]) | (e[2] + se.de[2][i])) >= 0) << i;
  }
  return m;
}

// 1/w at the pixel centre with edge values e[] (raster.hpp's pixel_weights' sum).
inline double centre_inv_w(const TriangleSetup& s, const double inv_w[3], const int64_t e[3]) {
  double z = 0.0;
  for (int k = 0; k < 3; ++k) z += double(e[k] + s.bias[k]) * s.inv_area * inv_w[s.order[k]];
  return z;
}

// Calls fn(y, x, n, e) for each row of pixels in `rect` that may have a sample inside (x .. x + n - 1,
// edge values e[] at the centre of (x, y)); a superset by at most the pixels whose masks are empty.
template <class Fn>
void sample_spans(const TriangleSetup& s, const SampleEdges& se, const PixelRect& rect, Fn&& fn) {
  // A sample lies within half a pixel of its centre, so one pixel beyond the centres' bounds.
  const int px0 = std::max(rect.x0, s.px0 - 1), px1 = std::min(rect.x1 - 1, s.px1 + 1);
  const int py0 = std::max(rect.y0, s.py0 - 1), py1 = std::min(rect.y1 - 1, s.py1 + 1);
  if (px0 > px1 || py0 > py1) return;
  int64_t e_row[3] = {s.edge(0, px0, py0), s.edge(1, px0, py0), s.edge(2, px0, py0)};
  for (int y = py0; y <= py1; ++y) {
    const int64_t reach[3] = {e_row[0] + se.reach[0], e_row[1] + se.reach[1], e_row[2] + se.reach[2]};
    int64_t first, last = px1 - px0;
    row_span(s, reach, first, last);
    if (last >= first) {
      const int64_t e[3] = {e_row[0] + first * s.step_x[0], e_row[1] + first * s.step_x[1],
                            e_row[2] + first * s.step_x[2]};
      fn(y, px0 + int(first), int(last - first + 1), e);
    }
    for (int k = 0; k < 3; ++k) e_row[k] += s.step_y[k];
  }
}

// A float 1/w as a key that orders like it (non-negative floats order as their bits); 0 for none.
inline uint32_t depth_key(double inv_w) {
  const float z = float(inv_w);
  return z > 0.0f ? std::bit_cast<uint32_t>(z) : 0u;
}

// A fan triangle drawn into a tile. `item` is the caller's surface (one per polygon): fragments of
// one item in one pixel are shaded once, whichever of its triangles own the samples.
struct TileTriangle {
  TriangleSetup setup;
  double inv_w[3] = {1.0, 1.0, 1.0};  // in the caller's vertex order
  uint32_t item = 0;
  uint32_t k = 0;      // fan triangle (0, k+1, k+2) of the item's clipped polygon
  uint32_t group = 0;  // plane group (depth keys only): a sample owned by the same group is kept
};

// How the resolve shades and names the items (each pipeline binds its own SurfaceShader).
class TileShading {
 public:
  virtual ~TileShading() = default;
  // f's weights are for fan triangle t.k of the item; called grouped by triangle in draw order.
  virtual Color shade(const TileTriangle& t, const Fragment& f) = 0;
  virtual uint32_t id(uint32_t item) const = 0;
  virtual float alpha(uint32_t item) const = 0;  // opacity of a translucent item
  // True when shade() does not depend on the triangle's binding (one colour per polygon): the
  // resolve then shades in pixel order without grouping by triangle.
  virtual bool constant() const = 0;
  // The colours of pixels x .. x + n - 1 (n <= abuffer_tile) of row y, each wholly triangle t's and
  // shaded at its centre. The default calls shade() per pixel; a pipeline may shade them as a span.
  virtual void shade_run(const TileTriangle& t, int x, int y, int n, Color* out);
};

// raster.hpp's fragment of triangle t at the centre of pixel (x, y): 1/w and weights.
Fragment centre_fragment(const TileTriangle& t, int x, int y);

// Per-tile state; one per worker thread, reused across tiles and frames (no allocation once grown).
class TileABuffer {
 public:
  void begin(const PixelRect& rect, const SampleSet& set);
  // Adds a triangle; false when it has no area.
  bool add(const TriangleSetup& s, const double inv_w[3], uint32_t item, uint32_t k, uint32_t group = 0);
  // The last added triangle takes every sample it covers whose key is smaller than its own: the
  // interpolated 1/w when `depth_keyed`, else `key`. Returns the pixels with a covered sample.
  size_t cover_opaque(bool depth_keyed, uint32_t key);
  // The last added triangle as a translucent layer of composite position `order` (increasing
  // orders are composited later, i.e. nearer), over the samples where it is nearer than the opaque
  // owner. Draw every opaque triangle of the tile first.
  size_t cover_translucent(bool depth_keyed, uint32_t key, uint32_t order);
  // Shades each visible fragment once, blends by coverage over `background` and writes the tile's
  // pixels and ids (the centre's surface; untouched where no sample is covered).
  void resolve(TileShading& shading, Color background, uint8_t* rgb, uint32_t* ids, size_t width);
  // The most a tile buffer holds at `samples` sub-samples: keys and owners of S + 1 samples, the
  // layers, and S opaque records per pixel.
  static size_t bytes(int samples);

 private:
  struct Layer {
    uint32_t tri, order, mask;
    uint8_t sample;  // shading point: the centre when inside, else the nearest covered sample
    float alpha;
    Color colour;
  };
  struct Record {  // one opaque item's samples in one pixel
    uint32_t tri, mask;
    uint16_t pixel;
    uint8_t sample;
    Color colour;
  };
  uint8_t shading_sample(uint32_t inside) const;
  double centre_row_inv_w(const TileTriangle& t, int x, const int64_t e[3], int& zx) const;
  Fragment fragment_at(const TileTriangle& t, int x, int y, int sample) const;
  void collect_records();
  void resolve_constant(TileShading& shading, Color background, uint8_t* rgb, uint32_t* ids, size_t width);
  void shade_layers(TileShading& shading, bool constant);
  uint32_t top_at_centre(size_t pixel, uint32_t centre) const;
  Color composite_constant(size_t pixel, const uint32_t* own, Color background) const;
  struct Run {  // solo pixels of one triangle following each other on a row
    uint32_t tri;
    uint16_t pixel, n;
  };
  Color composite(size_t pixel, const Color* sample_colour) const;
  void shade_opaque(TileShading& shading);

  PixelRect rect_;
  SampleSet set_;
  int stride_ = 1;  // S + 1 samples per pixel
  std::vector<TileTriangle> tris_;
  std::vector<uint32_t> key_, owner_;  // per tile pixel x stride
  std::vector<Layer> layers_;          // per tile pixel x max_translucent_layers
  std::vector<uint8_t> layer_count_;   // per tile pixel
  bool has_layers_ = false;
  std::vector<Record> records_;
  std::vector<uint32_t> record_begin_;  // per tile pixel + 1
  std::vector<uint32_t> order_;         // records sorted by triangle
  std::vector<uint32_t> solo_;          // per tile pixel: its one triangle, else no_owner
  std::vector<Color> solo_colour_;      // per tile pixel, for solo pixels
  std::vector<Run> runs_;
  std::vector<uint32_t> run_start_, run_order_;
  std::vector<uint32_t> tri_start_;
  std::vector<Color> tri_colour_;  // one colour per polygon: per triangle
  std::vector<uint32_t> tri_id_;
  std::vector<std::array<uint8_t, 3>> tri_bytes_;
  std::vector<std::pair<uint32_t, uint32_t>> layer_order_;  // (tri, pixel * cap + slot)
  SampleEdges edges_;
};

// The calling thread's tile buffers, at least `count` of them, kept for its next frame: a frame's
// workers reuse them tile after tile, so no frame faults in fresh pages.
std::vector<TileABuffer>& kept_tile_buffers(unsigned count);

// The memory budget's count for one frame (docs/antialiasing.md, "Memory"): per pixel the image
// (3 bytes), ids (4), the z-buffer's depth and triangle (8) and, with samples > 1, the front-to-back
// walk's coverage mask (4); plus, with samples > 1, one tile buffer per tile worked on at once (at
// most the pool's threads + 1, and no more than there are tiles).
long long render_bytes(int width, int height, int samples);

}  // namespace rr

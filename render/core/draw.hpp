// The front end every pipeline shares after tessellation: back-face test, clipping of one world
// polygon to clip space, projection to screen vertices, and rasterization of the resulting convex
// polygon as a fan. Fan triangles share edges, and the top-left rule covers those pixels once.
#pragma once

#include "render/core/camera.hpp"
#include "render/core/image.hpp"
#include "render/core/raster.hpp"
#include "render/core/tessellate.hpp"

#include <span>
#include <vector>

namespace rr {

// True when the eye is behind (or on) the plane of a polygon of a closed object, so it cannot be
// seen. Open surfaces are never back-facing.
inline bool is_back_facing(const Polygon& polygon, Vec3 eye) {
  return (polygon.flags & polygon_closed) && glm::dot(polygon.normal, eye) - polygon.offset <= 0.0;
}

struct DrawScratch {
  std::vector<ClipVertex> in, clipped, tmp;
  std::vector<RasterVertex> screen;  // matches `clipped` vertex for vertex
};

// Clips a polygon to the view volume and projects it; false when nothing is left.
bool project_polygon(const ViewTransform& view, const PolygonSoup& soup, const Polygon& polygon, DrawScratch& scratch);

// Rasterizes a projected convex polygon as the fan (0, k+1, k+2). Calls fn(fragment, k): the
// fragment's barycentrics weight vertices 0, k+1 and k+2 of `screen`.
template <class Fn>
void rasterize_convex(std::span<const RasterVertex> screen, const PixelRect& rect, Fn&& fn) {
  for (size_t k = 0; k + 2 < screen.size(); ++k) {
    rasterize_triangle(screen[0], screen[k + 1], screen[k + 2], rect, [&](const Fragment& f) { fn(f, k); });
  }
}

// Where fragments go, and how they combine with what is there.
enum class DepthMode {
  none,            // priority pipelines (painter, bsp): the drawing order decides, last one wins
  test_and_write,  // opaque z-buffering: nearer 1/w wins, ties keep the first drawn
  test_only,       // translucent over a z-buffer: hidden behind opaque surfaces, writes no depth
};

struct FrameTarget {
  Image& image;
  IdBuffer& ids;
  std::vector<float>* depth = nullptr;  // 1/w per pixel; required unless DepthMode::none
  PixelRect rect;
};

// Draws the polygon last projected into `scratch`: for each covered pixel that passes the depth
// mode, writes `id` and shade(fragment, k) blended with `alpha` (1 = opaque) over the pixel.
// Returns the number of covered pixels (before the depth test).
template <class ShadeFn>
size_t draw_projected(FrameTarget& t, const DrawScratch& scratch, uint32_t id, float alpha, DepthMode mode,
                      ShadeFn&& shade) {
  size_t covered = 0;
  const size_t width = size_t(t.image.width);
  // Raw pointers in locals: the colour writes go through uint8_t*, which may alias anything, so
  // through the vectors the compiler would reload every pointer for every fragment.
  float* const depth = t.depth ? t.depth->data() : nullptr;
  uint32_t* const ids = t.ids.ids.data();
  uint8_t* const rgb = t.image.rgb.data();
  rasterize_convex(scratch.screen, t.rect, [&](const Fragment& f, size_t k) {
    ++covered;
    const size_t i = size_t(f.y) * width + size_t(f.x);
    if (mode != DepthMode::none) {
      const float z = float(f.inv_w);
      if (z <= depth[i]) return;
      if (mode == DepthMode::test_and_write) depth[i] = z;
    }
    ids[i] = id;
    const Color c = shade(f, k);
    uint8_t* px = rgb + i * 3;
    if (alpha >= 1.0f) {
      px[0] = to_byte(c.r), px[1] = to_byte(c.g), px[2] = to_byte(c.b);
    } else {
      for (int ch = 0; ch < 3; ++ch) px[ch] = to_byte(alpha * c[ch] + (1.0f - alpha) * float(px[ch]) / 255.0f);
    }
  });
  return covered;
}

}  // namespace rr

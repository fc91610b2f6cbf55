// The bsp pipeline's front-to-back walk with a coverage buffer (docs/bsp.md "Occlusion"). In: a
// tree and one frame; out: the same image and ids as the back-to-front walk, drawing each pixel
// once. Opaque polygons are drawn nearest first and a pixel keeps its first writer; a subtree whose
// screen rectangle is wholly written is skipped, and the walk ends when every pixel is. Translucent
// polygons met on the way are blended afterwards, back to front, where they lie in front of the
// pixel's opaque writer, which is what the back-to-front walk leaves there.
#include "render/pipelines/bsp.hpp"

#include "render/core/draw.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

namespace rr {

namespace {

// Which pixels an opaque polygon has written, kept in the frame's own id buffer while the walk runs:
// a pixel holds the walk position of its writer, or background_id (no writer), and finish() turns
// positions into polygon ids. No buffer of its own: a per-frame 3.7 MB allocation at 1280x720 cost
// more in page faults than the pixels it saved. Per 8x8 tile, the number written, so that a
// rectangle's test skips whole tiles.
class Coverage {
 public:
  static constexpr int tile = 8;

  explicit Coverage(IdBuffer& ids)
      : width_(ids.width), height_(ids.height), tiles_x_((ids.width + tile - 1) / tile), writer_(ids.ids),
        written_(size_t(tiles_x_) * size_t((ids.height + tile - 1) / tile), 0) {}

  uint32_t writer(size_t pixel) const { return writer_[pixel]; }
  bool full() const { return total_ == writer_.size(); }
  // Claims pixel (x, y) (index `pixel`) for the polygon at walk position `seq`; false when an
  // earlier one holds it.
  bool claim(size_t pixel, int x, int y, uint32_t seq) {
    uint32_t& w = writer_[pixel];
    if (w != background_id) return false;
    w = seq;
    ++written_[size_t(y / tile) * size_t(tiles_x_) + size_t(x / tile)];
    ++total_;
    return true;
  }
  // A translucent polygon drawn over the pixel: later (nearer) ones compare with it.
  void overlay(size_t pixel, uint32_t seq) { writer_[pixel] = seq; }
  // Whether every pixel of [x0, x1) x [y0, y1) (inside the image) is written.
  bool covered(int x0, int y0, int x1, int y1) const {
    for (int ty = y0 / tile; ty * tile < y1; ++ty) {
      for (int tx = x0 / tile; tx * tile < x1; ++tx) {
        const int ax = tx * tile, ay = ty * tile;
        const int bx = std::min(ax + tile, width_), by = std::min(ay + tile, height_);
        if (written_[size_t(ty) * size_t(tiles_x_) + size_t(tx)] == (bx - ax) * (by - ay)) continue;
        if (ax >= x0 && bx <= x1 && ay >= y0 && by <= y1) return false;  // a hole inside the rectangle
        for (int y = std::max(ay, y0); y < std::min(by, y1); ++y) {
          for (int x = std::max(ax, x0); x < std::min(bx, x1); ++x) {
            if (writer_[size_t(y) * size_t(width_) + size_t(x)] == background_id) return false;
          }
        }
      }
    }
    return true;
  }
  // Walk positions -> polygon ids (`id_of` is indexed by walk position).
  void finish(const std::vector<uint32_t>& id_of) {
    for (uint32_t& w : writer_) {
      if (w != background_id) w = id_of[w];
    }
  }

 private:
  int width_, height_, tiles_x_;
  std::vector<uint32_t>& writer_;
  std::vector<uint16_t> written_;  // at most tile^2 = 64
  size_t total_ = 0;
};

// Whether every pixel whose centre lies in the screen rectangle [min, max] is written. One pixel of
// margin on each side covers the rasterizer's vertex snapping (1/256 pixel) and pixel-centre
// sampling: a polygon whose screen vertices lie in the rectangle writes no pixel outside it.
bool rect_hidden(const Coverage& coverage, const ViewTransform& view, Vec2 min, Vec2 max) {
  auto clamp_to = [](double v, int limit) { return int(std::clamp(v, 0.0, double(limit))); };
  const int x0 = clamp_to(std::floor(min.x) - 1.0, view.width), x1 = clamp_to(std::ceil(max.x) + 2.0, view.width);
  const int y0 = clamp_to(std::floor(min.y) - 1.0, view.height), y1 = clamp_to(std::ceil(max.y) + 2.0, view.height);
  return x0 < x1 && y0 < y1 && coverage.covered(x0, y0, x1, y1);
}

// Whether every pixel a polygon inside the box could write is already written. The box's corners
// project to a rectangle that holds the projection of everything inside it when all of them are in
// front of the eye (w > 0); otherwise the box is not tested.
bool box_hidden(const Coverage& coverage, const ViewTransform& view, Vec3 lo, Vec3 hi) {
  Vec2 min(std::numeric_limits<double>::infinity()), max(-std::numeric_limits<double>::infinity());
  for (int c = 0; c < 8; ++c) {
    const Vec3 p(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
    const Vec4 clip = view.clip_from_world * Vec4(p, 1.0);
    if (!(clip.w > 0.0)) return false;
    const Vec2 s = screen_from_clip(view, clip);
    min = glm::min(min, s), max = glm::max(max, s);
  }
  return rect_hidden(coverage, view, min, max);
}

// The same test for a projected polygon (its clipped screen vertices).
bool polygon_hidden(const Coverage& coverage, const ViewTransform& view, std::span<const RasterVertex> screen) {
  Vec2 min(std::numeric_limits<double>::infinity()), max(-std::numeric_limits<double>::infinity());
  for (const RasterVertex& v : screen) min = glm::min(min, Vec2(v.x, v.y)), max = glm::max(max, Vec2(v.x, v.y));
  return rect_hidden(coverage, view, min, max);
}

// The pixel write of draw_projected: opaque colours replace, translucent ones blend over.
void write_pixel(Image& image, size_t pixel, Color c, float alpha) {
  uint8_t* px = image.rgb.data() + pixel * 3;
  if (alpha >= 1.0f) {
    px[0] = to_byte(c.r), px[1] = to_byte(c.g), px[2] = to_byte(c.b);
  } else {
    for (int ch = 0; ch < 3; ++ch) px[ch] = to_byte(alpha * c[ch] + (1.0f - alpha) * float(px[ch]) / 255.0f);
  }
}

struct Translucent {
  uint32_t index;  // in the tree's fragments
  uint32_t seq;    // walk position: in front of every opaque writer with a larger one
};

// One frame's walk: the coverage, the shader and the per-stage clocks shared by its steps.
class FrontToBack {
 public:
  FrontToBack(const BspTree& tree, const FrameInput& input, Frame& frame, RenderStats& stats)
      : tree_(tree), soup_(tree.fragments), input_(input), view_(input.view), frame_(frame), stats_(stats),
        frustum_(input.view), coverage_(frame.ids), shader_(input, soup_) {}

  // A subtree is entered unless it is outside the frustum or its screen rectangle is all written.
  bool enter(int32_t index, const BspNode& node) {
    const bool outside = frustum_.outside(node.lo, node.hi);
    if (!outside && !box_hidden(coverage_, view_, node.lo, node.hi)) return true;
    if (!outside) ++stats_.bsp_subtrees_occluded;
    culled_ += subtree_polygons(tree_, index);
    return false;
  }

  // Draws an opaque polygon on the pixels nobody wrote (translucent ones wait); false when the
  // screen is full and nothing later can show.
  bool emit(uint32_t index) {
    if ((seq_ & 4095) == 4095) check_cancel(input_.context.cancel);
    const uint32_t position = seq_++;
    const Polygon& poly = soup_.polygons[index];
    id_of_.push_back(poly.id);
    if (poly.flags & polygon_translucent) {
      translucent_.push_back({index, position});
      return true;
    }
    walk_ms_ += clock_.lap_ms();
    if (project(index, true)) {
      draw(1.0f, [&](size_t pixel, int x, int y) { return coverage_.claim(pixel, x, y, position); });
    }
    stats_.bsp_screen_full = coverage_.full();
    return !stats_.bsp_screen_full;
  }

  // Translucent polygons, farthest first, over the pixels whose opaque writer lies behind them.
  void blend_translucent() {
    walk_ms_ += clock_.lap_ms();
    for (auto it = translucent_.rbegin(); it != translucent_.rend(); ++it) {
      const Polygon& poly = soup_.polygons[it->index];
      if (!project(it->index, false)) continue;
      const uint32_t seq = it->seq;
      // Drawn farthest first, so a pixel's last translucent writer is farther than this one too.
      draw(soup_.materials[poly.material].opacity, [&](size_t pixel, int, int) {
        if (coverage_.writer(pixel) < seq) return false;
        coverage_.overlay(pixel, seq);
        return true;
      });
    }
  }

  void finish(StageTimings& timings) {
    coverage_.finish(id_of_);
    raster_ms_ += clock_.lap_ms();
    stats_.polygons_culled = culled_;  // fragments: back faces, outside the frustum, hidden, clipped away
    timings.traverse_ms += walk_ms_;
    timings.shade_ms += shade_ms_;
    timings.raster_ms += raster_ms_;
  }

  size_t& culled() { return culled_; }

 private:
  // Clips, projects and binds the shader; false when nothing is left to draw, or when `opaque` and
  // every pixel it could write is written (a translucent one still shows over those).
  bool project(uint32_t index, bool opaque) {
    if (!project_polygon(view_, soup_, soup_.polygons[index], scratch_)) {
      ++culled_;
      return false;
    }
    if (opaque && polygon_hidden(coverage_, view_, scratch_.screen)) {
      ++culled_;
      ++stats_.bsp_polygons_occluded;
      return false;
    }
    shader_.prepare(index);
    shader_.bind(index, scratch_);
    shade_ms_ += clock_.lap_ms();
    ++stats_.polygons_drawn;
    stats_.triangles += scratch_.screen.size() - 2;
    return true;
  }

  // Rasterizes the projected polygon; `accept(pixel, x, y)` decides which covered pixels it writes.
  template <class Accept>
  void draw(float alpha, Accept&& accept) {
    const size_t width = size_t(frame_.image.width);
    rasterize_convex(scratch_.screen, {0, 0, frame_.image.width, frame_.image.height},
                     [&](const Fragment& f, size_t k) {
                       ++stats_.fragments;
                       const size_t pixel = size_t(f.y) * width + size_t(f.x);
                       if (!accept(pixel, f.x, f.y)) return;  // it also records the writer
                       write_pixel(frame_.image, pixel, shader_.fragment(f, k), alpha);
                     });
    raster_ms_ += clock_.lap_ms();
  }

  const BspTree& tree_;
  const PolygonSoup& soup_;
  const FrameInput& input_;
  const ViewTransform& view_;
  Frame& frame_;
  RenderStats& stats_;
  const Frustum frustum_;
  Coverage coverage_;
  SurfaceShader shader_;
  DrawScratch scratch_;
  std::vector<Translucent> translucent_;
  std::vector<uint32_t> id_of_;  // polygon id per walk position
  Stopwatch clock_;
  size_t culled_ = 0;
  uint32_t seq_ = 0;
  double walk_ms_ = 0.0, shade_ms_ = 0.0, raster_ms_ = 0.0;
};

}  // namespace

void draw_bsp_front_to_back(const BspTree& tree, const FrameInput& input, Frame& frame, RenderStats& stats,
                            StageTimings& timings) {
  FrontToBack walk(tree, input, frame, stats);
  walk_bsp(
      tree, input.view.eye, WalkOrder::front_to_back,
      [&](int32_t index, const BspNode& node) { return walk.enter(index, node); },
      [&](uint32_t index) { return walk.emit(index); }, walk.culled());
  walk.blend_translucent();
  walk.finish(timings);
}

}  // namespace rr

// The bsp pipeline's front-to-back walk with a coverage buffer (docs/bsp.md "Occlusion"). In: a
// tree and one frame; out: the same image and ids as the back-to-front walk, shading each pixel
// once. The walk (one thread) rasterizes opaque polygons nearest first for coverage only, a pixel
// keeping its first writer; a subtree whose screen rectangle is wholly written is skipped, and the
// walk ends when every pixel is. Then the tiles are shaded on the thread pool (draw_first_wins):
// each pixel by its writer, and the translucent polygons met on the way, back to front, where they
// lie in front of the pixel's opaque writer, which is what the back-to-front walk leaves there.
// With options.antialias > 1 the walk claims sub-samples instead and a pixel is written when all of
// them and its centre are; the tiles then resolve through the A-buffer (ordered_draw_aa.cpp).
#include "render/pipelines/bsp.hpp"

#include "render/core/abuffer.hpp"
#include "render/core/draw.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/ordered_draw.hpp"

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

  // With samples > 1 a pixel is written when its sub-samples and its centre are all claimed, in a
  // mask per pixel (kept by the thread for its next frame); the id buffer is left to the drawing.
  Coverage(IdBuffer& ids, int samples)
      : width_(ids.width),
        height_(ids.height),
        tiles_x_((ids.width + tile - 1) / tile),
        writer_(ids.ids),
        written_(size_t(tiles_x_) * size_t((ids.height + tile - 1) / tile), 0) {
    if (samples <= 1) return;
    thread_local std::vector<uint32_t> kept_masks;
    masks_ = &kept_masks;
    masks_->assign(writer_.size(), 0u);
    set_ = make_sample_set(samples);
    full_mask_ = (uint32_t{2} << samples) - 1;  // the samples and the centre
  }

  bool sampled() const { return masks_ != nullptr; }
  // Claims the sub-samples a triangle covers; returns the pixels where it covers any.
  size_t claim_samples(const TriangleSetup& s, const double inv_w[3]) {
    SampleEdges se;
    setup_sample_edges(s, inv_w, set_, se);
    size_t covered = 0;
    sample_spans(s, se, PixelRect{0, 0, width_, height_}, [&](int y, int x, int n, const int64_t e0[3]) {
      int64_t e[3] = {e0[0], e0[1], e0[2]};
      uint32_t* const row = masks_->data() + size_t(y) * size_t(width_);
      uint16_t* const written = written_.data() + size_t(y / tile) * size_t(tiles_x_);
      for (int i = x; i < x + n; ++i, e[0] += s.step_x[0], e[1] += s.step_x[1], e[2] += s.step_x[2]) {
        const uint32_t m = sample_mask(se, e);
        if (m == 0) continue;
        ++covered;
        const uint32_t before = row[i], after = before | m;
        row[i] = after;
        if (before != full_mask_ && after == full_mask_) ++written[i / tile], ++total_;
      }
    });
    return covered;
  }

  bool full() const { return total_ == writer_.size(); }
  // Claims the unwritten pixels of x .. x + n - 1 on row y for the polygon at walk position `seq`.
  void claim_span(int y, int x, int n, uint32_t seq) {
    uint32_t* const row = writer_.data() + size_t(y) * size_t(width_);
    uint16_t* const written = written_.data() + size_t(y / tile) * size_t(tiles_x_);
    // Per 8-pixel piece, branch-free so that it vectorizes: most pixels are claimed.
    for (int a = x; a < x + n;) {
      const int b = std::min(x + n, (a / tile + 1) * tile);
      int claimed = 0;
      for (int i = a; i < b; ++i) {
        const bool free = row[i] == background_id;
        row[i] = free ? seq : row[i];
        claimed += free;
      }
      written[a / tile] = uint16_t(written[a / tile] + claimed);
      total_ += size_t(claimed);
      a = b;
    }
  }
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
            if (!written(size_t(y) * size_t(width_) + size_t(x))) return false;
          }
        }
      }
    }
    return true;
  }

 private:
  bool written(size_t i) const { return masks_ ? (*masks_)[i] == full_mask_ : writer_[i] != background_id; }

  int width_, height_, tiles_x_;
  std::vector<uint32_t>& writer_;
  std::vector<uint32_t>* masks_ = nullptr;
  SampleSet set_;
  uint32_t full_mask_ = 0;
  std::vector<uint16_t> written_;  // at most tile^2 = 64
  size_t total_ = 0;
};

// Whether every pixel whose centre lies in the screen rectangle [min, max] is written. One pixel of
// margin on each side covers the rasterizer's vertex snapping (raster.hpp's sub-pixel grid) and pixel-centre
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

struct Translucent {
  uint32_t index;  // in the tree's fragments
  uint32_t seq;    // walk position: in front of every opaque writer with a larger one
};

// One frame's walk: the coverage, the shader and the per-stage clocks shared by its steps.
class FrontToBack {
 public:
  FrontToBack(const BspTree& tree, const FrameInput& input, Frame& frame, RenderStats& stats, ProjectedSet& drawn)
      : tree_(tree),
        soup_(tree.fragments),
        input_(input),
        view_(input.view),
        frame_(frame),
        stats_(stats),
        frustum_(input.view),
        coverage_(frame.ids, input.options.antialias),
        shader_(input, soup_),
        drawn_(drawn) {
    drawn_.clear();
  }

  // A subtree is entered unless it is outside the frustum or its screen rectangle is all written.
  // With occlusion culling, also unless it lies behind the frame's depth pyramid (bsp_node_occluded).
  bool enter(int32_t index, const BspNode& node) {
    const bool outside = frustum_.outside(node.lo, node.hi);
    if (!outside && !box_hidden(coverage_, view_, node.lo, node.hi) && !bsp_node_occluded(input_, node, stats_)) {
      return true;
    }
    if (!outside) ++stats_.bsp_subtrees_occluded;
    culled_ += subtree_polygons(tree_, index);
    return false;
  }

  // Claims for an opaque polygon the pixels nobody wrote (translucent ones wait); false when the
  // screen is full and nothing later can show.
  bool emit(uint32_t index) {
    if ((seq_ & 4095) == 4095) check_cancel(input_.context.cancel);
    const Polygon& poly = soup_.polygons[index];
    if (!input_.id_may_show(poly.id)) {  // a piece of a polygon the occlusion walk found hidden
      ++culled_;
      return true;
    }
    const uint32_t position = seq_++;
    id_of_.push_back(poly.id);
    if (poly.flags & polygon_translucent) {
      translucent_.push_back({index, position});
      return true;
    }
    walk_ms_ += clock_.lap_ms();
    if (project(index, position, true)) claim(position);
    stats_.bsp_screen_full = coverage_.full();
    return !stats_.bsp_screen_full;
  }

  // Shades the claimed pixels, then the translucent polygons farthest first, tile by tile.
  void draw() {
    walk_ms_ += clock_.lap_ms();
    for (auto it = translucent_.rbegin(); it != translucent_.rend(); ++it) project(it->index, it->seq, false);
    thread_local TileGrid grid;  // kept for this thread's next frame
    bin_projected(drawn_, frame_.image.width, frame_.image.height, grid);
    check_cancel(input_.context.cancel);
    const DrawSource source{&soup_, &shader_};
    stats_.fragments +=
        draw_first_wins(input_, {&source, 1}, drawn_, id_of_, grid, std::max(1u, input_.context.threads), frame_);
    raster_ms_ += clock_.lap_ms();
  }

  void finish(StageTimings& timings) {
    stats_.polygons_culled = culled_;  // fragments: back faces, outside the frustum, hidden, clipped away
    timings.traverse_ms += walk_ms_;
    timings.shade_ms += shade_ms_;
    timings.raster_ms += raster_ms_;
  }

  size_t& culled() { return culled_; }

 private:
  // Clips, projects, prepares the shader and keeps the projection for drawing; false when nothing
  // is left to draw, or when `opaque` and every pixel it could write is written (a translucent one
  // still shows over those).
  bool project(uint32_t index, uint32_t position, bool opaque) {
    ++stats_.polygons_projected;
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
    shade_ms_ += clock_.lap_ms();
    ++stats_.polygons_drawn;
    stats_.triangles += scratch_.screen.size() - 2;
    drawn_.add(scratch_, {&soup_, &shader_}, {index, 0}, position, view_.width, view_.height);
    return true;
  }

  // Rasterizes the projected polygon for coverage only: its fragments claim the unwritten pixels.
  void claim(uint32_t position) {
    const PixelRect frame_rect{0, 0, frame_.image.width, frame_.image.height};
    const std::vector<RasterVertex>& v = scratch_.screen;
    for (size_t k = 0; k + 2 < v.size(); ++k) {
      TriangleSetup s;
      if (!setup_screen_triangle(v[0], v[k + 1], v[k + 2], s)) continue;
      if (coverage_.sampled()) {
        const double inv_w[3] = {v[0].inv_w, v[k + 1].inv_w, v[k + 2].inv_w};
        stats_.fragments += coverage_.claim_samples(s, inv_w);
        continue;
      }
      triangle_spans(s, frame_rect, [&](int y, int x, int n, const int64_t*) {
        stats_.fragments += size_t(n);
        coverage_.claim_span(y, x, n, position);
      });
    }
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
  ProjectedSet& drawn_;  // opaque polygons drawn, in walk order, then the translucent ones farthest first
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
  thread_local ProjectedSet drawn;  // kept for this thread's next frame
  FrontToBack walk(tree, input, frame, stats, drawn);
  walk_bsp(
      tree, input.view.eye, WalkOrder::front_to_back,
      [&](int32_t index, const BspNode& node) { return walk.enter(index, node); },
      [&](uint32_t index) { return walk.emit(index); }, walk.culled());
  walk.draw();
  walk.finish(timings);
  drawn.release_if_large();
}

}  // namespace rr

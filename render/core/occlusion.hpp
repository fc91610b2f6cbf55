// Occlusion culling: a hierarchical depth buffer (Greene's z-pyramid) over 8x8-pixel blocks, filled
// while the scene's hierarchy (hierarchy.hpp) is walked front to back, and the test that skips a
// node whose screen rectangle lies wholly behind it.
// Depth is 1/w (1 / view depth; larger is nearer), as in the pipelines. A block holds a lower bound
// on the final 1/w of every pixel and sub-sample in it: it is raised only by an opaque polygon the
// pipeline will draw that covers the whole block (its area, not only its pixel centres, so any
// sample pattern and any rasterization of the polygon's pieces is covered) with a margin beyond the
// rasterizer's vertex snapping, to that polygon's least 1/w over the block less the snapping's
// effect. A node is hidden when 1/w of its box's nearest corner, widened by occlusion_margin, is
// below every block its rectangle meets: nothing in it can win a pixel, nor tie with what does, so
// the drawn frame keeps its bytes (docs/culling.md gives the argument and its one assumption).
#pragma once

#include "render/core/camera.hpp"
#include "render/core/cells.hpp"
#include "render/core/hierarchy.hpp"
#include "render/core/raster.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace rr {

constexpr int occlusion_block = 8;  // pixels per pyramid block side at level 0

// The relative widening of a node's nearest 1/w before it is compared: it covers float rounding of
// the pipelines' depth (2^-24), interpolation in double, and the spread between coplanar polygons of
// one plane group (their planes agree within 1e-10 of the scene size), so a culled polygon is behind
// what every pixel shows by more than any of these.
constexpr double occlusion_margin = 1.0 / 4096.0;

class DepthPyramid {
 public:
  DepthPyramid() = default;
  DepthPyramid(int width, int height) { reset(width, height); }
  void reset(int width, int height);  // empty, for a frame of this size (keeps its memory)

  // Raises the blocks the projected convex polygon `screen` (pixels, 1/w per vertex, as
  // project_polygon makes them) wholly covers. Returns the number of blocks it raised.
  size_t add_polygon(std::span<const RasterVertex> screen);

  // Whether every pixel of [x0, x1) x [y0, y1) (clamped to the image) lies behind depth `inv_w`.
  bool hidden(int x0, int y0, int x1, int y1, double inv_w) const;
  // Whether no block meeting the rectangle lies behind depth `inv_w` (raised above it): then nothing
  // whose 1/w is at least `inv_w` can be hidden there. With inv_w = 0: nothing raised there yet.
  bool in_front(int x0, int y0, int x1, int y1, double inv_w) const;
  bool empty() const { return raised_ == 0; }
  // Brings the coarser levels up to date: after it, tests only read, so threads may share it.
  void finish() const { refresh(); }

  int blocks_x() const { return levels_.empty() ? 0 : levels_[0].w; }
  int blocks_y() const { return levels_.empty() ? 0 : levels_[0].h; }
  double block(int bx, int by) const { return levels_[0].min[size_t(by) * size_t(levels_[0].w) + size_t(bx)]; }

 private:
  struct Level {
    int w = 0, h = 0;
    std::vector<double> min, max;  // over the level-0 blocks below each entry
  };
  void raise(int bx, int by, double inv_w);
  // Greene's hierarchical walk over the level-0 blocks bx0..bx1 x by0..by1 (inclusive): from the
  // level where they span at most 2x2 entries down, asking `visit(level, entry, index)` of each
  // entry met; true as soon as it answers found, false once every entry was skipped.
  enum class Visit { skip, found, descend };
  template <class VisitEntry>
  bool find_entry(int bx0, int by0, int bx1, int by1, VisitEntry visit) const;
  // The coarser levels are refreshed over the blocks raised since the last refresh only when a test
  // reads them: most tests read a few level-0 blocks, and most polygons are drawn between tests.
  void refresh() const;
  int width_ = 0, height_ = 0;
  mutable std::vector<Level> levels_;
  size_t raised_ = 0;
  mutable int dirty_x0_ = 0, dirty_y0_ = 0, dirty_x1_ = -1, dirty_y1_ = -1;  // level-0 blocks, inclusive
};

// The screen rectangle (pixels, half-open, clamped) that holds every pixel and sample a polygon in
// the box can reach, and the box's largest 1/w; false when the box reaches the near plane or behind
// the eye (it cannot be tested, so it is kept).
struct ScreenBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double near_inv_w = 0.0;
  double far_inv_w = 0.0;  // the box's least 1/w
};
bool project_box(const ViewTransform& view, Vec3 lo, Vec3 hi, ScreenBox& out);

// The occlusion test of one box: true when everything in it lies behind the pyramid. `tested` says
// whether the test could be made (the pyramid holds something, and the box lies beyond the near
// plane). `eager`: see walk_occlusion.
bool box_occluded(const DepthPyramid& pyramid, const ViewTransform& view, Vec3 lo, Vec3 hi, int eager, bool& tested);

// One frame's occlusion walk over a hierarchy. In: the hierarchy of a soup, the soup the frame draws
// (`frame_of[h]` gives the frame polygon of hierarchy-soup polygon h, or no_frame_polygon; empty when
// they are the same soup), which of its polygons the pipeline would draw (`drawn`), the view.
// Out: per frame polygon, 1 when it may be visible; the pyramid for later tests; counters.
constexpr uint32_t no_frame_polygon = 0xFFFFFFFFu;
struct OcclusionResult {
  std::vector<uint8_t> shown;  // per frame polygon
  DepthPyramid pyramid;
  size_t nodes_tested = 0;         // hierarchy nodes tested against the pyramid
  size_t nodes_occluded = 0;       // of which hidden (their subtrees skipped)
  size_t occluders = 0;            // polygons drawn into the pyramid
  size_t nodes_outside_cells = 0;  // nodes skipped because no reached cell can show them
};
// Which frame polygons the pipeline draws, and which of those may raise the pyramid (opaque ones).
// With `cells`, nodes and polygons that no cell the portal walk reached can show are skipped first.
struct OcclusionCandidates {
  std::span<const uint8_t> drawn;     // per frame polygon: not a back face, object in view
  std::span<const uint8_t> occluder;  // per frame polygon: opaque (only read where drawn)
  const CellFilter* cells = nullptr;  // indexed by hierarchy node and hierarchy-soup polygon
};
// `eager` is for tests only: it widens the test the wrong way by that many margins (a mutation the
// identity tests must catch); 0 in every render.
// Fills `out` (its memory is kept, so a thread may reuse one for its next frame).
void walk_occlusion(const SceneHierarchy& hierarchy, const PolygonSoup& frame_soup, std::span<const uint32_t> frame_of,
                    const OcclusionCandidates& candidates, const ViewTransform& view, int eager, OcclusionResult& out);

}  // namespace rr

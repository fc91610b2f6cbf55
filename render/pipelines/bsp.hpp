// The bsp pipeline: a binary space partitioning tree of the static scene, built once per scene and
// set of BSP options (cached across requests in RenderContext::bsp_cache), walked back to front for
// each camera and drawn with no depth buffer, as in the classic algorithm (docs/bsp.md).
//
// Build: each node's splitter is the candidate with the lowest score
//   w1 * |front - back| + w2 * splits + w3 * coplanar          (options.bsp; lower is better)
// where candidates are every polygon of the node when it holds at most `max_candidates`, else that
// many polygons sampled evenly, and the counts come from at most kScoreSample polygons of the node,
// so choosing a splitter costs O(max_candidates * kScoreSample) however large the node. Vertices
// within epsilon (options.bsp.epsilon times the scene's bounding-box diagonal) of a plane count as
// on it; polygons on the splitter's plane stay in its node, polygons crossing it are split. When the
// best polygon leaves the whole sample on one side (a convex run), a free plane through the polygons'
// median may split the node instead; its node may hold no polygon (count == 0). Build and traversal
// use explicit stacks: chains of polygon splitters can still be deep.
#pragma once

#include "render/core/draw.hpp"  // is_back_facing
#include "render/core/frame.hpp"
#include "render/core/frustum.hpp"
#include "render/core/lru_cache.hpp"
#include "render/core/polygon_ops.hpp"

#include <string>
#include <utility>
#include <vector>

namespace rr {

constexpr size_t kScoreSample = 512;  // polygons classified to score one candidate

struct BspNode {
  Plane plane;
  uint32_t first = 0;  // polygons on the plane: BspTree::node_polygons[first, first + count)
  uint32_t count = 0;
  int32_t front = -1;  // child node indices, -1 when empty
  int32_t back = -1;
  Vec3 lo{0.0}, hi{0.0};  // bounds of every polygon in the subtree
};

struct BspTree {
  PolygonSoup fragments;       // the input polygons, split where splitters crossed them; ids kept
  std::vector<BspNode> nodes;  // nodes[0] is the root; empty for an empty scene
  std::vector<uint32_t> node_polygons;
  double epsilon = 0.0;  // the classification band in metres
  size_t depth = 0;
  size_t input_polygons = 0;
  size_t splits = 0;
  double build_ms = 0.0;

  size_t bytes() const;  // what the tree costs against the cache budget
};

// Builds the tree of `soup` (bsp_build.cpp) on up to `threads` threads; the tree is the same for
// any thread count. Throws RenderCancelled when `cancel` expires.
BspTree build_bsp(const PolygonSoup& soup, const BspOptions& options, const CancelToken* cancel = nullptr,
                  unsigned threads = 1);

// The cache key of a scene's tree: its scene id and every option that shapes the tree.
std::string bsp_cache_key(const std::string& scene_id, const BspOptions& options);

// Polygons held by the subtree rooted at node `root` (what skipping it saves).
size_t subtree_polygons(const BspTree& tree, int32_t root);

enum class WalkOrder { back_to_front, front_to_back };

// Walks the tree for the eye. enter(node_index, node) says whether to walk a subtree (false skips
// it); emit(polygon_index) gets each polygon that is not a back face of a closed solid (those are
// counted in `culled`) and returns false to stop the walk. front_to_back visits exactly the reverse
// of back_to_front's sequence (a node's own polygons too), so first-writer-wins drawing in one
// equals last-writer-wins drawing in the other.
template <class Enter, class Emit>
void walk_bsp(const BspTree& tree, Vec3 eye, WalkOrder order, Enter&& enter, Emit&& emit, size_t& culled) {
  if (tree.nodes.empty()) return;
  struct Step {
    int32_t node;
    bool emit;  // false: visit the subtree; true: emit the node's own polygons
  };
  const bool reversed = order == WalkOrder::front_to_back;
  std::vector<Step> stack{{0, false}};
  while (!stack.empty()) {
    const Step step = stack.back();
    stack.pop_back();
    const BspNode& node = tree.nodes[size_t(step.node)];
    if (step.emit) {
      for (uint32_t j = 0; j < node.count; ++j) {
        const uint32_t index = tree.node_polygons[node.first + (reversed ? node.count - 1 - j : j)];
        if (is_back_facing(tree.fragments.polygons[index], eye)) {
          ++culled;
        } else if (!emit(index)) {
          return;
        }
      }
      continue;
    }
    if (!enter(step.node, node)) continue;
    // Back to front, far side first: the eye in front of the plane sees the back subtree behind the
    // node's polygons, and those behind the front subtree. On the plane either order is right, and
    // the choice (>= 0) is the same both ways so that one walk is the other reversed.
    const bool eye_in_front = node.plane.distance(eye) >= 0.0;
    int32_t first = eye_in_front ? node.back : node.front;
    int32_t last = eye_in_front ? node.front : node.back;
    if (reversed) std::swap(first, last);
    if (last >= 0) stack.push_back({last, false});
    stack.push_back({step.node, true});
    if (first >= 0) stack.push_back({first, false});
  }
}

// The tree's polygons back to front for the camera: subtrees whose bounds lie outside the view
// frustum and back faces of closed solids are skipped (counted in `culled`). With `occlusion` (a
// frame that culls occlusion), so are subtrees behind its depth pyramid and pieces of polygons its
// walk found hidden (counted in `culled` too, and the tests in stats->nodes_tested).
std::vector<uint32_t> bsp_back_to_front(const BspTree& tree, const ViewTransform& view, size_t& culled,
                                        const FrameInput* occlusion = nullptr, RenderStats* stats = nullptr);

// Whether the frame's occlusion culling skips BSP node `node` (its box lies behind the frame's depth
// pyramid); counts the test in stats.nodes_tested. False when the frame does not cull occlusion.
bool bsp_node_occluded(const FrameInput& input, const BspNode& node, RenderStats& stats);

// Draws the tree front to back, each pixel by the first polygon that reaches it, skipping subtrees
// whose screen bounds are already covered and stopping when the screen is full; translucent
// polygons in front of the result are then blended back to front. The image and ids equal the
// back-to-front walk's (bsp_occlusion.cpp, docs/bsp.md "Occlusion").
void draw_bsp_front_to_back(const BspTree& tree, const FrameInput& input, Frame& frame, RenderStats& stats,
                            StageTimings& timings);

void draw_bsp(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings);

}  // namespace rr

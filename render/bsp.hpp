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
// on it; polygons on the splitter's plane stay in its node, polygons crossing it are split.
// Build and traversal use explicit stacks: a convex room makes a tree as deep as its polygon count.
#pragma once

#include "lru_cache.hpp"
#include "pipeline.hpp"
#include "polygon_ops.hpp"

#include <string>
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
  PolygonSoup fragments;  // the input polygons, split where splitters crossed them; ids kept
  std::vector<BspNode> nodes;  // nodes[0] is the root; empty for an empty scene
  std::vector<uint32_t> node_polygons;
  double epsilon = 0.0;  // the classification band in metres
  size_t depth = 0;
  size_t input_polygons = 0;
  size_t splits = 0;
  double build_ms = 0.0;

  size_t bytes() const;  // what the tree costs against the cache budget
};

// Builds the tree of `soup`. Throws RenderCancelled when `cancel` expires.
BspTree build_bsp(const PolygonSoup& soup, const BspOptions& options, const CancelToken* cancel = nullptr);

// The cache key of a scene's tree: its scene id and every option that shapes the tree.
std::string bsp_cache_key(const std::string& scene_id, const BspOptions& options);

// The tree's polygons back to front for the camera: subtrees whose bounds lie outside the view
// frustum and back faces of closed solids are skipped (counted in `culled`).
std::vector<uint32_t> bsp_back_to_front(const BspTree& tree, const ViewTransform& view, size_t& culled);

void draw_bsp(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings);

}  // namespace rr

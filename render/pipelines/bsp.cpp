// The bsp pipeline: cache key, walks and drawing (see bsp.hpp and docs/bsp.md; the build is in
// bsp_build.cpp).
#include "render/pipelines/bsp.hpp"

#include "render/core/draw.hpp"
#include "render/core/occlusion.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/ordered_draw.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rr {

size_t BspTree::bytes() const {
  return sizeof(BspTree) + fragments.positions.capacity() * sizeof(Vec3) +
         fragments.normals.capacity() * sizeof(glm::vec3) + fragments.polygons.capacity() * sizeof(Polygon) +
         fragments.materials.capacity() * sizeof(Material) + fragments.objects.capacity() * sizeof(SceneObject) +
         fragments.uv_maps.capacity() * sizeof(UvMap) + nodes.capacity() * sizeof(BspNode) +
         node_polygons.capacity() * sizeof(uint32_t);
}

std::string bsp_cache_key(const std::string& scene_id, const BspOptions& o) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "|bsp|%.17g|%.17g|%.17g|%.17g|%d", o.w1, o.w2, o.w3, o.epsilon,
                o.max_candidates);
  return scene_id + buffer;
}

size_t subtree_polygons(const BspTree& tree, int32_t root) {
  size_t count = 0;
  std::vector<int32_t> stack{root};
  while (!stack.empty()) {
    const BspNode& s = tree.nodes[size_t(stack.back())];
    stack.pop_back();
    count += s.count;
    for (int32_t c : {s.front, s.back}) {
      if (c >= 0) stack.push_back(c);
    }
  }
  return count;
}

bool bsp_node_occluded(const FrameInput& input, const BspNode& node, RenderStats& stats) {
  if (!input.occlusion) return false;
  bool tested = false;
  const bool hidden = box_occluded(*input.occlusion, input.view, node.lo, node.hi, input.context.cull_eager, tested);
  stats.nodes_tested += tested;
  return hidden;
}

std::vector<uint32_t> bsp_back_to_front(const BspTree& tree, const ViewTransform& view, size_t& culled,
                                        const FrameInput* occlusion, RenderStats* stats) {
  std::vector<uint32_t> order;
  const Frustum frustum(view);
  auto enter = [&](int32_t index, const BspNode& node) {
    const bool skip = frustum.outside(node.lo, node.hi) || (occlusion && bsp_node_occluded(*occlusion, node, *stats));
    if (!skip) return true;
    culled += subtree_polygons(tree, index);  // what the skip saves
    return false;
  };
  walk_bsp(
      tree, view.eye, WalkOrder::back_to_front, enter,
      [&](uint32_t index) {
        if (occlusion && !occlusion->id_may_show(tree.fragments.polygons[index].id)) {
          ++culled;
          return true;
        }
        order.push_back(index);
        return true;
      },
      culled);
  return order;
}

void draw_bsp(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings) {
  Stopwatch clock;
  std::shared_ptr<const BspTree> tree;
  auto build = [&] {
    auto built = std::make_shared<const BspTree>(
        build_bsp(input.soup, input.options.bsp, input.context.cancel, input.context.threads));
    return BspCache::Built{built, built->bytes()};
  };
  if (input.context.bsp_cache) {
    std::string id = input.context.scene_id;
    bool hit = false;
    tree = input.context.bsp_cache->get_or_build(bsp_cache_key(id, input.options.bsp), build, hit);
    stats.bsp_cache = hit ? "hit" : "miss";
  } else {
    tree = build().value;
    stats.bsp_cache = "miss";  // no cache to ask: a private tree for this frame
  }
  timings.build_ms += stats.bsp_cache == "hit" ? 0.0 : clock.lap_ms();
  clock.lap_ms();
  stats.bsp_nodes = tree->nodes.size();
  stats.bsp_depth = tree->depth;
  stats.bsp_input_polygons = tree->input_polygons;
  stats.bsp_fragments = tree->fragments.polygons.size();
  stats.bsp_splits = tree->splits;

  if (input.options.bsp.traversal == BspTraversal::front_to_back) {
    draw_bsp_front_to_back(*tree, input, frame, stats, timings);
    return;
  }
  size_t culled = 0;
  std::vector<uint32_t> order = bsp_back_to_front(*tree, input.view, culled, &input, &stats);
  timings.traverse_ms += clock.lap_ms();

  SurfaceShader shader(input, tree->fragments);
  for (uint32_t index : order) shader.prepare(index);
  timings.shade_ms += clock.lap_ms();

  const DrawSource source{&tree->fragments, &shader};
  stats.polygons_projected += order.size();
  std::vector<OrderedItem> items(order.size());
  for (size_t k = 0; k < order.size(); ++k) items[k] = {order[k], 0};
  // Kept by this thread for its next frame, so their memory is not allocated again.
  thread_local ProjectedSet projected;
  thread_local TileGrid grid;
  const unsigned threads = std::max(1u, input.context.threads);
  culled += project_in_order(input.view, {&source, 1}, items, threads, projected);
  stats.polygons_drawn += projected.polygons.size();
  stats.triangles += projected.triangles;
  bin_projected(projected, frame.image.width, frame.image.height, grid);
  check_cancel(input.context.cancel);
  stats.fragments += draw_last_wins(input, {&source, 1}, projected, grid, threads, frame);
  projected.release_if_large();
  stats.polygons_culled = culled;  // fragments: back faces, outside the frustum, clipped away
  timings.raster_ms += clock.lap_ms();
}

}  // namespace rr

// The bsp pipeline (see bsp.hpp and docs/bsp.md).
#include "render/pipelines/bsp.hpp"

#include "render/core/draw.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/ordered_draw.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rr {

namespace {

struct Work {
  int32_t node;
  std::vector<uint32_t> polygons;  // indices into the tree's fragments
  size_t depth;
};

// Evenly spaced picks of `want` out of `n` (all of them when n <= want): deterministic, and spread
// over the whole node rather than its first polygons, which tessellation groups by object.
template <class Fn>
void for_each_sample(size_t n, size_t want, Fn&& fn) {
  if (n <= want) {
    for (size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  for (size_t k = 0; k < want; ++k) fn(k * n / want);
}

// The build checks its token once per this many polygon classifications (a triangle's takes tens of
// nanoseconds, a split a few times that): well under a millisecond between checks even at the root
// of a 10^5-polygon soup, where one node's splitter choice alone is 10^4+ classifications.
constexpr size_t kClassificationsPerCheck = 16384;

// The splitter: the chosen polygon's index in `soup`.
uint32_t choose_splitter(const PolygonSoup& soup, const std::vector<uint32_t>& polygons,
                         const BspOptions& options, double epsilon, CancelMeter& meter) {
  double best_score = std::numeric_limits<double>::infinity();
  uint32_t best = polygons[0];
  for_each_sample(polygons.size(), size_t(options.max_candidates), [&](size_t c) {
    meter.add(std::min(polygons.size(), kScoreSample));
    const Plane plane = plane_of(soup.polygons[polygons[c]]);
    double front = 0, back = 0, splits = 0, coplanar = 0;
    for_each_sample(polygons.size(), kScoreSample, [&](size_t i) {
      switch (classify_polygon(soup.points(soup.polygons[polygons[i]]), plane, epsilon)) {
        case PlaneSide::front: ++front; break;
        case PlaneSide::back: ++back; break;
        case PlaneSide::on: ++coplanar; break;
        case PlaneSide::spanning: ++splits; break;
      }
    });
    double score = options.w1 * std::abs(front - back) + options.w2 * splits + options.w3 * coplanar;
    if (score < best_score) best_score = score, best = polygons[c];  // ties: the first candidate
  });
  return best;
}

void grow(Vec3& lo, Vec3& hi, Vec3 p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

double scene_epsilon(const PolygonSoup& soup, double fraction) {
  if (soup.positions.empty()) return 0.0;
  Vec3 lo = soup.positions[0], hi = lo;
  double magnitude = 0.0;
  for (const Vec3& p : soup.positions) {
    grow(lo, hi, p);
    magnitude = std::max({magnitude, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  // A fraction of the scene's size, but never below what doubles can resolve at its coordinates: a
  // room 1e6 m from the origin still classifies its own vertices as on their own planes.
  return std::max(fraction * glm::length(hi - lo), 64.0 * DBL_EPSILON * magnitude);
}

}  // namespace

size_t BspTree::bytes() const {
  return sizeof(BspTree) + fragments.positions.capacity() * sizeof(Vec3) +
         fragments.normals.capacity() * sizeof(glm::vec3) + fragments.polygons.capacity() * sizeof(Polygon) +
         fragments.materials.capacity() * sizeof(Material) + fragments.objects.capacity() * sizeof(SceneObject) +
         nodes.capacity() * sizeof(BspNode) + node_polygons.capacity() * sizeof(uint32_t);
}

BspTree build_bsp(const PolygonSoup& soup, const BspOptions& options, const CancelToken* cancel) {
  Stopwatch clock;
  BspTree tree;
  tree.input_polygons = soup.polygons.size();
  tree.epsilon = scene_epsilon(soup, options.epsilon);
  tree.fragments = make_fragment_soup(soup);
  tree.fragments.positions.reserve(soup.positions.size());
  tree.fragments.normals.reserve(soup.normals.size());
  tree.fragments.polygons.reserve(soup.polygons.size());
  CancelMeter meter(cancel, kClassificationsPerCheck);
  std::vector<uint32_t> all;
  all.reserve(soup.polygons.size());
  for (const Polygon& p : soup.polygons) {
    meter.add(1);
    all.push_back(append_polygon(tree.fragments, soup, p));
  }
  if (all.empty()) {
    tree.build_ms = clock.elapsed_ms();
    return tree;
  }

  PolygonSoup& frags = tree.fragments;
  std::vector<Work> stack;
  tree.nodes.emplace_back();
  stack.push_back({0, std::move(all), 1});
  while (!stack.empty()) {
    Work work = std::move(stack.back());
    stack.pop_back();
    tree.depth = std::max(tree.depth, work.depth);
    const uint32_t splitter = choose_splitter(frags, work.polygons, options, tree.epsilon, meter);
    const Plane plane = plane_of(frags.polygons[splitter]);
    const uint32_t group = frags.polygons[splitter].plane_group;
    std::vector<uint32_t> front, back;
    const uint32_t first = uint32_t(tree.node_polygons.size());
    for (uint32_t index : work.polygons) {
      meter.add(1);
      // The splitter's plane group stays in its node whatever the band, so that ties there are
      // decided by id (below), as the reference decides them.
      const bool same_plane = group != 0 && frags.polygons[index].plane_group == group;
      switch (same_plane ? PlaneSide::on : classify_polygon(frags.points(frags.polygons[index]), plane, tree.epsilon)) {
        case PlaneSide::on: tree.node_polygons.push_back(index); break;
        case PlaneSide::front: front.push_back(index); break;
        case PlaneSide::back: back.push_back(index); break;
        case PlaneSide::spanning: {
          meter.add(4);  // a split writes two new polygons
          SplitResult parts = split_polygon(frags, frags.polygons[index], plane, tree.epsilon, frags);
          ++tree.splits;
          if (parts.front >= 0) front.push_back(uint32_t(parts.front));
          if (parts.back >= 0) back.push_back(uint32_t(parts.back));
          break;
        }
      }
    }
    // The splitter's own polygon is on its plane by construction, so every node keeps at least one
    // polygon and the recursion always shrinks: it cannot loop on a polygon split by its own plane.
    BspNode& node = tree.nodes[size_t(work.node)];
    node.plane = plane;
    node.first = first;
    node.count = uint32_t(tree.node_polygons.size()) - first;
    if (node.count == 0) {
      // Only when the splitter's vertices are not within epsilon of its own stored plane (a
      // degenerate or non-planar input polygon): keep it here rather than lose it.
      tree.node_polygons.push_back(front.empty() ? back.back() : front.back());
      (front.empty() ? back : front).pop_back();
      tree.nodes[size_t(work.node)].count = 1;
    }
    // Drawn back to front, the last of a node's polygons wins an overlap: highest id first, so the
    // lowest id wins ties as in the reference (docs/accuracy.md, "Ties"); front to back the reverse.
    std::stable_sort(tree.node_polygons.begin() + first, tree.node_polygons.end(),
                     [&](uint32_t a, uint32_t b) { return frags.polygons[a].id > frags.polygons[b].id; });
    for (auto* side : {&back, &front}) {
      if (side->empty()) continue;
      int32_t child = int32_t(tree.nodes.size());
      tree.nodes.emplace_back();
      (side == &front ? tree.nodes[size_t(work.node)].front : tree.nodes[size_t(work.node)].back) = child;
      stack.push_back({child, std::move(*side), work.depth + 1});
    }
  }

  // Keep only the polygons the nodes hold (a split polygon's original is replaced by its parts), in
  // node order, so the tree's memory and its fragment count are what is drawn.
  PolygonSoup compact = make_fragment_soup(soup);
  compact.polygons.reserve(tree.node_polygons.size());
  for (uint32_t& index : tree.node_polygons) {
    meter.add(1);
    index = append_polygon(compact, frags, frags.polygons[index]);
  }
  tree.fragments = std::move(compact);
  // Splits leave T-junctions between a polygon's fragments; close them so the seams rasterize
  // without cracks (docs/accuracy.md, "Specks").
  close_t_junctions(tree.fragments, tree.epsilon, cancel);

  // Bounds bottom-up: children always have larger indices than their parent.
  for (size_t i = tree.nodes.size(); i-- > 0;) {
    BspNode& node = tree.nodes[i];
    meter.add(1 + node.count);
    node.lo = Vec3(std::numeric_limits<double>::infinity());
    node.hi = -node.lo;
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      const PolygonSoup& kept = tree.fragments;
      for (const Vec3& p : kept.points(kept.polygons[tree.node_polygons[k]])) grow(node.lo, node.hi, p);
    }
    for (int32_t child : {node.front, node.back}) {
      if (child < 0) continue;
      node.lo = glm::min(node.lo, tree.nodes[size_t(child)].lo);
      node.hi = glm::max(node.hi, tree.nodes[size_t(child)].hi);
    }
  }
  tree.build_ms = clock.elapsed_ms();
  return tree;
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

std::vector<uint32_t> bsp_back_to_front(const BspTree& tree, const ViewTransform& view, size_t& culled) {
  std::vector<uint32_t> order;
  const Frustum frustum(view);
  auto enter = [&](int32_t index, const BspNode& node) {
    if (!frustum.outside(node.lo, node.hi)) return true;
    culled += subtree_polygons(tree, index);  // what the skip saves
    return false;
  };
  walk_bsp(tree, view.eye, WalkOrder::back_to_front, enter, [&](uint32_t index) {
    order.push_back(index);
    return true;
  }, culled);
  return order;
}

void draw_bsp(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings) {
  Stopwatch clock;
  std::shared_ptr<const BspTree> tree;
  auto build = [&] {
    auto built = std::make_shared<const BspTree>(build_bsp(input.soup, input.options.bsp, input.context.cancel));
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
  std::vector<uint32_t> order = bsp_back_to_front(*tree, input.view, culled);
  timings.traverse_ms += clock.lap_ms();

  SurfaceShader shader(input, tree->fragments);
  for (uint32_t index : order) shader.prepare(index);
  timings.shade_ms += clock.lap_ms();

  const DrawSource source{&tree->fragments, &shader};
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

// Binned-SAH BVH build (see bvh.hpp). Work items sit on an explicit stack, so a degenerate input (all
// centroids equal, a million coplanar slivers) costs depth, never recursion: a node whose items
// cannot be separated by centroid, or that reaches max_bvh_depth, becomes a leaf.
#include "render/core/bvh.hpp"

#include <algorithm>

namespace rr {

namespace {

constexpr int bin_count = 16;
constexpr uint32_t leaf_size = 4;       // at most this many items before splitting is considered
constexpr double traversal_cost = 1.0;  // relative to one item test, in the SAH

constexpr uint32_t no_parent = ~0u;

struct BuildTask {
  uint32_t second_child_of;  // the parent when this is its second child, else no_parent
  uint32_t begin, end;       // range of `items`
  int depth;
};

struct Split {
  int axis = -1;
  int last_left_bin = 0;  // items in bins 0..last_left_bin go left
  double cost = std::numeric_limits<double>::infinity();
};

Vec3 centre(const Box& b) { return 0.5 * (b.lo + b.hi); }

// The best of bin_count - 1 planes per axis by surface area heuristic.
// The bin of an item's centroid along `axis` of the centroid box; the build partitions with this
// same function, so both sides of a chosen split are non-empty.
int bin_of(const Box& item, const Box& centroids, int axis) {
  const double lo = centroids.lo[axis], extent = centroids.hi[axis] - lo;
  return std::clamp(int(double(bin_count) * (centre(item)[axis] - lo) / extent), 0, bin_count - 1);
}

Split find_split(std::span<const Box> boxes, std::span<const uint32_t> items, const Box& centroids) {
  Split best;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(centroids.hi[axis] - centroids.lo[axis] > 0.0)) continue;
    std::array<Box, bin_count> bin_box;
    std::array<uint32_t, bin_count> bin_n{};
    for (uint32_t item : items) {
      const int b = bin_of(boxes[item], centroids, axis);
      bin_box[size_t(b)].grow(boxes[item]);
      ++bin_n[size_t(b)];
    }
    std::array<double, bin_count> right_cost{};
    Box acc;
    uint32_t n = 0;
    for (int b = bin_count - 1; b > 0; --b) {
      acc.grow(bin_box[size_t(b)]);
      n += bin_n[size_t(b)];
      right_cost[size_t(b)] = acc.half_area() * double(n);
    }
    acc = Box{};
    n = 0;
    for (int b = 0; b + 1 < bin_count; ++b) {
      acc.grow(bin_box[size_t(b)]);
      n += bin_n[size_t(b)];
      const double cost = acc.half_area() * double(n) + right_cost[size_t(b) + 1];
      if (n > 0 && n < items.size() && cost < best.cost) {
        best = {axis, b, cost};
      }
    }
  }
  return best;
}

}  // namespace

Box polygon_box(const PolygonSoup& soup, const Polygon& polygon) {
  Box b;
  for (const Vec3& p : soup.points(polygon)) b.grow(p);
  return b;
}

Bvh build_bvh(std::span<const Box> boxes) {
  Bvh bvh;
  for (uint32_t i = 0; i < boxes.size(); ++i) {
    if (!boxes[i].empty()) bvh.items.push_back(i);
  }
  if (bvh.items.empty()) return bvh;
  bvh.nodes.reserve(2 * bvh.items.size() / leaf_size + 1);
  // Depth first, left child first: a node is numbered when its task is taken, so a first child is
  // numbered right after its parent and the second child tells its parent its number.
  std::vector<BuildTask> stack{{no_parent, 0, uint32_t(bvh.items.size()), 0}};
  while (!stack.empty()) {
    const BuildTask task = stack.back();
    stack.pop_back();
    const uint32_t node = uint32_t(bvh.nodes.size());
    bvh.nodes.push_back({});
    if (task.second_child_of != no_parent) bvh.nodes[task.second_child_of].first = node;
    Box box, centroids;
    for (uint32_t i = task.begin; i < task.end; ++i) {
      box.grow(boxes[bvh.items[i]]);
      centroids.grow(centre(boxes[bvh.items[i]]));
    }
    bvh.nodes[node].box = box;
    const uint32_t n = task.end - task.begin;
    const std::span<uint32_t> range(bvh.items.data() + task.begin, n);
    Split split;
    if (n > leaf_size && task.depth < max_bvh_depth) split = find_split(boxes, range, centroids);
    // Leaf when no plane separates the centroids or splitting costs more than testing every item.
    const double area = box.half_area();
    if (split.axis < 0 || (area > 0.0 && split.cost / area + traversal_cost >= double(n))) {
      bvh.nodes[node].first = task.begin;
      bvh.nodes[node].count = n;
      continue;
    }
    auto middle = std::partition(range.begin(), range.end(), [&](uint32_t item) {
      return bin_of(boxes[item], centroids, split.axis) <= split.last_left_bin;
    });
    const uint32_t mid = task.begin + uint32_t(middle - range.begin());
    stack.push_back({node, mid, task.end, task.depth + 1});
    stack.push_back({no_parent, task.begin, mid, task.depth + 1});
  }
  return bvh;
}

Bvh build_polygon_bvh(const PolygonSoup& soup, std::span<const uint32_t> polygons) {
  std::vector<Box> boxes(polygons.size());
  for (size_t i = 0; i < polygons.size(); ++i) boxes[i] = polygon_box(soup, soup.polygons[polygons[i]]);
  Bvh bvh = build_bvh(boxes);
  for (uint32_t& item : bvh.items) item = polygons[item];
  return bvh;
}

}  // namespace rr

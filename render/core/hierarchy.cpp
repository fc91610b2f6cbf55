// Binned-SAH build of the pipelines' hierarchy (see hierarchy.hpp). Work items sit on an explicit
// stack, so a degenerate input (equal centroids, a million coplanar slivers) costs depth, never
// recursion; a range the heuristic cannot split is halved in polygon order, so leaves stay small.
#include "render/core/hierarchy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace rr {

namespace {

constexpr int bin_count = 16;
// A node test against one polygon's cost, in the SAH: a node's occlusion test projects a box and reads
// the pyramid, so leaves of a dozen polygons pay (on the homes: 60 % fewer node tests, 2 % more
// polygons projected than with a cost of 1).
constexpr double traversal_cost = 4.0;

struct Bounds {
  Vec3 lo{std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity()};
  void grow(Vec3 p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  void grow(const Bounds& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
  double half_area() const {
    if (!(lo.x <= hi.x)) return 0.0;
    const Vec3 e = hi - lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

struct Task {
  uint32_t parent;  // the node whose second child this is, or no_parent
  uint32_t begin, end;
};
constexpr uint32_t no_parent = std::numeric_limits<uint32_t>::max();

float down(double v) {
  float f = float(v);
  return double(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float up(double v) {
  float f = float(v);
  return double(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

struct Builder {
  std::vector<Bounds> boxes;  // per soup polygon
  std::vector<Vec3> centres;  // per soup polygon: its box's centre
  SceneHierarchy& out;

  // Splits [begin, end) of out.polygons at the returned position; end when it stays a leaf.
  uint32_t split(uint32_t begin, uint32_t end, const Bounds& box) {
    const uint32_t n = end - begin;
    if (n <= 2) return end;
    Bounds centroid;
    for (uint32_t i = begin; i < end; ++i) centroid.grow(centres[out.polygons[i]]);
    int best_axis = -1, best_bin = 0;
    double best_cost = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = centroid.lo[axis], extent = centroid.hi[axis] - lo;
      if (!(extent > 0.0)) continue;
      std::array<Bounds, bin_count> bin_box;
      std::array<uint32_t, bin_count> bin_n{};
      for (uint32_t i = begin; i < end; ++i) {
        const uint32_t p = out.polygons[i];
        const int b = std::clamp(int(bin_count * (centres[p][axis] - lo) / extent), 0, bin_count - 1);
        bin_box[size_t(b)].grow(boxes[p]);
        ++bin_n[size_t(b)];
      }
      std::array<double, bin_count> right{};
      Bounds acc;
      uint32_t count = 0;
      for (int b = bin_count - 1; b > 0; --b) {
        acc.grow(bin_box[size_t(b)]);
        count += bin_n[size_t(b)];
        right[size_t(b)] = acc.half_area() * double(count);
      }
      acc = Bounds{};
      count = 0;
      for (int b = 0; b + 1 < bin_count; ++b) {
        acc.grow(bin_box[size_t(b)]);
        count += bin_n[size_t(b)];
        const double cost = acc.half_area() * double(count) + right[size_t(b) + 1];
        if (count > 0 && count < n && cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
      }
    }
    const double area = box.half_area();
    const bool worth = best_axis >= 0 && (area <= 0.0 || traversal_cost + best_cost / area < double(n));
    if (!worth && n <= hierarchy_leaf_max) return end;
    if (best_axis < 0) return begin + n / 2;  // inseparable centroids: halve in polygon order
    const double lo = centroid.lo[best_axis], extent = centroid.hi[best_axis] - lo;
    auto* first = out.polygons.data() + begin;
    auto* middle = std::stable_partition(first, out.polygons.data() + end, [&](uint32_t p) {
      return std::clamp(int(bin_count * (centres[p][best_axis] - lo) / extent), 0, bin_count - 1) <= best_bin;
    });
    return uint32_t(middle - out.polygons.data());
  }
};

}  // namespace

size_t SceneHierarchy::bytes() const {
  return sizeof(SceneHierarchy) + nodes.capacity() * sizeof(HierarchyNode) + polygons.capacity() * sizeof(uint32_t) +
         spheres.capacity() * sizeof(PolygonSphere);
}

SceneHierarchy build_hierarchy(const PolygonSoup& soup, const CancelToken* cancel) {
  SceneHierarchy out;
  const size_t n = soup.polygons.size();
  Builder b{std::vector<Bounds>(n), std::vector<Vec3>(n), out};
  out.spheres.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto points = soup.points(soup.polygons[i]);
    for (const Vec3& p : points) b.boxes[i].grow(p);
    b.centres[i] = 0.5 * (b.boxes[i].lo + b.boxes[i].hi);
    double r2 = 0.0;
    for (const Vec3& p : points) r2 = std::max(r2, glm::dot(p - b.centres[i], p - b.centres[i]));
    const glm::vec3 c(b.centres[i]);
    // The float centre moved by up to half an ulp per axis: the radius grows by that distance.
    out.spheres[i] = {c, up(std::sqrt(r2) + glm::length(Vec3(c) - b.centres[i]))};
  }
  out.polygons.resize(n);
  for (uint32_t i = 0; i < n; ++i) out.polygons[i] = i;
  if (n == 0) return out;
  out.nodes.reserve(2 * n / 3 + 1);
  std::vector<Task> stack{{no_parent, 0, uint32_t(n)}};
  CancelMeter meter(cancel, size_t(1) << 16);  // units: polygons partitioned
  while (!stack.empty()) {
    const Task task = stack.back();
    meter.add(task.end - task.begin);
    stack.pop_back();
    const uint32_t index = uint32_t(out.nodes.size());
    if (task.parent != no_parent) out.nodes[task.parent].second = index;
    Bounds box;
    for (uint32_t i = task.begin; i < task.end; ++i) box.grow(b.boxes[out.polygons[i]]);
    HierarchyNode node;
    node.lo = {down(box.lo.x), down(box.lo.y), down(box.lo.z)};
    node.hi = {up(box.hi.x), up(box.hi.y), up(box.hi.z)};
    node.first = task.begin;
    node.count = task.end - task.begin;
    out.nodes.push_back(node);
    const uint32_t middle = b.split(task.begin, task.end, box);
    if (middle == task.end) continue;  // a leaf
    // The second child is pushed first, so the first child is numbered right after its parent.
    stack.push_back({index, middle, task.end});
    stack.push_back({no_parent, task.begin, middle});
  }
  return out;
}

}  // namespace rr

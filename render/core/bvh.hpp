// A bounding volume hierarchy over world-space boxes (one per polygon), for the reference ray
// caster. Built with binned SAH and an explicit work stack; traversed with an explicit stack, nearer
// child first. Item indices are the caller's (e.g. polygon indices); the tree only orders them.
// Invariant: every node's box holds the boxes of all items below it.
#pragma once

#include "render/core/math.hpp"
#include "render/core/tessellate.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace rr {

struct Box {
  Vec3 lo{std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity()};
  void grow(Vec3 p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  void grow(const Box& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
  bool empty() const { return !(lo.x <= hi.x); }
  double half_area() const {
    const Vec3 e = hi - lo;
    return empty() ? 0.0 : e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

Box polygon_box(const PolygonSoup& soup, const Polygon& polygon);

struct BvhNode {
  Box box;
  uint32_t first = 0;  // leaf: first entry in Bvh::items; inner: index of the second child
  uint32_t count = 0;  // leaf: number of items (> 0); inner: 0, first child at this index + 1
};

struct Bvh {
  std::vector<BvhNode> nodes;   // nodes[0] is the root (absent when there are no items)
  std::vector<uint32_t> items;  // caller's indices, grouped by leaf
};

// Builds a tree over `boxes` (items are their indices; empty boxes are left out).
Bvh build_bvh(std::span<const Box> boxes);
// The same over a subset of polygons of `soup`: items are the given polygon indices.
Bvh build_polygon_bvh(const PolygonSoup& soup, std::span<const uint32_t> polygons);

// A ray prepared for box tests.
struct BvhRay {
  Vec3 origin;
  Vec3 direction;
  Vec3 inv_direction;  // 1 / direction (infinite where a component is 0)
  BvhRay(Vec3 o, Vec3 d) : origin(o), direction(d), inv_direction(1.0 / d.x, 1.0 / d.y, 1.0 / d.z) {}
};

// Entry distance of the ray into `box` within [t_min, t_max], or +inf when it misses. The far
// distance is widened by a few ulps (Ize, "Robust BVH ray traversal") so that rounding never
// loses a box the ray grazes; extra boxes only cost time.
inline double ray_box_entry(const BvhRay& ray, const Box& box, double t_min, double t_max) {
  constexpr double widen = 8.0 * std::numeric_limits<double>::epsilon();
  double t0 = t_min, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] == 0.0) {  // parallel to the slabs: inside them or a miss
      if (ray.origin[a] < box.lo[a] || ray.origin[a] > box.hi[a]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double near = (box.lo[a] - ray.origin[a]) * ray.inv_direction[a];
    double far = (box.hi[a] - ray.origin[a]) * ray.inv_direction[a];
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far + std::abs(far) * widen);
  }
  return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

// Visits every item whose box the ray enters within [t_min, t_max]; nearer children first.
// visit(item, t_max) may lower t_max (closest-hit search) and returns true to stop (any-hit search).
template <class Visit>
void traverse_bvh(const Bvh& bvh, const BvhRay& ray, double t_min, double& t_max, Visit&& visit) {
  if (bvh.nodes.empty()) return;
  std::array<uint32_t, 128> stack;  // depth is bounded by the build (max_bvh_depth)
  size_t top = 0;
  if (ray_box_entry(ray, bvh.nodes[0].box, t_min, t_max) == std::numeric_limits<double>::infinity()) return;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = bvh.nodes[stack[--top]];
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (visit(bvh.items[i], t_max)) return;
      }
      continue;
    }
    const uint32_t a = uint32_t(&node - bvh.nodes.data()) + 1, b = node.first;
    const double ta = ray_box_entry(ray, bvh.nodes[a].box, t_min, t_max);
    const double tb = ray_box_entry(ray, bvh.nodes[b].box, t_min, t_max);
    constexpr double miss = std::numeric_limits<double>::infinity();
    // Push the farther child first so the nearer one is visited first.
    if (ta <= tb) {
      if (tb != miss) stack[top++] = b;
      if (ta != miss) stack[top++] = a;
    } else {
      if (ta != miss) stack[top++] = a;
      stack[top++] = b;
    }
  }
}

// The build stops splitting below this depth, so the traversal stack (2 entries per level) fits.
constexpr int max_bvh_depth = 60;

}  // namespace rr

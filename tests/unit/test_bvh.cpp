// BVH: the tree holds every item once, every node's box bounds what is below it, degenerate inputs
// terminate within the depth bound, and closest-hit and any-hit searches through the tree find
// exactly what a brute-force loop over every polygon finds (same polygon, bit-identical t), on
// seeded random soups. ROOMRENDER_TEST_SEED replays one seed.
#include "render/core/bvh.hpp"
#include "render/pipelines/reference.hpp"
#include "support/soup_builder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

namespace rr {
namespace {

bool box_contains(const Box& outer, const Box& inner) {
  return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z && outer.hi.x >= inner.hi.x &&
         outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

// Depth of the tree, checking containment on the way (explicit stack, like the build).
int check_tree(const Bvh& bvh, std::span<const Box> boxes) {
  int depth = 0;
  std::vector<std::pair<uint32_t, int>> stack{{0u, 1}};
  while (!stack.empty()) {
    auto [n, d] = stack.back();
    stack.pop_back();
    depth = std::max(depth, d);
    const BvhNode& node = bvh.nodes[n];
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        EXPECT_TRUE(box_contains(node.box, boxes[bvh.items[i]])) << "item " << bvh.items[i];
      }
      continue;
    }
    for (uint32_t child : {n + 1, node.first}) {
      EXPECT_TRUE(box_contains(node.box, bvh.nodes[child].box)) << "node " << child;
      stack.push_back({child, d + 1});
    }
  }
  return depth;
}

TEST(Bvh, HoldsEveryItemOnceAndBoundsItsChildren) {
  std::mt19937 rng(7);
  PolygonSoup soup = testing::random_triangle_soup(rng, 3000, 10.0);
  std::vector<Box> boxes;
  for (const Polygon& p : soup.polygons) boxes.push_back(polygon_box(soup, p));
  Bvh bvh = build_bvh(boxes);
  std::vector<uint32_t> items = bvh.items;
  std::sort(items.begin(), items.end());
  for (uint32_t i = 0; i < items.size(); ++i) ASSERT_EQ(items[i], i);
  ASSERT_EQ(items.size(), boxes.size());
  EXPECT_LE(check_tree(bvh, boxes), max_bvh_depth + 1);
  EXPECT_GT(bvh.nodes.size(), 100u);  // 3000 items at <= 4 per leaf need many nodes
}

TEST(Bvh, IdenticalBoxesBecomeOneLeafAndEmptyInputGivesNoNodes) {
  std::vector<Box> same(5000);
  for (Box& b : same) b.grow(Vec3(1, 2, 3)), b.grow(Vec3(2, 3, 4));
  Bvh bvh = build_bvh(same);
  ASSERT_EQ(bvh.nodes.size(), 1u);  // no centroid plane separates them: one leaf, no recursion
  EXPECT_EQ(bvh.nodes[0].count, 5000u);
  EXPECT_TRUE(build_bvh(std::vector<Box>{}).nodes.empty());
  EXPECT_TRUE(build_bvh(std::vector<Box>(3)).nodes.empty());  // empty boxes are left out
}

struct Closest {
  uint32_t polygon = ~0u;
  double t = std::numeric_limits<double>::infinity();
  // The nearer hit, ties to the lower index, so both searches agree whatever order they visit in.
  void offer(uint32_t i, double ti) {
    if (ti < t || (ti == t && i < polygon)) polygon = i, t = ti;
  }
};

TEST(Bvh, ClosestAndAnyHitEqualBruteForceOnRandomSoups) {
  const auto seeds = testing::test_seeds(20261201, 20);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    const PolygonSoup soup = testing::random_triangle_soup(rng, 400, 10.0);
    std::vector<uint32_t> all(soup.polygons.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    const Bvh bvh = build_polygon_bvh(soup, all);
    std::uniform_real_distribution<double> coord(-15.0, 15.0);
    size_t hits = 0;
    for (int r = 0; r < 500; ++r) {
      const Vec3 o(coord(rng), coord(rng), coord(rng));
      Vec3 d = Vec3(coord(rng), coord(rng), coord(rng)) - o;
      if (r % 10 == 0) d.y = 0.0;  // axis-parallel components exercise the slab special case
      Closest brute, tree;
      for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
        if (auto t = intersect_polygon(soup, soup.polygons[i], o, d, 0.0, 1e300)) brute.offer(i, *t);
      }
      double t_max = 1e300;
      traverse_bvh(bvh, BvhRay(o, d), 0.0, t_max, [&](uint32_t i, double& limit) {
        if (auto t = intersect_polygon(soup, soup.polygons[i], o, d, 0.0, 1e300)) {
          tree.offer(i, *t);
          limit = std::min(limit, tree.t);
        }
        return false;
      });
      ASSERT_EQ(tree.polygon, brute.polygon)
          << "seed " << seed << " (replay with ROOMRENDER_TEST_SEED=" << seed << "), ray " << r;
      ASSERT_EQ(tree.t, brute.t) << "seed " << seed << ", ray " << r;
      // Any-hit within the segment t < 1.
      bool any = false;
      double one = 1.0;
      traverse_bvh(bvh, BvhRay(o, d), 0.0, one, [&](uint32_t i, double&) {
        return any = intersect_polygon(soup, soup.polygons[i], o, d, 0.0, 1.0).has_value();
      });
      EXPECT_EQ(any, brute.t < 1.0) << "seed " << seed << ", ray " << r;
      hits += brute.polygon != ~0u;
    }
    EXPECT_GT(hits, 50u) << "seed " << seed << ": the rays should hit something often";
  }
}

}  // namespace
}  // namespace rr

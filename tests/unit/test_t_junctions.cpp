// close_t_junctions (polygon_ops.hpp), which the BSP build runs on its fragments: a vertex of a
// sibling fragment on an edge's interior is inserted into that edge, bit for bit and in order, and
// nothing else changes; and after a real BSP build no fragment has a sibling's vertex strictly
// inside one of its edges, the condition that left one-pixel cracks (tests/stress, seed 2011).
#include "render/core/polygon_ops.hpp"
#include "render/pipelines/bsp.hpp"
#include "support/soup_builder.hpp"

#include <gtest/gtest.h>

namespace rr {
namespace {

TEST(TJunctions, SiblingVertexOnAnEdgeIsInsertedInOrder) {
  // The square [0,2]x[0,1] (z = 0) as three fragments of polygon 7: L = [0,1]x[0,1], and the right
  // half split again into R1 = [1,2]x[0,0.5], R2 = [1,2]x[0.5,1]: (1, 0.5) is a T-junction on L's
  // right edge. A fourth polygon (id 8) touching the seam is not a sibling and stays as it is.
  PolygonSoup soup;
  testing::add_polygon(soup, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  testing::add_polygon(soup, {{1, 0, 0}, {2, 0, 0}, {2, 0.5, 0}, {1, 0.5, 0}});
  testing::add_polygon(soup, {{1, 0.5, 0}, {2, 0.5, 0}, {2, 1, 0}, {1, 1, 0}});
  testing::add_polygon(soup, {{1, 0.25, 1}, {1, 0.75, 1}, {1, 0.75, -1}});
  for (int i = 0; i < 3; ++i) soup.polygons[size_t(i)].id = 7;
  soup.polygons[3].id = 8;
  close_t_junctions(soup, 1e-9);
  ASSERT_EQ(soup.polygons.size(), 4u);
  const auto left = soup.points(soup.polygons[0]);
  ASSERT_EQ(left.size(), 5u);
  const std::vector<Vec3> expected = {{0, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {1, 1, 0}, {0, 1, 0}};
  for (size_t j = 0; j < 5; ++j) EXPECT_EQ(left[j], expected[j]) << j;
  EXPECT_EQ(soup.polygons[1].vertex_count, 4u);  // R1 and R2 hold every vertex of their edges
  EXPECT_EQ(soup.polygons[2].vertex_count, 4u);
  EXPECT_EQ(soup.polygons[3].vertex_count, 3u);
  EXPECT_EQ(soup.normals.size(), soup.positions.size());
}

TEST(TJunctions, BspFragmentsHaveNoSiblingVertexInsideAnEdge) {
  const auto seeds = testing::test_seeds(2011, 5);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    const PolygonSoup soup = testing::random_triangle_soup(rng, 60, 2.0);
    const BspTree tree = build_bsp(soup, BspOptions{});
    const PolygonSoup& f = tree.fragments;
    ASSERT_GT(tree.splits, 0u) << "seed " << seed;
    size_t t_junctions = 0;
    for (const Polygon& a : f.polygons) {
      const auto pa = f.points(a);
      for (const Polygon& b : f.polygons) {
        if (&a == &b || a.id != b.id) continue;
        for (const Vec3& v : f.points(b)) {
          for (size_t j = 0; j < pa.size(); ++j) {
            const Vec3 s = pa[j], e = pa[(j + 1) % pa.size()];
            const double t = glm::dot(v - s, e - s) / glm::dot(e - s, e - s);
            if (v == s || v == e || !(t > 0.0 && t < 1.0)) continue;
            t_junctions += glm::length(v - (s + t * (e - s))) <= 1e-12 * glm::length(e - s);
          }
        }
      }
    }
    EXPECT_EQ(t_junctions, 0u) << "seed " << seed << " (replay with ROOMRENDER_TEST_SEED=" << seed << ")";
  }
}

}  // namespace
}  // namespace rr

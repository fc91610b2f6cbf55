// The BSP build's own properties: the sampled scorer picks what the plain definition of bsp.hpp
// picks (every candidate classified with classify_polygon), the tree does not depend on the thread
// count, and rooms that are convex runs (split by free planes, nodes with no polygon) stay exact
// against the zbuffer for both walks on seeded random views.
#include "render/pipelines/bsp.hpp"
#include "render/pipelines/bsp_build.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>

namespace rr {
namespace {

using json = nlohmann::json;

// Random triangles and planar quads (parallelograms) in a 4 m box, a few of them in one plane so
// that candidates also count polygons on their plane.
PolygonSoup random_soup(std::mt19937& rng, size_t count) {
  std::uniform_real_distribution<double> u(-2.0, 2.0), small(-0.3, 0.3);
  json vertices = json::array(), faces = json::array();
  for (size_t f = 0; f < count; ++f) {
    const int base = int(vertices.size());
    const double ax = u(rng), ay = f % 7 == 0 ? 0.5 : u(rng), az = u(rng);
    const double ux = small(rng), uy = f % 7 == 0 ? 0.0 : small(rng), uz = small(rng);
    const double vx = small(rng), vy = f % 7 == 0 ? 0.0 : small(rng), vz = small(rng);
    vertices.push_back({ax, ay, az});
    vertices.push_back({ax + ux, ay + uy, az + uz});
    vertices.push_back({ax + ux + vx, ay + uy + vy, az + uz + vz});
    if (f % 3 == 0) {
      vertices.push_back({ax + vx, ay + vy, az + vz});
      faces.push_back({base, base + 1, base + 2, base + 3});
    } else {
      faces.push_back({base, base + 1, base + 2});
    }
  }
  json scene = {{"solids", json::array({{{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}}})}};
  json request = {{"scene", scene}, {"camera", {{"position", {0.0, 0.0, 5.0}}, {"target", {0.0, 0.0, 0.0}}}}};
  return tessellate(request_from_json(request).scene.geometry);
}

// The definition in bsp.hpp, written out plainly: evenly sampled candidates, each scored on evenly
// sampled polygons classified by classify_polygon; the lowest score wins, ties to the first.
uint32_t plain_best(const PolygonSoup& soup, const std::vector<uint32_t>& polygons, const BspOptions& o,
                    double epsilon) {
  auto pick = [](size_t n, size_t want, size_t k) { return n <= want ? k : k * n / want; };
  const size_t candidates = std::min(polygons.size(), size_t(o.max_candidates));
  const size_t sampled = std::min(polygons.size(), kScoreSample);
  double best_score = std::numeric_limits<double>::infinity();
  uint32_t best = polygons[0];
  for (size_t c = 0; c < candidates; ++c) {
    const uint32_t candidate = polygons[pick(polygons.size(), size_t(o.max_candidates), c)];
    double front = 0, back = 0, splits = 0, on = 0;
    for (size_t i = 0; i < sampled; ++i) {
      const Polygon& p = soup.polygons[polygons[pick(polygons.size(), kScoreSample, i)]];
      switch (classify_polygon(soup.points(p), plane_of(soup.polygons[candidate]), epsilon)) {
        case PlaneSide::front:
          ++front;
          break;
        case PlaneSide::back:
          ++back;
          break;
        case PlaneSide::on:
          ++on;
          break;
        case PlaneSide::spanning:
          ++splits;
          break;
      }
    }
    const double score = o.w1 * std::abs(front - back) + o.w2 * splits + o.w3 * on;
    if (score < best_score) best_score = score, best = candidate;
  }
  return best;
}

TEST(BspBuild, SampledScorerChoosesWhatThePlainDefinitionChooses) {
  BspOptions negative_w1;
  negative_w1.w1 = -0.5, negative_w1.w2 = 1.0, negative_w1.w3 = 2.0, negative_w1.max_candidates = 7;
  BspOptions negative_w2;
  negative_w2.w2 = -1.0, negative_w2.max_candidates = 50;
  for (uint32_t seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(seed);
    const size_t count = std::array<size_t, 4>{20, 150, 700, 3000}[seed % 4];
    const PolygonSoup soup = random_soup(rng, count);
    for (const BspOptions& options : {BspOptions{}, negative_w1, negative_w2}) {
      for (size_t stride : {size_t(1), size_t(3)}) {
        SCOPED_TRACE("seed " + std::to_string(seed) + ", stride " + std::to_string(stride) + ", w1 " +
                     std::to_string(options.w1));
        std::vector<uint32_t> polygons;
        for (uint32_t i = 0; i < soup.polygons.size(); i += uint32_t(stride)) polygons.push_back(i);
        for (double epsilon : {1e-7, 1e-3}) {
          bsp_detail::SplitterChooser chooser;
          bsp_detail::SplitCounts counts;
          CancelMeter meter(nullptr, 1 << 20);
          EXPECT_EQ(chooser.best_polygon(soup, polygons, options, epsilon, meter, counts),
                    plain_best(soup, polygons, options, epsilon));
        }
      }
    }
  }
}

bool same_tree(const BspTree& a, const BspTree& b) {
  if (a.nodes.size() != b.nodes.size() || a.node_polygons != b.node_polygons || a.depth != b.depth ||
      a.splits != b.splits || a.fragments.positions != b.fragments.positions ||
      a.fragments.normals != b.fragments.normals || a.fragments.polygons.size() != b.fragments.polygons.size()) {
    return false;
  }
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    const BspNode &x = a.nodes[i], &y = b.nodes[i];
    if (x.plane.normal != y.plane.normal || x.plane.offset != y.plane.offset || x.first != y.first ||
        x.count != y.count || x.front != y.front || x.back != y.back || x.lo != y.lo || x.hi != y.hi) {
      return false;
    }
  }
  for (size_t i = 0; i < a.fragments.polygons.size(); ++i) {
    const Polygon &p = a.fragments.polygons[i], &q = b.fragments.polygons[i];
    if (p.first_vertex != q.first_vertex || p.vertex_count != q.vertex_count || p.id != q.id) return false;
  }
  return true;
}

// Large enough for subtrees built as tasks of their own and for several id ranges of seams.
TEST(BspBuild, TreeIsTheSameForOneTwoAndEightThreads) {
  std::mt19937 rng(7);
  const PolygonSoup soup = random_soup(rng, 10000);
  const BspTree one = build_bsp(soup, BspOptions{}, nullptr, 1);
  EXPECT_GT(one.splits, 0u);
  for (unsigned threads : {2u, 8u}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    EXPECT_TRUE(same_tree(one, build_bsp(soup, BspOptions{}, nullptr, threads)));
  }
}

// A round room of `walls` walls (normals inward) with `clutter` random triangles inside.
json round_room(std::mt19937& rng, int walls, int clutter) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double radius = 4.0 + 2.0 * u(rng);
  json vertices = json::array(), faces = json::array();
  for (int i = 0; i < walls; ++i) {
    const double a = 2.0 * std::numbers::pi * i / walls;
    vertices.push_back({radius * std::cos(a), 0.0, radius * std::sin(a)});
    vertices.push_back({radius * std::cos(a), 3.0, radius * std::sin(a)});
  }
  for (int i = 0; i < walls; ++i) {
    const int j = (i + 1) % walls;
    faces.push_back({2 * i, 2 * i + 1, 2 * j + 1, 2 * j});
  }
  for (int t = 0; t < clutter; ++t) {
    const int base = int(vertices.size());
    const double cx = 0.5 * radius * u(rng), cy = 1.5 + u(rng), cz = 0.5 * radius * u(rng);
    for (int k = 0; k < 3; ++k) vertices.push_back({cx + 0.8 * u(rng), cy + 0.8 * u(rng), cz + 0.8 * u(rng)});
    faces.push_back({base, base + 1, base + 2});
  }
  const double eye_angle = std::numbers::pi * u(rng);
  return {{"scene", {{"solids", json::array({{{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}}})}}},
          {"camera",
           {{"position", {0.3 * radius * u(rng), 1.5 + 0.5 * u(rng), 0.3 * radius * u(rng)}},
            {"target", {radius * std::cos(eye_angle), 1.2, radius * std::sin(eye_angle)}}}},
          {"options", {{"width", 96}, {"height", 72}}}};
}

TEST(BspBuild, SeededRoundRoomsWithClutterMatchTheZbufferForBothWalks) {
  for (uint32_t seed = 1; seed <= 16; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    RenderRequest r = request_from_json(round_room(rng, 100 + int(seed) * 40, int(seed % 5) * 6));
    const PolygonSoup soup = tessellate(r.scene.geometry);
    const BspTree tree = build_bsp(soup, r.options.bsp);
    EXPECT_TRUE(std::any_of(tree.nodes.begin(), tree.nodes.end(), [](const BspNode& n) { return n.count == 0; }));
    RenderOptions options = r.options;
    options.pipeline = pipeline_id("zbuffer");
    const IdBuffer z = render_frame(r.scene, soup, r.camera, options).frame.ids;
    options.pipeline = pipeline_id("bsp");
    for (BspTraversal walk : {BspTraversal::front_to_back, BspTraversal::back_to_front}) {
      options.bsp.traversal = walk;
      testing::IdDiff d = testing::compare_ids(z, render_frame(r.scene, soup, r.camera, options).frame.ids, true);
      EXPECT_EQ(d.interior, 0u) << d.edge << " edge pixels differ";
    }
  }
}

}  // namespace
}  // namespace rr

// The BSP pipeline: exact visibility against the zbuffer pipeline (pixel by pixel away from id
// edges, see testing::is_edge_pixel), the cache of trees across requests and threads, numerical
// robustness far from the origin and at small scale, area conservation of the fragments, and convex
// rooms split by free planes.
#include "render/pipelines/bsp.hpp"
#include "render/pipelines/bsp_build.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/render_helpers.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <thread>

namespace rr {
namespace {

using json = nlohmann::json;

json example(const std::string& stem, int width = 320, int height = 240) {
  return testing::example_request(stem, width, height);
}

RenderResult render(const RenderRequest& r, const PolygonSoup& soup, PipelineId pipeline,
                    const RenderContext& context = {}) {
  RenderOptions options = r.options;
  options.pipeline = pipeline;
  return render_frame(r.scene, soup, r.camera, options, context);
}

double total_area(const PolygonSoup& soup) {
  double sum = 0.0;
  for (const Polygon& p : soup.polygons) sum += polygon_area(soup.points(p));
  return sum;
}

TEST(Bsp, EveryExampleMatchesTheZbufferAwayFromEdges) {
  for (const auto& file : testing::example_files()) {
    SCOPED_TRACE(file.stem().string());
    RenderRequest r = request_from_json(example(file.stem().string()));
    PolygonSoup soup = tessellate(r.scene.geometry);
    RenderResult z = render(r, soup, pipeline_id("zbuffer"));
    RenderResult b = render(r, soup, pipeline_id("bsp"));
    // Edges of either image: a fragment's cut edge snaps to the sub-pixel grid on its own, so a
    // pixel centre within ~1/400 pixel of a cut may flip (docs/bsp.md).
    testing::IdDiff d = testing::compare_ids(z.frame.ids, b.frame.ids, true);
    EXPECT_EQ(d.interior, 0u) << d.edge << " edge pixels differ";
  }
}

TEST(Bsp, IntersectingScenesAreSplitAndExact) {
  for (const char* stem : {"tri_intersecting", "cubes_45_pyramid_cylinder"}) {
    SCOPED_TRACE(stem);
    RenderRequest r = request_from_json(example(stem, 640, 480));
    PolygonSoup soup = tessellate(r.scene.geometry);
    RenderResult b = render(r, soup, pipeline_id("bsp"));
    EXPECT_GT(b.stats.bsp_splits, 0u);
    // Each split replaces one polygon by at most two (a sliver part of zero area is dropped).
    EXPECT_LE(b.stats.bsp_fragments, b.stats.bsp_input_polygons + b.stats.bsp_splits);
    EXPECT_GT(b.stats.bsp_fragments, b.stats.bsp_input_polygons);
    testing::IdDiff d = testing::compare_ids(render(r, soup, pipeline_id("zbuffer")).frame.ids, b.frame.ids, true);
    EXPECT_EQ(d.interior, 0u) << d.edge << " edge pixels differ";
    EXPECT_GT(b.stats.bsp_nodes, 0u);
    EXPECT_GE(b.stats.bsp_depth, 2u);
  }
}

TEST(Bsp, SecondCameraHitsTheCacheAndBuildsNothing) {
  BspCache cache(64u << 20);
  json first = example("apartment");
  first["options"]["pipeline"] = "bsp";
  json second = first;
  second["camera"]["position"] = {1.0, 6.0, 9.0};
  RenderContext context{&cache, nullptr, ""};
  rr::testing::TextRender a = rr::testing::render_text(first.dump(), context);
  rr::testing::TextRender b = rr::testing::render_text(second.dump(), context);
  EXPECT_EQ(a.result.stats.bsp_cache, "miss");
  EXPECT_GT(a.result.timings.build_ms, 0.0);
  EXPECT_EQ(b.result.stats.bsp_cache, "hit");
  EXPECT_EQ(b.result.timings.build_ms, 0.0);
  EXPECT_EQ(cache.stats().builds, 1u);
  EXPECT_EQ(cache.stats().hits, 1u);
  EXPECT_NE(a.png, b.png);  // a different view of the same tree
  // Other BSP options shape another tree: a miss again.
  second["options"]["bsp"] = {{"w2", 8}};
  EXPECT_EQ(rr::testing::render_text(second.dump(), context).result.stats.bsp_cache, "miss");
  EXPECT_EQ(cache.stats().builds, 2u);
}

TEST(Bsp, EightSimultaneousFirstRequestsBuildOnce) {
  BspCache cache(64u << 20);
  json request = example("four_cylinders");
  request["options"]["pipeline"] = "bsp";
  const std::string text = request.dump();
  std::vector<std::string> pngs(8);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < pngs.size(); ++t) {
    threads.emplace_back([&, t] { pngs[t] = rr::testing::render_text(text, RenderContext{&cache, nullptr, ""}).png; });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(cache.stats().builds, 1u);
  for (const std::string& png : pngs) EXPECT_EQ(png, pngs[0]);
}

// The same room far from the origin and a thousand times smaller: splits, classification and the
// raster front end must not lose what the default-sized room gets right.
TEST(Bsp, FarFromTheOriginAndSmallStaysExact) {
  const double scale = 1e-3, shift = 1e4;
  RenderRequest r = request_from_json(example("apartment"));
  PolygonSoup soup = tessellate(r.scene.geometry);
  const double area = total_area(soup);
  for (Vec3& p : soup.positions) p = p * scale + Vec3(shift);
  for (Polygon& p : soup.polygons) p.offset = p.offset * scale + glm::dot(p.normal, Vec3(shift));
  r.camera.position = r.camera.position * scale + Vec3(shift);
  r.camera.target = r.camera.target * scale + Vec3(shift);
  r.camera.near *= scale;
  r.camera.far *= scale;
  RenderResult z = render(r, soup, pipeline_id("zbuffer"));
  RenderResult b = render(r, soup, pipeline_id("bsp"));
  testing::IdDiff d = testing::compare_ids(z.frame.ids, b.frame.ids, true);
  EXPECT_EQ(d.interior, 0u) << d.edge << " edge pixels differ";

  BspTree tree = build_bsp(soup, r.options.bsp);
  EXPECT_GT(tree.splits, 0u);
  for (const Vec3& p : tree.fragments.positions)
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  const double fragment_area = total_area(tree.fragments) / (scale * scale);
  EXPECT_NEAR(fragment_area / area, 1.0, 1e-9) << fragment_area << " vs " << area;
}

TEST(Bsp, FragmentAreaEqualsInputAreaOnEveryExample) {
  for (const auto& file : testing::example_files()) {
    SCOPED_TRACE(file.stem().string());
    RenderRequest r = request_from_json(example(file.stem().string()));
    PolygonSoup soup = tessellate(r.scene.geometry);
    BspTree tree = build_bsp(soup, r.options.bsp);
    if (soup.polygons.empty()) continue;
    EXPECT_NEAR(total_area(tree.fragments) / total_area(soup), 1.0, 1e-9);
    EXPECT_EQ(tree.fragments.polygons.size(), tree.node_polygons.size());  // every fragment in one node
    for (const Polygon& p : tree.fragments.polygons) EXPECT_LT(p.id, soup.polygons.size());
  }
}

// A convex room seen from inside: every polygon is in front of every other, so polygon splitters
// could only peel one wall per node (a chain as deep as the room has walls, O(n^2) to build). Free
// planes through the walls' median halve it instead: a shallow tree, with nodes that hold no
// polygon, drawn exactly by both walks.
TEST(Bsp, ConvexRoomIsHalvedByFreePlanesIntoAShallowTree) {
  const int segments = 2500;
  json vertices = json::array(), faces = json::array();
  for (int i = 0; i < segments; ++i) {
    double a = 2.0 * std::numbers::pi * i / segments;
    vertices.push_back({10.0 * std::cos(a), 0.0, 10.0 * std::sin(a)});
    vertices.push_back({10.0 * std::cos(a), 3.0, 10.0 * std::sin(a)});
  }
  for (int i = 0; i < segments; ++i) {
    int j = (i + 1) % segments;  // counter-clockwise seen from inside: normals point inward
    faces.push_back({2 * i, 2 * i + 1, 2 * j + 1, 2 * j});
  }
  json request = {{"scene", {{"solids", json::array({{{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}}})}}},
                  {"camera", {{"position", {0.0, 1.5, 0.0}}, {"target", {5.0, 1.5, 1.0}}}},
                  {"options", {{"width", 160}, {"height", 120}}}};
  RenderRequest r = request_from_json(request);
  PolygonSoup soup = tessellate(r.scene.geometry);
  ASSERT_EQ(soup.polygons.size(), size_t(segments));
  BspTree tree = build_bsp(soup, r.options.bsp);
  // Halving down to chains of fewer than kFreeSplitMin walls: log2(2500 / 64) ~ 5 levels above them.
  EXPECT_LE(tree.depth, bsp_detail::kFreeSplitMin + 12);
  EXPECT_GT(tree.splits, 0u);  // each free plane cuts the walls it crosses
  EXPECT_LE(tree.splits, size_t(segments) / 10);
  EXPECT_TRUE(std::any_of(tree.nodes.begin(), tree.nodes.end(), [](const BspNode& n) { return n.count == 0; }));
  const IdBuffer z = render(r, soup, pipeline_id("zbuffer")).frame.ids;
  for (BspTraversal walk : {BspTraversal::front_to_back, BspTraversal::back_to_front}) {
    r.options.bsp.traversal = walk;
    testing::IdDiff d = testing::compare_ids(z, render(r, soup, pipeline_id("bsp")).frame.ids, true);
    EXPECT_EQ(d.interior, 0u) << d.edge << " edge pixels differ";
  }
}

TEST(Bsp, SeededRandomTrianglesMatchTheZbuffer) {
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    json vertices = json::array(), faces = json::array();
    for (int t = 0; t < 12; ++t) {
      for (int k = 0; k < 3; ++k) vertices.push_back({u(rng), u(rng) + 1.0, u(rng)});
      faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    }
    json request = {
        {"scene", {{"solids", json::array({{{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}}})}}},
        {"camera", {{"position", {2.5 * u(rng), 1.0 + u(rng), 3.0}}, {"target", {0.0, 1.0, 0.0}}}},
        {"options", {{"width", 96}, {"height", 72}}}};
    RenderRequest r = request_from_json(request);
    PolygonSoup soup = tessellate(r.scene.geometry);
    testing::IdDiff d = testing::compare_ids(render(r, soup, pipeline_id("zbuffer")).frame.ids,
                                             render(r, soup, pipeline_id("bsp")).frame.ids, true);
    EXPECT_EQ(d.interior, 0u) << d.edge << " edge pixels differ";
  }
}

TEST(Bsp, SubtreesOutsideTheViewAreSkipped) {
  RenderRequest r = request_from_json(example("rows"));
  PolygonSoup soup = tessellate(r.scene.geometry);
  BspTree tree = build_bsp(soup, r.options.bsp);
  size_t culled_wide = 0, culled_narrow = 0;
  ViewTransform wide = make_view(r.camera, 320, 240);
  Camera narrow_camera = r.camera;
  narrow_camera.fov_y_deg = 5.0;
  ViewTransform narrow = make_view(narrow_camera, 320, 240);
  size_t drawn_wide = bsp_back_to_front(tree, wide, culled_wide).size();
  size_t drawn_narrow = bsp_back_to_front(tree, narrow, culled_narrow).size();
  EXPECT_LT(drawn_narrow, drawn_wide);
  EXPECT_EQ(drawn_wide + culled_wide, tree.fragments.polygons.size());
  EXPECT_EQ(drawn_narrow + culled_narrow, tree.fragments.polygons.size());
}

}  // namespace
}  // namespace rr

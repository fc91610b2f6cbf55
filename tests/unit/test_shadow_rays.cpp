// The pipelines' shadow-ray tree (render/core/shadow_rays.hpp) against the brute-force search over
// every polygon: the same answer for every ray (and the same tint through the panes), since both end in the same exact
// polygon test and the tree's padded float boxes must never lose a polygon the ray meets. Seeded random rooms (the
// studio's walls, windows and door with random boxes and lights), rays from random points of random
// polygons, and axis-aligned rays whose slab products meet 0 x infinity. Then options.shadow.method
// rays through every raster pipeline against the reference's own shadow rays on the same rooms.
#include "render/core/error_metrics.hpp"
#include "render/core/shadow_rays.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/culling_cases.hpp"
#include "support/soup_builder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <random>

namespace rr {
namespace {

using nlohmann::json;

json random_room_request(std::mt19937& rng) {
  json request = json::parse(testing::read_file(testing::examples_dir() / "studio.json"));
  std::uniform_real_distribution<double> at(0.3, 5.7), size(0.1, 1.6), base(0.0, 1.5), height(0.3, 2.5);
  json solids = json::array();
  for (int i = 0, n = 4 + int(rng() % 12); i < n; ++i) {
    solids.push_back({{"type", "box"},
                      {"center", {at(rng), at(rng)}},
                      {"base", base(rng)},
                      {"size", {size(rng), size(rng), size(rng)}},
                      {"color", "#a08060"}});
  }
  request["scene"]["solids"] = solids;
  json lights = json::array();
  for (int i = 0; i < 3; ++i) lights.push_back({{"type", "point"}, {"position", {at(rng), height(rng), at(rng)}}});
  std::uniform_real_distribution<double> tilt(-1.0, 1.0);
  lights.push_back({{"type", "directional"}, {"direction", {tilt(rng), -1.0, tilt(rng)}}});
  lights.push_back({{"type", "directional"}, {"direction", {0.0, -1.0, 0.0}}});  // parallel to two slab pairs
  lights.push_back({{"type", "directional"}, {"direction", {1.0, 0.0, 0.0}}});
  request["scene"]["lights"] = lights;
  return request;
}

PreparedScene random_room(std::mt19937& rng) {
  return prepare_scene(request_from_json(random_room_request(rng)).scene);
}

Vec3 random_point_on(const PolygonSoup& soup, const Polygon& poly, std::mt19937& rng) {
  const auto points = soup.points(poly);
  const size_t k = rng() % (points.size() - 2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double a = u(rng), b = u(rng);
  if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
  return points[0] + a * (points[k + 1] - points[0]) + b * (points[k + 2] - points[0]);
}

// Calls fn(rng, prepared, bvh) for each seeded random room of the test's seeds (default: `count`
// from `first`), its shadow BVH built; a failure names the seed and how to replay it.
template <class Fn>
void for_each_random_room(unsigned first, unsigned count, Fn&& fn) {
  const auto seeds = testing::test_seeds(first, count);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " (replay with ROOMRENDER_TEST_SEED=" + std::to_string(seed) + ")");
    std::mt19937 rng(seed);
    const PreparedScene prepared = random_room(rng);
    const ShadowBvh bvh = build_shadow_bvh(prepared.soup, *prepared.hierarchy);
    fn(rng, prepared, bvh);
  }
}

// Where random ray i of a room starts: two rays in three from a random polygon's surface (the ray
// leaves that polygon out as `self`), the rest from anywhere in and around the room (self: none).
struct RayOrigin {
  uint32_t self;
  Vec3 p;
};
RayOrigin random_ray_origin(const PolygonSoup& soup, int i, std::mt19937& rng) {
  std::uniform_real_distribution<double> anywhere(-0.5, 6.5), up(-0.2, 3.0);
  const bool on_surface = i % 3 != 0;
  const uint32_t self = on_surface ? uint32_t(rng() % soup.polygons.size()) : 0xFFFFFFFFu;
  const Vec3 p =
      on_surface ? random_point_on(soup, soup.polygons[self], rng) : Vec3(anywhere(rng), up(rng), anywhere(rng));
  return {self, p};
}

TEST(ShadowRays, SameAnswerAsTheBruteForceSearchOnSeededRandomRooms) {
  size_t blocked = 0, open = 0;
  for_each_random_room(3101, 12, [&](std::mt19937& rng, const PreparedScene& prepared, const ShadowBvh& bvh) {
    const PolygonSoup& soup = prepared.soup;
    ASSERT_FALSE(bvh.nodes.empty());
    EXPECT_EQ(bvh.ray_epsilon, shadow_ray_epsilon(soup));
    for (int i = 0; i < 3000; ++i) {
      const auto [self, p] = random_ray_origin(soup, i, rng);
      for (const Light& light : prepared.scene.lights) {
        const bool fast = shadow_ray_blocked(bvh, self, p, light);
        ASSERT_EQ(fast, shadow_ray_blocked_brute_force(soup, bvh.ray_epsilon, self, p, light))
            << "ray " << i << " from " << p.x << "," << p.y << "," << p.z;
        (fast ? blocked : open)++;
      }
    }
  });
  EXPECT_GT(blocked, 10000u);  // both answers are common: the comparison means something
  EXPECT_GT(open, 10000u);
}

// The panes' tree tints a ray as the brute-force search over every translucent polygon does: the
// same panes crossed, so the same product (to the rounding of its order).
TEST(ShadowRays, PanesTintAsTheBruteForceSearchOnSeededRandomRooms) {
  size_t tinted = 0, clear = 0;
  for_each_random_room(3121, 8, [&](std::mt19937& rng, const PreparedScene& prepared, const ShadowBvh& bvh) {
    const PolygonSoup& soup = prepared.soup;
    ASSERT_FALSE(bvh.glass.nodes.empty());
    for (int i = 0; i < 3000; ++i) {
      const auto [self, p] = random_ray_origin(soup, i, rng);
      for (const Light& light : prepared.scene.lights) {
        const Color fast = shadow_ray_transmittance(bvh, soup, self, p, light);
        const Color slow = shadow_ray_transmittance_brute_force(soup, bvh.ray_epsilon, self, p, light);
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(fast[c], slow[c], 1e-6f) << "ray " << i << " from " << p.x << "," << p.y << "," << p.z;
        }
        (fast == Color(1.0f) ? clear : tinted)++;
      }
    }
  });
  EXPECT_GT(tinted, 1000u);  // rays through the windows and rays past them are both common
  EXPECT_GT(clear, 10000u);
}

// The memo (the last blocker tried first) changes the work, never an answer: with one memo per light
// kept across every ray of a room, each answer is the brute-force search's, also for a ray that
// starts on the memo's own polygon (which it must leave out, as the walk does).
TEST(ShadowRays, MemoOfTheLastBlockerGivesTheBruteForceAnswers) {
  ShadowRayStats stats;
  size_t from_memo_polygon = 0;
  for_each_random_room(3111, 8, [&](std::mt19937& rng, const PreparedScene& prepared, const ShadowBvh& bvh) {
    const PolygonSoup& soup = prepared.soup;
    std::vector<ShadowRayMemo> memos(prepared.scene.lights.size());
    for (int i = 0; i < 2000; ++i) {
      const uint32_t self = uint32_t(rng() % soup.polygons.size());
      const Vec3 p = random_point_on(soup, soup.polygons[self], rng);
      for (size_t l = 0; l < memos.size(); ++l) {
        const Light& light = prepared.scene.lights[l];
        ASSERT_EQ(shadow_ray_blocked(bvh, self, p, light, &memos[l], &stats),
                  shadow_ray_blocked_brute_force(soup, bvh.ray_epsilon, self, p, light))
            << "ray " << i << " light " << l;
        if (memos[l].blocker == UINT32_MAX) continue;
        // A ray from the memo's own polygon: the memo must not block it.
        const Polygon& own = soup.polygons[memos[l].blocker];
        const Vec3 q = random_point_on(soup, own, rng);
        ASSERT_EQ(shadow_ray_blocked(bvh, own.id, q, light, &memos[l], &stats),
                  shadow_ray_blocked_brute_force(soup, bvh.ray_epsilon, own.id, q, light))
            << "ray " << i << " from the memo's polygon, light " << l;
        ++from_memo_polygon;
      }
    }
  });
  // Random points are far less coherent than a frame's pixels, yet the memo answers many rays (so the
  // comparison means something) and the walk still finds other blockers.
  EXPECT_GT(stats.memo_hits, stats.rays / 20);  // about one ray in ten with the default seeds
  EXPECT_LT(stats.memo_hits, stats.blocked);
  EXPECT_GT(from_memo_polygon, 1000u);
}

TEST(ShadowRays, TranslucentPanesCastNothingButTintAndAnEmptySoupNothingAtAll) {
  const PreparedScene empty = prepare_scene(Scene{});
  const ShadowBvh none = build_shadow_bvh(empty.soup, *empty.hierarchy);
  EXPECT_TRUE(none.nodes.empty());
  EXPECT_TRUE(none.glass.nodes.empty());
  Light sun;
  sun.type = LightType::directional;
  sun.direction = Vec3(0.0, -1.0, 0.0);
  EXPECT_FALSE(shadow_ray_blocked(none, 0, Vec3(0.0), sun));
  // The studio's windows are translucent: none of them is an item of the tree.
  const PreparedScene studio =
      prepare_scene(request_from_json(json::parse(testing::read_file(testing::examples_dir() / "studio.json"))).scene);
  const ShadowBvh bvh = build_shadow_bvh(studio.soup, *studio.hierarchy);
  size_t translucent = 0;
  for (const Polygon& p : studio.soup.polygons) translucent += (p.flags & polygon_translucent) != 0;
  ASSERT_GT(translucent, 0u);
  EXPECT_EQ(bvh.items.size(), studio.soup.polygons.size() - translucent);
  for (uint32_t j : bvh.items) EXPECT_FALSE(studio.soup.polygons[j].flags & polygon_translucent);
  // They are the panes' tree's items, every one of them.
  EXPECT_EQ(bvh.glass.items.size(), translucent);
  for (uint32_t j : bvh.glass.items) EXPECT_TRUE(studio.soup.polygons[j].flags & polygon_translucent);
  EXPECT_GT(bvh.bytes(), bvh.items.size() * sizeof(uint32_t));
  // The prepared scene holds the same tree (built once, shared by every view of it).
  ASSERT_TRUE(studio.shadow_bvh);
  EXPECT_EQ(studio.shadow_bvh->items, bvh.items);
  EXPECT_EQ(studio.shadow_bvh->leaf_begin, bvh.leaf_begin);
  EXPECT_EQ(studio.shadow_bvh->nodes.size(), bvh.nodes.size());
  EXPECT_EQ(studio.shadow_bvh->ray_epsilon, bvh.ray_epsilon);
}

// Pixels away from the reference's id edges and from the 2-pixel band around its shadow edges, showing
// the reference's polygon, whose colour differs from the reference's by more than 2 levels in a
// channel (the Phong of floats and a specular table against doubles stays well within that).
size_t pixels_off_the_reference(const Frame& truth, const Frame& test, int width, int height) {
  std::vector<uint8_t> near_edge(size_t(width * height), 0);
  const auto& m = truth.shadow_mask;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y * width + x);
      const bool edge = (x > 0 && m[i - 1] != m[i]) || (x + 1 < width && m[i + 1] != m[i]) ||
                        (y > 0 && m[i - size_t(width)] != m[i]) || (y + 1 < height && m[i + size_t(width)] != m[i]);
      if (!edge) continue;
      for (int v = std::max(0, y - shadow_edge_band); v <= std::min(height - 1, y + shadow_edge_band); ++v) {
        for (int u = std::max(0, x - shadow_edge_band); u <= std::min(width - 1, x + shadow_edge_band); ++u)
          near_edge[size_t(v * width + u)] = 1;
      }
    }
  }
  size_t off = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y * width + x);
      if (near_edge[i] || is_edge_pixel(truth.ids, x, y) || truth.ids.ids[i] != test.ids.ids[i]) continue;
      for (size_t c = 0; c < 3; ++c)
        off += std::abs(int(truth.image.rgb[3 * i + c]) - int(test.image.rgb[3 * i + c])) > 2;
    }
  }
  return off;
}

// Every raster pipeline with options.shadow.method rays (and the z-buffer's A-buffer) decides each
// visible point's light exactly as the reference's shadow rays: its light mask is the reference's at
// every pixel away from the 2-pixel band around the reference's shadow edges (where the rasterized
// point and the reference's hit differ by rounding and an exact decision may flip). Pixels where
// another polygon is visible (a visibility difference, measured elsewhere) are not compared. The
// cameras look over the room from its corners, in Phong and flat shading.
TEST(ShadowRays, RaysMethodDecidesAsTheReferenceAwayFromShadowEdgesOnSeededRandomRooms) {
  const auto seeds = testing::test_seeds(3131, 6);
  constexpr int width = 160, height = 120;
  size_t compared = 0, lit = 0, unlit = 0;
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " (replay with ROOMRENDER_TEST_SEED=" + std::to_string(seed) + ")");
    std::mt19937 rng(seed);
    json request = random_room_request(rng);
    const double corner = seed % 2 ? 0.4 : 5.6;
    request["camera"] = {{"position", {corner, 2.4, 6.0 - corner}}, {"target", {3.0, 0.6, 3.0}}, {"fov_y", 70}};
    request["options"] = {{"width", width}, {"height", height}, {"shadows", true}, {"shading", "phong"}};
    request["options"]["shadow"]["method"] = "rays";
    const PreparedScene prepared = prepare_scene(request_from_json(request).scene);
    RenderContext context;
    context.shadow_mask = true;
    context.shadow_bvh = prepared.shadow_bvh.get();
    context.shadow_bvh_soup = &prepared.soup;
    auto draw = [&](const json& r) {
      const RenderRequest q = request_from_json(r);
      return render_frame(q.scene, prepared.soup, q.camera, q.options, context);
    };
    json reference = request;
    reference["options"]["pipeline"] = "reference";
    const RenderResult truth = draw(reference);
    ASSERT_EQ(truth.frame.shadow_mask_bytes, 1u);
    for (const PipelineInfo& pipeline : pipeline_table()) {
      if (pipeline.reference) continue;
      for (const char* shading : {"phong", "flat"}) {
        for (int antialias : {1, 4}) {
          if (antialias > 1 && (pipeline.name != std::string("zbuffer") || shading != std::string("phong"))) continue;
          SCOPED_TRACE(std::string(pipeline.name) + " " + shading + " antialias " + std::to_string(antialias));
          json r = request;
          r["options"]["pipeline"] = pipeline.name;
          r["options"]["shading"] = shading;
          r["options"]["antialias"] = antialias;
          const RenderResult test = draw(r);
          EXPECT_FALSE(test.stats.shadow_skipped);
          EXPECT_EQ(test.timings.shadow_ms, 0.0) << "the prepared scene's tree is used, not a private one";
          std::vector<uint8_t> mask = test.frame.shadow_mask;
          ASSERT_EQ(mask.size(), truth.frame.shadow_mask.size());
          for (size_t i = 0; i < mask.size(); ++i) {
            if (test.frame.ids.ids[i] != truth.frame.ids.ids[i]) mask[i] = truth.frame.shadow_mask[i];
          }
          const ShadowError e = shadow_error(truth.frame.shadow_mask, mask, 1, width);
          ASSERT_TRUE(e.split);
          EXPECT_EQ(e.away_differing, 0u) << "of " << e.away_pixels << " pixels away from shadow edges";
          EXPECT_GT(e.away_pixels, size_t(width * height / 2));
          compared += e.away_pixels;
          // The mask is written per fragment; the colours of the span path take their own rays. In
          // Phong they are the reference's colours to within the float shading's rounding wherever
          // the decisions agree, while one wrong decision moves a pixel by a light's whole term.
          if (shading == std::string("phong") && antialias == 1) {
            EXPECT_EQ(pixels_off_the_reference(truth.frame, test.frame, width, height), 0u);
          }
        }
      }
    }
    for (uint8_t m : truth.frame.shadow_mask) lit += m != 0, unlit += m != 0x3F;
  }
  EXPECT_GT(lit, 5000u);  // pixels some light reaches and pixels some light does not are both common
  EXPECT_GT(unlit, 5000u);
  EXPECT_GT(compared, 100000u);
}

// A lamp's fixture map closes only directions whose rays are blocked: on the homes' lamps (pendant
// shades, wall uplights' cups, work lamps' shades: the polygons of the objects whose bounds hold each
// lamp), every seeded random point the map says is closed has its shadow ray blocked by the tree
// (itself checked against the brute-force search above), and the maps close a good share of the
// points around each uplight.
TEST(ShadowRays, FixtureMapsCloseOnlyDirectionsWhoseRaysAreBlocked) {
  const std::vector<testing::CullingScene> homes =
      testing::culling_scenes("homes", testing::source_dir(), testing::shared_data_dir(), {"3BedroomApartment"});
  if (homes.empty()) GTEST_SKIP() << "no homes (../shared/data absent)";
  const PreparedScene prepared = prepare_scene(homes[0].request.scene);
  const PolygonSoup& soup = prepared.soup;
  ASSERT_TRUE(prepared.shadow_bvh);
  const auto seeds = testing::test_seeds(3737, 1);
  SCOPED_TRACE("seed " + std::to_string(seeds.first) +
               " (replay with ROOMRENDER_TEST_SEED=" + std::to_string(seeds.first) + ")");
  std::mt19937 rng(seeds.first);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> distance(0.0, 3.0);
  size_t maps = 0, closed = 0, tested = 0;
  for (const Light& light : prepared.scene.lights) {
    if (light.type != LightType::point) continue;
    std::vector<uint32_t> fixture;
    for (uint32_t j = 0; j < soup.polygons.size(); ++j) {
      const SceneObject& o = soup.objects[soup.polygons[j].object];
      if (o.bounded && glm::all(glm::lessThan(o.lo, light.position)) && glm::all(glm::lessThan(light.position, o.hi)))
        fixture.push_back(j);
    }
    const FixtureMap map = fixture_map(soup, fixture, light, 2e-6, 64);
    if (map.n == 0) continue;
    ++maps;
    for (int k = 0; k < 4000; ++k) {
      const Vec3 p = light.position + distance(rng) * glm::normalize(Vec3(gauss(rng), gauss(rng), gauss(rng)));
      ++tested;
      if (!map.closes(p)) continue;
      ++closed;
      ASSERT_TRUE(shadow_ray_blocked(*prepared.shadow_bvh, UINT32_MAX, p, light))
          << "a closed direction let a ray through: light at " << light.position.x << ", " << light.position.y << ", "
          << light.position.z << ", point " << p.x << ", " << p.y << ", " << p.z;
    }
  }
  EXPECT_GE(maps, 10u) << "the apartment's lamps hang in fixtures";
  EXPECT_GT(closed, tested / 5) << closed << " of " << tested << " points closed";
}

}  // namespace
}  // namespace rr

// Occlusion culling (render/core/occlusion.hpp, docs/culling.md): the depth pyramid's bounds hold for
// the rasterizer; options.culling on and off give byte-identical images and id buffers for every
// pipeline whose row uses it, on the examples, homes imported with their furniture models, R2V plans
// and the fireplace room, from their own and seeded cameras, flat and Phong with shadow maps and with
// shadow rays (where culling also skips lamps that see no cell the view reaches), at 1 and 4 samples, with the portal
// walk of the scene's cells (render/core/cells.hpp) and without; a test made one margin too eager is caught, and so is
// one portal dropped; the counters do not depend on the thread count. The seed is printed; ROOMRENDER_CULLING_SEED
// replays another. bench/culling.cpp runs the full matrix.
#include "render/core/cells.hpp"
#include "render/core/draw.hpp"
#include "render/core/occlusion.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/pipelines/render.hpp"
#include "render/pipelines/shadow_cache.hpp"
#include "support/culling_cases.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <random>

namespace rr {
namespace {

using testing::CullingScene;
using testing::SeededCamera;

uint64_t culling_seed() {
  const char* text = std::getenv("ROOMRENDER_CULLING_SEED");
  const uint64_t seed = text ? std::strtoull(text, nullptr, 10) : 20291;
  std::cout << "culling seed " << seed << " (ROOMRENDER_CULLING_SEED=" << seed << " replays it)\n";
  return seed;
}

// One view drawn with culling off and on (`eager` margins too eager): where they differ, or "".
struct Matrix {
  BspCache bsp_cache{size_t(2) << 30};
  ShadowCache shadow_cache{size_t(1) << 30};  // its key ignores the pipeline and culling: shared by all
  int width = 320, height = 180;
  size_t compared = 0;
  size_t cells_skipped = 0;          // pairs whose frame with culling on skipped cells the portal walk did not reach
  size_t lamps_culled = 0;           // lamps skipped by the frames with culling on (shadow rays)
  size_t lamps_blocked = 0;          // (shown polygon, kept lamp) pairs those frames left unlit
  uint32_t drop_portal = no_object;  // the portal walk ignores this portal with culling on (a mutation)
  bool flat_shadows = false;         // flat frames cast shadows too (Phong frames always do)

  RenderOutcome draw(const RenderRequest& base, const PreparedScene& scene, const Camera& camera, PipelineId pipeline,
                     int antialias, bool phong, CullingMode culling, int eager, unsigned threads = 2,
                     ShadowMethod method = ShadowMethod::map) {
    RenderRequest r = base;
    r.camera = camera;
    r.options.width = width, r.options.height = height;
    r.options.pipeline = pipeline;
    r.options.antialias = antialias;
    r.options.shading = phong ? ShadingMode::phong : ShadingMode::flat;
    r.options.shadows = phong || flat_shadows;
    r.options.shadow.method = method;
    r.options.culling = culling;
    RenderContext context;
    context.encode = false;
    context.threads = threads;
    context.bsp_cache = &bsp_cache;
    context.shadow_cache = &shadow_cache;
    context.cull_eager = eager;
    if (culling == CullingMode::on) context.drop_portal = drop_portal;
    return render(r, scene, context);
  }

  // Every culling pipeline at 1 and 4 samples, flat, Phong with shadow maps and Phong with shadow
  // rays; the first difference.
  std::string compare(const CullingScene& s, const PreparedScene& scene, const SeededCamera& cam, int eager) {
    for (const PipelineInfo& row : pipeline_table()) {
      if (!row.occlusion_culling) continue;
      for (int antialias : {1, 4}) {
        for (int lit : {0, 1, 2}) {
          const PipelineId p = pipeline_id(row);
          const bool phong = lit > 0;
          const ShadowMethod method = lit == 2 ? ShadowMethod::rays : ShadowMethod::map;
          const RenderOutcome off =
              draw(s.request, scene, cam.camera, p, antialias, phong, CullingMode::off, 0, 2, method);
          const RenderOutcome on =
              draw(s.request, scene, cam.camera, p, antialias, phong, CullingMode::on, eager, 2, method);
          ++compared;
          if (on.report.stats.cells_visited < on.report.stats.cells) ++cells_skipped;
          lamps_culled += on.report.stats.lamps_culled;
          lamps_blocked += on.report.stats.lamps_blocked;
          EXPECT_EQ(off.report.stats.lamps_culled, 0u) << "culling off skips no lamp";
          EXPECT_EQ(off.report.stats.lamps_blocked, 0u) << "culling off leaves no polygon unlit";
          if (lit != 2) {
            EXPECT_EQ(on.report.stats.lamps_culled, 0u) << "only shadow rays skip lamps";
            EXPECT_EQ(on.report.stats.lamps_blocked, 0u) << "only shadow rays leave polygons unlit";
          }
          const bool same_image = off.frame.image.rgb == on.frame.image.rgb;
          const bool same_ids = off.frame.ids.ids == on.frame.ids.ids;
          if (same_image && same_ids) continue;
          return s.name + " camera " + cam.kind + " " + row.name + " S=" + std::to_string(antialias) +
                 (lit == 2 ? " phong+shadow rays"
                  : phong  ? " phong+shadow maps"
                           : " flat") +
                 (same_image ? "" : ": image differs") + (same_ids ? "" : ": ids differ");
        }
      }
    }
    return "";
  }
};

// The identity check over `scenes`, one seeded camera of each kind per scene (plus its own). Returns
// how many pairs skipped cells; `lamps_culled`, when given, gets how many lamps the frames skipped,
// and `lamps_blocked` how many (polygon, lamp) pairs they left unlit.
size_t expect_identical(const std::vector<CullingScene>& scenes, uint64_t seed, size_t* lamps_culled = nullptr,
                        size_t* lamps_blocked = nullptr) {
  if (scenes.empty()) return 0;
  Matrix m;
  for (const CullingScene& s : scenes) {
    const PreparedScene scene = prepare_scene(s.request.scene);
    for (const SeededCamera& cam : testing::seeded_cameras(s.request, scene.soup, seed, 1)) {
      EXPECT_EQ(m.compare(s, scene, cam, 0), "") << "seed " << seed;
    }
  }
  std::cout << m.compared << " on/off pairs compared, " << m.cells_skipped << " of them skipping cells, "
            << m.lamps_culled << " lamps skipped, " << m.lamps_blocked << " polygon-lamp pairs left unlit\n";
  if (lamps_culled) *lamps_culled = m.lamps_culled;
  if (lamps_blocked) *lamps_blocked = m.lamps_blocked;
  return m.cells_skipped;
}

TEST(Culling, IdenticalOnAndOffExamples) {
  (void)expect_identical(testing::culling_scenes("examples", testing::source_dir(), testing::shared_data_dir()),
                         culling_seed());
}

TEST(Culling, IdenticalOnAndOffHomesWithModels) {
  const std::vector<CullingScene> homes =
      testing::culling_scenes("homes", testing::source_dir(), testing::shared_data_dir(),
                              {"Studio", "3BedroomApartment", "2BedroomHouseWithBasement"});
  if (homes.empty()) GTEST_SKIP() << "no homes (../shared/data absent)";
  size_t lamps_culled = 0, lamps_blocked = 0;
  EXPECT_GT(expect_identical(homes, culling_seed(), &lamps_culled, &lamps_blocked), 0u)
      << "the homes' cells were compared";
  EXPECT_GT(lamps_culled, 0u) << "shadow rays skipped lamps in rooms out of sight, with the same bytes";
  EXPECT_GT(lamps_blocked, 0u) << "and left polygons out of kept lamps' sight unlit, with the same bytes";
}

// A lamp shut in a room with no opening cannot see the cells a camera in another room reaches: with
// shadow rays and culling on it is skipped (counted, and its terms never evaluated); the lamp of the
// camera's room is not. With culling off, or shadow maps, nothing is skipped; the bytes are the same.
// Rooms A (x 0..4) and B (x 4..8), z 0..4, inside four outer walls; `middle` is the wall between
// them (from (4, 0) to (4, 4)), with its openings if any. One table, the lights and the camera given.
RenderRequest two_rooms(nlohmann::json middle, const nlohmann::json& table, const nlohmann::json& lights,
                        const nlohmann::json& camera) {
  nlohmann::json walls = nlohmann::json::array();
  for (const auto& [x0, z0, x1, z1] :
       std::vector<std::array<double, 4>>{{0, 0, 8, 0}, {8, 0, 8, 4}, {8, 4, 0, 4}, {0, 4, 0, 0}})
    walls.push_back({{"start", {x0, z0}}, {"end", {x1, z1}}});
  middle["start"] = {4, 0};
  middle["end"] = {4, 4};
  walls.push_back(std::move(middle));
  const nlohmann::json rooms = {{{"id", "A"}, {"points", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}}},
                                {{"id", "B"}, {"points", {{4, 0}, {8, 0}, {8, 4}, {4, 4}}}}};
  return request_from_json(
      {{"scene", {{"walls", walls}, {"rooms", rooms}, {"solids", {table}}, {"lights", lights}}}, {"camera", camera}});
}

TEST(Culling, LampInAClosedRoomTheViewCannotReachIsSkipped) {
  const nlohmann::json table = {{"type", "box"}, {"center", {2.0, 2.0}}, {"size", {0.8, 0.75, 0.8}}};
  const nlohmann::json lights = {{{"type", "point"}, {"position", {1.0, 2.0, 1.0}}, {"intensity", 0.6}},
                                 {{"type", "point"}, {"position", {6.0, 2.0, 2.0}}, {"intensity", 0.6}},
                                 {{"type", "directional"}, {"direction", {0.3, -1.0, 0.2}}, {"intensity", 0.3}}};
  const RenderRequest request =
      two_rooms(nlohmann::json::object(), table, lights, {{"position", {0.5, 1.6, 3.5}}, {"target", {3.0, 0.5, 1.0}}});
  const PreparedScene scene = prepare_scene(request.scene);
  ASSERT_TRUE(scene.cells && scene.cells->derived());
  Matrix m;
  m.flat_shadows = true;
  const PipelineId z = pipeline_id(pipeline_table()[0]);
  ASSERT_TRUE(pipeline_table()[0].occlusion_culling);
  for (bool phong : {true, false}) {
    SCOPED_TRACE(phong ? "phong" : "flat");
    auto draw = [&](CullingMode culling, ShadowMethod method) {
      return m.draw(request, scene, request.camera, z, 1, phong, culling, 0, 2, method);
    };
    const RenderOutcome on = draw(CullingMode::on, ShadowMethod::rays);
    const RenderOutcome off = draw(CullingMode::off, ShadowMethod::rays);
    const RenderOutcome maps = draw(CullingMode::on, ShadowMethod::map);
    EXPECT_EQ(on.report.stats.lamps_culled, 1u) << "the lamp of room B";
    EXPECT_EQ(off.report.stats.lamps_culled, 0u);
    EXPECT_EQ(maps.report.stats.lamps_culled, 0u);
    EXPECT_LT(on.report.stats.lights_evaluated, off.report.stats.lights_evaluated);
    EXPECT_TRUE(on.frame.image.rgb == off.frame.image.rgb);
    EXPECT_TRUE(on.frame.ids.ids == off.frame.ids.ids);
  }
}

// A lamp in room B that sees room A only through a narrow open doorway in the wall between them is
// kept, but the table in A's corner lies outside every sight line through the doorway: with
// shadow rays and culling on, the table's polygons are left out of the lamp's shading (counted, fewer
// light evaluations) and the bytes are those of culling off, which casts every ray and finds it
// blocked.
TEST(Culling, PolygonsOutOfAKeptLampsSightAreLeftUnlit) {
  const nlohmann::json doorway = {
      {"openings", {{{"type", "door"}, {"offset", 1.7}, {"width", 0.6}, {"height", 2.1}, {"leaf", false}}}}};
  const nlohmann::json table = {{"type", "box"}, {"center", {1.0, 3.4}}, {"size", {0.8, 0.75, 0.8}}};
  const nlohmann::json lights = {{{"type", "point"}, {"position", {6.0, 2.0, 2.0}}, {"intensity", 0.6}},
                                 {{"type", "point"}, {"position", {2.0, 2.2, 2.0}}, {"intensity", 0.4}}};
  const RenderRequest request =
      two_rooms(doorway, table, lights, {{"position", {3.5, 1.6, 0.3}}, {"target", {1.0, 0.5, 3.4}}});
  const PreparedScene scene = prepare_scene(request.scene);
  ASSERT_TRUE(scene.cells && scene.cells->derived());
  Matrix m;
  m.flat_shadows = true;
  const PipelineId z = pipeline_id(pipeline_table()[0]);
  for (bool phong : {true, false}) {
    SCOPED_TRACE(phong ? "phong" : "flat");
    auto draw = [&](CullingMode culling) {
      return m.draw(request, scene, request.camera, z, 1, phong, culling, 0, 2, ShadowMethod::rays);
    };
    const RenderOutcome on = draw(CullingMode::on);
    const RenderOutcome off = draw(CullingMode::off);
    EXPECT_EQ(on.report.stats.lamps_culled, 0u) << "room B's lamp sees room A through the doorway";
    EXPECT_GE(on.report.stats.lamps_blocked, 5u) << "the table's visible faces, at least";
    EXPECT_EQ(off.report.stats.lamps_blocked, 0u);
    EXPECT_LT(on.report.stats.lights_evaluated, off.report.stats.lights_evaluated);
    EXPECT_TRUE(on.frame.image.rgb == off.frame.image.rgb);
    EXPECT_TRUE(on.frame.ids.ids == off.frame.ids.ids);
  }
}

// What lamp culling knows without the camera (each lamp's cube-face portal walks, its fixture map) is
// made once with the prepared scene: a frame takes it and makes none, and its bytes are those of a
// frame that makes its own. A frame of a scene prepared without it makes its own once, then takes the
// ones this thread kept; a lamp that moved makes its own while the others are taken.
TEST(Culling, LampWalksAndFixtureMapsAreMadeOnceWithTheSameBytes) {
  const nlohmann::json doorway = {
      {"openings", {{{"type", "door"}, {"offset", 1.7}, {"width", 0.6}, {"height", 2.1}, {"leaf", false}}}}};
  const nlohmann::json table = {{"type", "box"}, {"center", {1.0, 3.4}}, {"size", {0.8, 0.75, 0.8}}};
  // The second lamp sits inside the table (its fixture): its map closes every direction.
  const nlohmann::json lights = {{{"type", "point"}, {"position", {6.0, 2.0, 2.0}}, {"intensity", 0.6}},
                                 {{"type", "point"}, {"position", {1.0, 0.4, 3.4}}, {"intensity", 0.4}},
                                 {{"type", "point"}, {"position", {2.0, 2.2, 2.0}}, {"intensity", 0.4}}};
  const nlohmann::json camera = {{"position", {3.5, 1.6, 0.3}}, {"target", {1.0, 0.5, 3.4}}};
  const RenderRequest request = two_rooms(doorway, table, lights, camera);
  const PreparedScene scene = prepare_scene(request.scene);
  ASSERT_TRUE(scene.cells && scene.cells->derived());
  ASSERT_TRUE(scene.lamps);
  ASSERT_EQ(scene.lamps->lamps.size(), 3u);
  EXPECT_GT(scene.lamps->lamps[1].fixture.n, 0) << "the table holds the second lamp";
  const PreparedScene unprepared = prepare_scene(request.scene, 2, PrepareLamps::no);
  EXPECT_FALSE(unprepared.lamps);
  Matrix m;
  const PipelineId z = pipeline_id(pipeline_table()[0]);
  auto draw = [&](const RenderRequest& r, const PreparedScene& s) {
    return m.draw(r, s, r.camera, z, 1, true, CullingMode::on, 0, 2, ShadowMethod::rays);
  };
  const RenderOutcome taken = draw(request, scene);
  EXPECT_EQ(taken.report.stats.lamp_walks_made, 0u);
  EXPECT_EQ(taken.report.stats.fixture_maps_made, 0u);
  const RenderOutcome made = draw(request, unprepared);
  EXPECT_GE(made.report.stats.lamp_walks_made, 3u * 6u) << "every lamp walks its six faces (none gives up here)";
  EXPECT_EQ(made.report.stats.fixture_maps_made, 1u);
  const RenderOutcome kept = draw(request, unprepared);
  EXPECT_EQ(kept.report.stats.lamp_walks_made, 0u) << "the thread's walks of the last frame";
  EXPECT_EQ(kept.report.stats.fixture_maps_made, 0u);
  for (const RenderOutcome* o : {&made, &kept}) {
    EXPECT_TRUE(o->frame.image.rgb == taken.frame.image.rgb);
    EXPECT_TRUE(o->frame.ids.ids == taken.frame.ids.ids);
    EXPECT_EQ(o->report.stats.lamps_blocked, taken.report.stats.lamps_blocked);
    EXPECT_EQ(o->report.stats.lights_evaluated, taken.report.stats.lights_evaluated);
  }
  EXPECT_GT(taken.report.stats.lamps_blocked, 0u);
  // The first lamp moved 1 cm: its prepared entries no longer serve it; the others' still do.
  PreparedScene shifted = scene;
  shifted.scene.lights[0].position.y += 0.01;
  const RenderOutcome partly = draw(request, shifted);
  EXPECT_GE(partly.report.stats.lamp_walks_made, 1u);
  EXPECT_LE(partly.report.stats.lamp_walks_made, 6u);
  EXPECT_EQ(partly.report.stats.fixture_maps_made, 0u);
  PreparedScene remade = shifted;
  remade.lamps = std::make_shared<const PreparedLamps>(prepare_lamps(remade.soup, *remade.cells, remade.scene.lights));
  const RenderOutcome fresh = draw(request, remade);
  EXPECT_EQ(fresh.report.stats.lamp_walks_made, 0u);
  EXPECT_TRUE(partly.frame.image.rgb == fresh.frame.image.rgb);
  EXPECT_FALSE(partly.frame.image.rgb == taken.frame.image.rgb) << "the moved lamp lights the room differently";
}

TEST(Culling, IdenticalOnAndOffPlansAndFireplaceRoom) {
  std::vector<CullingScene> scenes = testing::culling_scenes("r2v", testing::source_dir(), testing::shared_data_dir());
  if (scenes.size() > 2) scenes.resize(2);
  for (CullingScene& s : testing::culling_scenes("fireplace", testing::source_dir(), testing::shared_data_dir()))
    scenes.push_back(std::move(s));
  if (scenes.empty()) GTEST_SKIP() << "no plans (../shared/data absent)";
  (void)expect_identical(scenes, culling_seed());
}

// The mutation the identity tests exist for: the occlusion test made one margin too eager (a node
// counts as hidden when its nearest point is up to one margin in front of the pyramid) must show.
TEST(Culling, OneMarginTooEagerIsCaught) {
  const uint64_t seed = culling_seed();
  std::vector<CullingScene> scenes =
      testing::culling_scenes("examples", testing::source_dir(), testing::shared_data_dir());
  for (CullingScene& s :
       testing::culling_scenes("homes", testing::source_dir(), testing::shared_data_dir(), {"Studio"}))
    scenes.push_back(std::move(s));
  Matrix m;
  std::string first;
  for (const CullingScene& s : scenes) {
    const PreparedScene scene = prepare_scene(s.request.scene);
    for (const SeededCamera& cam : testing::seeded_cameras(s.request, scene.soup, seed, 1)) {
      first = m.compare(s, scene, cam, 1);
      if (!first.empty()) break;
    }
    if (!first.empty()) break;
  }
  EXPECT_NE(first, "") << "an eager occlusion test went unnoticed over " << m.compared << " pairs";
  std::cout << "eager test caught at: " << first << "\n";
}

// Whether two portal walks reached the same cells with the same regions.
bool same_walk(const CellWalk& a, const CellWalk& b) {
  if (a.reached != b.reached) return false;
  for (size_t c = 0; c < a.regions.size(); ++c) {
    if (a.regions[c].count != b.regions[c].count) return false;
    for (size_t k = 0; k < a.regions[c].count; ++k) {
      const ViewRegion &x = a.regions[c].region[k], &y = b.regions[c].region[k];
      if (x.x0 != y.x0 || x.y0 != y.y0 || x.x1 != y.x1 || x.y1 != y.y1) return false;
    }
  }
  return true;
}

// The mutation for the cells: one portal left out of the walk must show. A sight line that enters a
// wall through a crack at an opening's jamb travels inside it unseen, so the cells beside one wall
// with openings are joined by thin seam portals too, and in a home most rooms are reached more ways
// than one: a dropped door rarely shows there. Two rooms joined only by a gap between two walls
// without openings (so no seam) show it: each boundary portal whose loss changes the walk is dropped
// in turn, and what is seen through the gap must go missing from some frame.
TEST(Culling, OneDroppedPortalIsCaught) {
  nlohmann::json walls = nlohmann::json::array();
  for (const auto& [x0, z0, x1, z1] : std::vector<std::array<double, 4>>{
           {0, 0, 8, 0}, {8, 0, 8, 4}, {8, 4, 0, 4}, {0, 4, 0, 0}, {4, 0, 4, 1.5}, {4, 2.5, 4, 4}})
    walls.push_back({{"start", {x0, z0}}, {"end", {x1, z1}}});
  const nlohmann::json rooms = {{{"id", "A"}, {"points", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}}},
                                {{"id", "B"}, {"points", {{4, 0}, {8, 0}, {8, 4}, {4, 4}}}}};
  const nlohmann::json table = {{"type", "box"}, {"center", {6.0, 2.0}}, {"size", {0.8, 0.75, 0.8}}};
  const CullingScene s{"two rooms",
                       request_from_json({{"scene", {{"walls", walls}, {"rooms", rooms}, {"solids", {table}}}},
                                          {"camera", {{"position", {1.0, 1.6, 2.0}}, {"target", {6.0, 0.5, 2.0}}}}})};
  const PreparedScene scene = prepare_scene(s.request.scene);
  ASSERT_TRUE(scene.cells && scene.cells->derived());
  const SceneCells& cells = *scene.cells;
  Matrix m;
  EXPECT_EQ(m.compare(s, scene, {"own", s.request.camera}, 0), "");  // nothing dropped: identical
  const CellViewpoint viewpoint = cell_viewpoint(make_view(s.request.camera, m.width, m.height));
  CellWalk all, without;
  walk_cells(cells, cell_conditions(cells, {}), viewpoint, all);
  std::string first;
  size_t tried = 0;
  for (const Portal& p : cells.portals) {
    if (p.kind != PortalKind::boundary || p.from > p.to) continue;
    CellConditions conditions = cell_conditions(cells, {});
    conditions.dropped_pair = p.pair;
    walk_cells(cells, conditions, viewpoint, without);
    if (same_walk(without, all)) continue;
    ++tried;
    m.drop_portal = p.pair;
    first = m.compare(s, scene, {"own", s.request.camera}, 0);
    if (!first.empty()) break;
  }
  EXPECT_NE(first, "") << "a dropped portal went unnoticed over " << tried << " portals";
  std::cout << "dropped portal caught at: " << first << " (" << tried << " tried)\n";
}

// The counters and the image do not depend on the thread count; culling does skip work on a home.
TEST(Culling, CountersAreTheSameForAnyThreadCount) {
  std::vector<CullingScene> scenes =
      testing::culling_scenes("homes", testing::source_dir(), testing::shared_data_dir(), {"3BedroomApartment"});
  if (scenes.empty()) GTEST_SKIP() << "no homes (../shared/data absent)";
  const PreparedScene scene = prepare_scene(scenes[0].request.scene);
  Matrix m;
  for (const PipelineInfo& row : pipeline_table()) {
    if (!row.occlusion_culling) continue;
    const char* name = row.name;
    const PipelineId p = pipeline_id(row);
    const RenderOutcome one =
        m.draw(scenes[0].request, scene, scenes[0].request.camera, p, 1, false, CullingMode::on, 0, 1);
    const RenderOutcome three =
        m.draw(scenes[0].request, scene, scenes[0].request.camera, p, 1, false, CullingMode::on, 0, 3);
    const RenderOutcome off =
        m.draw(scenes[0].request, scene, scenes[0].request.camera, p, 1, false, CullingMode::off, 0, 3);
    const RenderStats &a = one.report.stats, &b = three.report.stats;
    EXPECT_EQ(a.objects_occluded, b.objects_occluded) << name;
    EXPECT_EQ(a.nodes_tested, b.nodes_tested) << name;
    EXPECT_EQ(a.polygons_projected, b.polygons_projected) << name;
    EXPECT_EQ(a.cells, b.cells) << name;
    EXPECT_EQ(a.cells_visited, b.cells_visited) << name;
    EXPECT_EQ(a.portals_walked, b.portals_walked) << name;
    EXPECT_GT(a.cells, 1u) << name << ": the apartment's cells are derived";
    EXPECT_LT(a.cells_visited, a.cells) << name << ": the observer's portal walk skips rooms";
    EXPECT_GT(a.portals_walked, 0u) << name;
    EXPECT_EQ(one.frame.image.rgb, three.frame.image.rgb) << name;
    EXPECT_GT(a.objects_occluded, 0u) << name << ": the observer sees one room of the apartment";
    EXPECT_GT(a.nodes_tested, 0u) << name;
    EXPECT_LT(a.polygons_projected, off.report.stats.polygons_projected) << name;
    EXPECT_EQ(off.report.stats.nodes_tested, 0u) << name;
    EXPECT_EQ(off.report.stats.objects_occluded, 0u) << name;
    EXPECT_EQ(off.report.stats.cells, 0u) << name;
  }
}

// Painter and the reference do not use it: their counts are the same either way.
TEST(Culling, PainterAndReferenceDoNotUseIt) {
  const RenderRequest request = request_from_json(testing::example_request("apartment", 96, 72));
  const PreparedScene scene = prepare_scene(request.scene);
  Matrix m;
  m.width = 96, m.height = 72;
  for (const PipelineInfo& row : pipeline_table()) {
    if (row.occlusion_culling) continue;
    const RenderOutcome on = m.draw(request, scene, request.camera, pipeline_id(row), 1, false, CullingMode::on, 0);
    const RenderOutcome off = m.draw(request, scene, request.camera, pipeline_id(row), 1, false, CullingMode::off, 0);
    EXPECT_EQ(on.frame.image.rgb, off.frame.image.rgb) << row.name;
    EXPECT_EQ(on.report.stats.polygons_projected, off.report.stats.polygons_projected) << row.name;
    EXPECT_EQ(on.report.stats.nodes_tested, 0u) << row.name;
  }
}

// The pyramid's promise, checked against the rasterizer itself: every pixel centre of a raised block
// is covered by the polygon that raised it, at a 1/w no smaller than the block's bound.
TEST(Culling, PyramidBoundsHoldForTheRasterizer) {
  const uint64_t seed = culling_seed();
  std::mt19937_64 rng(seed);
  auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  Camera camera;
  camera.position = Vec3(0.0, 0.0, 5.0), camera.target = Vec3(0.0), camera.near = 0.1;
  const ViewTransform view = make_view(camera, 160, 120);
  size_t raised_total = 0;
  for (int n = 0; n < 300; ++n) {
    PolygonSoup soup;
    const Vec3 c(uniform(-2.0, 2.0), uniform(-1.5, 1.5), uniform(-4.0, 4.0));
    const Vec3 u = glm::normalize(Vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)));
    const Vec3 v = glm::normalize(glm::cross(u, Vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1))));
    const double r = uniform(0.2, 3.0);
    const int corners = 3 + int(rng() % 6);
    for (int k = 0; k < corners; ++k) {
      const double a = 6.283185307179586 * (k + uniform(0.0, 0.3)) / corners;
      soup.positions.push_back(c + r * (std::cos(a) * u + std::sin(a) * glm::cross(v, u)));
      soup.normals.push_back(glm::vec3(v));
    }
    Polygon p;
    p.vertex_count = uint32_t(corners);
    soup.polygons.push_back(p);
    DrawScratch scratch;
    if (!project_polygon(view, soup, soup.polygons[0], scratch)) continue;
    DepthPyramid pyramid(view.width, view.height);
    raised_total += pyramid.add_polygon(scratch.screen);
    std::vector<double> depth(size_t(view.width) * size_t(view.height), 0.0);
    rasterize_convex(scratch.screen, PixelRect{0, 0, view.width, view.height}, [&](const Fragment& f, size_t) {
      depth[size_t(f.y) * size_t(view.width) + size_t(f.x)] = f.inv_w;
    });
    for (int y = 0; y < view.height; ++y) {
      for (int x = 0; x < view.width; ++x) {
        const double bound = pyramid.block(x / occlusion_block, y / occlusion_block);
        if (bound == 0.0) continue;
        ASSERT_GE(depth[size_t(y) * size_t(view.width) + size_t(x)], bound)
            << "seed " << seed << " polygon " << n << " pixel " << x << "," << y;
      }
    }
  }
  EXPECT_GT(raised_total, 100u) << "the random polygons raised blocks";
}

}  // namespace
}  // namespace rr

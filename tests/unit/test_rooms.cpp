// Rooms and levels: an L-shaped room's floor and ceiling areas, the parser's defaults and pointer
// errors, the per-view selection (ceilings by camera height and mode, levels by id) through render()
// with polygon ids kept, shadows cast only by what is drawn, every pipeline against the reference
// on a room with a ceiling, and Sweet Home 3D homes of ../shared (skipped without it).
#include "import_test_util.hpp"
#include "render/core/error_metrics.hpp"
#include "render/core/scene_id.hpp"
#include "render/import/import.hpp"
#include "render/pipelines/render.hpp"
#include "render/pipelines/view_selection.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace {

using nlohmann::json;

const json l_room = {{"id", "L"}, {"points", {{0, 0}, {4, 0}, {4, 2}, {2, 2}, {2, 4}, {0, 4}}}};  // area 12 m^2

rr::RenderRequest parse(const json& request) { return rr::request_from_json(request); }

// Sum of polygon areas of the room objects, split by ceiling or floor.
std::pair<double, double> floor_and_ceiling_area(const rr::PolygonSoup& soup, double& floor_y, double& ceiling_y) {
  double floor = 0.0, ceiling = 0.0;
  for (const rr::Polygon& p : soup.polygons) {
    const rr::SceneObject& o = soup.objects[p.object];
    if (o.element.kind != rr::ElementKind::room) continue;
    (o.ceiling ? ceiling : floor) += rr::polygon_area(soup.points(p));
    (o.ceiling ? ceiling_y : floor_y) = soup.points(p)[0].y;
    EXPECT_DOUBLE_EQ(p.normal.y, o.ceiling ? -1.0 : 1.0);  // floors face up, ceilings down
  }
  return {floor, ceiling};
}

TEST(Rooms, LShapedFloorAndCeilingAreasEqualThePolygonsArea) {
  json room = l_room;
  room["elevation"] = 0.5;
  room["ceiling_height"] = 2.4;
  rr::RenderRequest r = parse({{"scene", {{"rooms", {room}}}}});
  rr::PolygonSoup soup = rr::tessellate(r.scene.geometry);
  double floor_y = 0.0, ceiling_y = 0.0;
  auto [floor, ceiling] = floor_and_ceiling_area(soup, floor_y, ceiling_y);
  EXPECT_NEAR(floor, 12.0, 1e-12);
  EXPECT_NEAR(ceiling, 12.0, 1e-12);
  EXPECT_DOUBLE_EQ(floor_y, 0.5);
  EXPECT_DOUBLE_EQ(ceiling_y, 2.9);
  EXPECT_LE(soup.polygons.size(), rr::estimate_polygon_count(r.scene.geometry));
  room["ceiling"] = false;
  soup = rr::tessellate(parse({{"scene", {{"rooms", {room}}}}}).scene.geometry);
  EXPECT_EQ(floor_and_ceiling_area(soup, floor_y, ceiling_y).second, 0.0);
}

TEST(Rooms, DefaultsComeFromTheRoomsLevel) {
  json room = l_room;
  room["level"] = "upstairs";
  json scene;
  scene["levels"] = json::parse(R"([{"id": "ground"}, {"id": "upstairs", "elevation": 3.0, "height": 2.7}])");
  scene["rooms"] = {room, l_room};
  rr::RenderRequest r = parse({{"scene", scene}});
  const auto& rooms = r.scene.geometry.rooms;
  EXPECT_EQ(rooms[0].level, 1);
  EXPECT_DOUBLE_EQ(rooms[0].elevation, 3.0);
  EXPECT_DOUBLE_EQ(rooms[0].ceiling_height, 2.7);
  EXPECT_EQ(rooms[1].level, -1);
  EXPECT_DOUBLE_EQ(rooms[1].elevation, 0.0);
  EXPECT_DOUBLE_EQ(rooms[1].ceiling_height, 2.5);
  EXPECT_NEAR(rooms[1].ceiling_color.r, 240.0 / 255.0, 1e-6);  // #f0f0f0, documented
  EXPECT_TRUE(r.scene.geometry.levels[0].viewable);
}

std::string error_pointer(const json& request) {
  try {
    rr::request_from_json(request);
  } catch (const rr::InputError& e) {
    EXPECT_EQ(e.kind(), rr::InputError::Kind::invalid) << e.what();
    return e.pointer();
  }
  return "(no error)";
}

TEST(Rooms, ErrorsNameTheirPointer) {
  json bowtie = l_room;
  bowtie["points"] = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  EXPECT_EQ(error_pointer({{"scene", {{"rooms", {bowtie}}}}}), "/scene/rooms/0/points");
  json unknown = l_room;
  unknown["level"] = "attic";
  const json levels = {{{"id", "ground"}}};
  EXPECT_EQ(error_pointer({{"scene", {{"levels", levels}, {"rooms", {l_room, unknown}}}}}), "/scene/rooms/1/level");
  EXPECT_EQ(
      error_pointer({{"scene", {{"levels", levels}, {"walls", {{{"start", {0, 0}}, {"end", {1, 0}}, {"level", 3}}}}}}}),
      "/scene/walls/0/level");
  EXPECT_EQ(
      error_pointer(
          {{"scene", {{"solids", {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"level", "x"}}}}}}}),
      "/scene/solids/0/level");
  EXPECT_EQ(error_pointer({{"scene", {{"levels", {{{"id", "a"}}, {{"id", "a"}}}}}}}), "/scene/levels/1/id");
  EXPECT_EQ(error_pointer({{"scene", {{"levels", levels}}}, {"options", {{"levels", {"ground", "roof"}}}}}),
            "/options/levels/1");
  EXPECT_EQ(error_pointer({{"scene", json::object()}, {"options", {{"ceilings", "sometimes"}}}}), "/options/ceilings");
  // A stored scene's view is read without its scene and checked against it afterwards.
  rr::RenderRequest view = parse({{"options", {{"levels", {"roof"}}}}});
  rr::RenderRequest scene = parse({{"scene", {{"levels", levels}}}});
  EXPECT_THROW(rr::check_view_levels(view.options, scene.scene.geometry.levels), rr::InputError);
}

TEST(Rooms, SceneIdCoversRooms) {
  const rr::RenderRequest plain = parse({{"scene", {{"walls", {{{"start", {0, 0}}, {"end", {1, 0}}}}}}}});
  const rr::RenderRequest with_room =
      parse({{"scene", {{"walls", {{{"start", {0, 0}}, {"end", {1, 0}}}}}, {"rooms", {l_room}}}}});
  json taller = l_room;
  taller["ceiling_height"] = 3.0;
  const rr::RenderRequest taller_room =
      parse({{"scene", {{"walls", {{{"start", {0, 0}}, {"end", {1, 0}}}}}, {"rooms", {taller}}}}});
  EXPECT_NE(rr::scene_id(plain.scene.geometry), rr::scene_id(with_room.scene.geometry));
  EXPECT_NE(rr::scene_id(with_room.scene.geometry), rr::scene_id(taller_room.scene.geometry));
}

// A closed 4 x 4 m room: a floor tile grid, four walls, a room with a 2.5 m ceiling; sun from above.
json box_room(const std::string& pipeline, rr::Vec3 eye, rr::Vec3 target) {
  json walls = json::array();
  const double c[5][2] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {0, 0}};
  for (int i = 0; i < 4; ++i) {
    walls.push_back(
        {{"start", {c[i][0], c[i][1]}}, {"end", {c[i + 1][0], c[i + 1][1]}}, {"height", 2.5}, {"thickness", 0.2}});
  }
  json room = {{"points", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}}, {"ceiling_color", "#ff0000"}};
  json solids = {{{"type", "box"}, {"center", {2.5, 1.5}}, {"size", {0.8, 0.9, 0.6}}}};
  return {{"scene",
           {{"walls", walls},
            {"rooms", {room}},
            {"solids", solids},
            {"lights", {{{"type", "directional"}, {"direction", {0.2, -1.0, 0.1}}}}}}},
          {"camera", {{"position", {eye.x, eye.y, eye.z}}, {"target", {target.x, target.y, target.z}}}},
          {"options", {{"width", 96}, {"height", 72}, {"pipeline", pipeline}, {"painter", {{"key", "newell"}}}}}};
}

struct Drawn {
  rr::Frame frame;
  std::set<uint32_t> ids;  // polygon ids seen
};

Drawn draw(const json& request, const rr::RenderContext& context = {}) {
  rr::RenderRequest r = parse(request);
  rr::PreparedScene scene = rr::prepare_scene(r.scene);
  rr::RenderContext c = context;
  c.encode = false;
  Drawn out{rr::render(r, scene, c).frame, {}};
  out.ids.insert(out.frame.ids.ids.begin(), out.frame.ids.ids.end());
  return out;
}

std::set<uint32_t> ceiling_ids(const json& request) {
  rr::PolygonSoup soup = rr::tessellate(parse(request).scene.geometry);
  std::set<uint32_t> out;
  for (const rr::Polygon& p : soup.polygons) {
    if (soup.objects[p.object].ceiling) out.insert(p.id);
  }
  return out;
}

size_t count_in(const std::set<uint32_t>& seen, const std::set<uint32_t>& wanted) {
  size_t n = 0;
  for (uint32_t id : seen) n += wanted.count(id);
  return n;
}

TEST(Rooms, AutoCeilingsShowFromBelowOnlyAndModesOverride) {
  const json inside = box_room("zbuffer", {0.5, 1.6, 0.5}, {3.0, 2.3, 3.0});
  const json above = box_room("zbuffer", {2.0, 8.0, 2.5}, {2.0, 0.0, 2.0});
  const std::set<uint32_t> ceiling = ceiling_ids(inside);
  ASSERT_FALSE(ceiling.empty());
  EXPECT_GT(count_in(draw(inside).ids, ceiling), 0u);
  EXPECT_EQ(count_in(draw(above).ids, ceiling), 0u);
  json off = inside;
  off["options"]["ceilings"] = "off";
  EXPECT_EQ(count_in(draw(off).ids, ceiling), 0u);
  // "on" keeps the ceiling in the drawn soup, but it is one-sided: from above it is culled.
  json on = above;
  on["options"]["ceilings"] = "on";
  EXPECT_EQ(count_in(draw(on).ids, ceiling), 0u);
}

TEST(Rooms, EveryPipelineMatchesTheReferenceUnderACeiling) {
  const rr::Vec3 eye{0.6, 1.5, 0.7}, target{3.2, 2.2, 3.0};
  const Drawn truth = draw(box_room("reference", eye, target));
  const std::set<uint32_t> ceiling = ceiling_ids(box_room("reference", eye, target));
  ASSERT_GT(count_in(truth.ids, ceiling), 0u);
  for (const std::string& pipeline : rr::testing::pipeline_names()) {
    const Drawn test = draw(box_room(pipeline, eye, target));
    const rr::testing::IdDiff diff = rr::testing::compare_ids(truth.frame.ids, test.frame.ids, true);
    EXPECT_EQ(diff.interior, 0u) << pipeline << " (" << diff.edge << " edge pixels differ)";
  }
}

// The same with a selection in force (a level left out, so the pipelines draw a filtered soup whose
// ids have gaps), Gouraud shading so split fragments look their source polygon up by id.
TEST(Levels, EveryPipelineMatchesTheReferenceWithALevelLeftOut) {
  const rr::Vec3 eye{0.6, 1.5, 0.7}, target{3.2, 1.2, 3.0};
  auto request = [&](const std::string& pipeline) {
    json r = box_room(pipeline, eye, target);
    r["scene"]["levels"] = json::parse(R"([{"id": "low"}, {"id": "high", "elevation": 1.0}])");
    r["scene"]["solids"][0]["level"] = "high";
    r["scene"]["solids"].push_back(
        {{"type", "cylinder"}, {"center", {2.0, 2.5}}, {"radius", 0.4}, {"height", 1.2}, {"level", "low"}});
    r["options"]["levels"] = {"low"};
    r["options"]["shading"] = "gouraud";
    return r;
  };
  const Drawn truth = draw(request("reference"));
  rr::PolygonSoup soup = rr::tessellate(parse(request("reference")).scene.geometry);
  std::set<uint32_t> box, cylinder;
  for (const rr::Polygon& p : soup.polygons) {
    const rr::ElementRef& e = soup.objects[p.object].element;
    if (e.kind == rr::ElementKind::solid) (e.index == 0 ? box : cylinder).insert(p.id);
  }
  EXPECT_EQ(count_in(truth.ids, box), 0u);  // its level is left out
  EXPECT_GT(count_in(truth.ids, cylinder), 0u);
  for (const std::string& pipeline : rr::testing::pipeline_names()) {
    const Drawn test = draw(request(pipeline));
    const rr::testing::IdDiff diff = rr::testing::compare_ids(truth.frame.ids, test.frame.ids, true);
    EXPECT_EQ(diff.interior, 0u) << pipeline << " (" << diff.edge << " edge pixels differ)";
    // Split fragments are shaded as their source polygon, found by id in the filtered soup: a wrong
    // lookup shows as colour, not as ids.
    const rr::ShadingError shade = rr::shading_error(truth.frame.image, test.frame.image);
    EXPECT_LT(shade.rmse, 8.0) << pipeline;
  }
}

// Lit pixels of `id` under light 0 and how many of them are in shadow.
std::pair<size_t, size_t> lit_and_shadowed(const Drawn& d, const std::set<uint32_t>& ids) {
  size_t seen = 0, shadowed = 0;
  for (size_t i = 0; i < d.frame.ids.ids.size(); ++i) {
    if (!ids.count(d.frame.ids.ids[i])) continue;
    ++seen;
    shadowed += (d.frame.shadow_mask[i] & 1u) == 0;
  }
  return {seen, shadowed};
}

std::set<uint32_t> ids_of_kind(const json& request, rr::ElementKind kind, bool ceiling = false) {
  rr::PolygonSoup soup = rr::tessellate(parse(request).scene.geometry);
  std::set<uint32_t> out;
  for (const rr::Polygon& p : soup.polygons) {
    const rr::SceneObject& o = soup.objects[p.object];
    if (o.element.kind == kind && o.ceiling == ceiling) out.insert(p.id);
  }
  return out;
}

TEST(Rooms, DrawnCeilingsCastShadowsUndrawnOnesDoNot) {
  for (const std::string pipeline : {"zbuffer", "reference"}) {
    json request = box_room(pipeline, {0.6, 2.2, 0.6}, {2.5, 0.0, 2.5});
    request["options"]["shadows"] = true;
    const std::set<uint32_t> floor = ids_of_kind(request, rr::ElementKind::room);
    rr::RenderContext context;
    context.shadow_mask = true;
    auto [seen, shadowed] = lit_and_shadowed(draw(request, context), floor);
    ASSERT_GT(seen, 100u) << pipeline;
    EXPECT_EQ(shadowed, seen) << pipeline;  // the ceiling shades the whole floor from the sun
    request["options"]["ceilings"] = "off";
    auto [seen_off, shadowed_off] = lit_and_shadowed(draw(request, context), floor);
    ASSERT_GT(seen_off, 100u) << pipeline;
    EXPECT_LT(shadowed_off, seen_off / 4) << pipeline;  // only the box's and the walls' shadows remain
  }
}

TEST(Levels, LevelsNotDrawnCastNoShadow) {
  // A slab on level "up" hangs over a floor on no level; the sun shines straight down.
  const json request = {
      {"scene",
       {{"levels", {{{"id", "up"}, {"elevation", 2.0}}}},
        {"floor", {{"origin", {-2, -2}}, {"cells", {4, 4}}}},
        {"solids", {{{"type", "box"}, {"center", {0, 0}}, {"base", 2.0}, {"size", {2, 0.2, 2}}, {"level", "up"}}}},
        {"lights", {{{"type", "directional"}, {"direction", {0.0, -1.0, 0.0}}}}}}},
      {"camera", {{"position", {0.0, 1.0, 3.0}}, {"target", {0.0, 0.0, 0.0}}}},
      {"options", {{"width", 64}, {"height", 48}, {"shadows", true}}}};
  const std::set<uint32_t> floor = ids_of_kind(request, rr::ElementKind::floor);
  rr::RenderContext context;
  context.shadow_mask = true;
  auto [seen, shadowed] = lit_and_shadowed(draw(request, context), floor);
  EXPECT_GT(shadowed, 50u);
  json without = request;
  without["options"]["levels"] = json::array();
  auto [seen_without, shadowed_without] = lit_and_shadowed(draw(without, context), floor);
  EXPECT_GT(seen_without, 50u);
  EXPECT_EQ(shadowed_without, 0u);
  (void)seen;
}

TEST(Levels, SelectionKeepsPolygonIdsAndTheCacheApart) {
  const json request = {{"scene",
                         {{"levels", {{{"id", "a"}}, {{"id", "b"}, {"viewable", false}}}},
                          {"solids",
                           {{{"type", "box"}, {"center", {-1, 0}}, {"size", {1, 1, 1}}, {"level", "a"}},
                            {{"type", "box"}, {"center", {1, 0}}, {"size", {1, 1, 1}}, {"level", "b"}}}}}},
                        {"camera", {{"position", {0.0, 2.0, 5.0}}, {"target", {0.0, 0.5, 0.0}}}},
                        {"options", {{"width", 64}, {"height", 48}, {"pipeline", "bsp"}}}};
  rr::BspCache cache(8);
  rr::RenderContext context;
  context.bsp_cache = &cache;
  json all = request;
  all["options"]["levels"] = {"a", "b"};
  const Drawn both = draw(all, context);
  const Drawn viewable = draw(request, context);  // level b is not viewable
  // Box a's six faces are ids 0-5, box b's 6-11, whatever is drawn.
  auto has_id_in = [](const Drawn& d, uint32_t lo, uint32_t hi) {
    for (uint32_t id : d.ids) {
      if (id >= lo && id <= hi) return true;
    }
    return false;
  };
  EXPECT_TRUE(has_id_in(both, 0, 5));
  EXPECT_TRUE(has_id_in(both, 6, 11));
  EXPECT_TRUE(has_id_in(viewable, 0, 5));
  EXPECT_FALSE(has_id_in(viewable, 6, 11));
  // Where box a shows in both frames, it has the same ids.
  size_t same = 0;
  for (size_t i = 0; i < both.frame.ids.ids.size(); ++i) {
    if (both.frame.ids.ids[i] <= 5) same += viewable.frame.ids.ids[i] == both.frame.ids.ids[i];
  }
  EXPECT_GT(same, 0u);
}

// A view that leaves a level out draws the same bytes whether its selection is made for the frame or
// taken from a view cache, and the cache makes each selection once: its polygons, and their shadow-ray
// tree for rays, and for maps only when the kept polygons hold a pane.
TEST(Levels, ASelectionIsMadeOnceAndDrawsTheSameBytesFromTheCache) {
  json request = {
      {"scene",
       {{"levels", {{{"id", "a"}}, {{"id", "b"}, {"elevation", 2.0}}}},
        {"floor", {{"origin", {-2, -2}}, {"cells", {4, 4}}}},
        {"walls",
         {{{"start", {-2, -1}},
           {"end", {2, -1}},
           {"height", 2.0},
           {"level", "a"},
           {"openings",
            {{{"type", "window"},
              {"offset", 1.0},
              {"width", 1.5},
              {"sill", 0.5},
              {"height", 1.0},
              {"color", "#99ccff"}}}}}}},
        {"solids",
         {{{"type", "box"}, {"center", {0.5, 0.5}}, {"size", {0.6, 0.6, 0.6}}, {"level", "a"}},
          {{"type", "box"}, {"center", {0, 0}}, {"base", 2.0}, {"size", {2, 0.2, 2}}, {"level", "b"}}}},
        {"lights",
         {{{"type", "directional"}, {"direction", {0.3, -1.0, 0.6}}},
          {{"type", "point"}, {"position", {-1.0, 1.5, 0.5}}, {"intensity", 0.5}}}}}},
      {"camera", {{"position", {0.0, 1.2, 3.0}}, {"target", {0.0, 0.5, 0.0}}}},
      {"options", {{"width", 96}, {"height", 72}, {"shadows", true}, {"shading", "phong"}, {"levels", {"a"}}}}};
  const rr::RenderRequest parsed = parse(request);
  const rr::PreparedScene scene = rr::prepare_scene(parsed.scene);
  struct Case {
    const char* method;
    bool panes;
    size_t entries;  // the selection, and its tree when the frame casts rays or its maps meet a pane
  };
  for (const Case& c : {Case{"rays", true, 2}, Case{"map", true, 2}, Case{"rays", false, 2}, Case{"map", false, 1}}) {
    json r = request;
    r["options"]["shadow"]["method"] = c.method;
    if (!c.panes) r["scene"]["walls"][0]["openings"] = json::array();
    const rr::RenderRequest view = parse(r);
    const rr::PreparedScene prepared = c.panes ? rr::PreparedScene{} : rr::prepare_scene(view.scene);
    const rr::PreparedScene& drawn = c.panes ? scene : prepared;
    rr::RenderContext fresh;
    fresh.encode = false;
    const rr::RenderOutcome alone = rr::render(view, drawn, fresh);
    rr::ViewCache cache(size_t{1} << 26);
    rr::RenderContext cached = fresh;
    cached.view_cache = &cache;
    const rr::RenderOutcome first = rr::render(view, drawn, cached);
    const rr::RenderOutcome second = rr::render(view, drawn, cached);
    const std::string what = std::string(c.method) + (c.panes ? ", a pane kept" : ", no pane");
    EXPECT_EQ(alone.frame.image.rgb, first.frame.image.rgb) << what;
    EXPECT_EQ(alone.frame.image.rgb, second.frame.image.rgb) << what;
    EXPECT_EQ(alone.frame.ids.ids, second.frame.ids.ids) << what;
    const rr::CacheStats stats = cache.stats();
    EXPECT_EQ(stats.builds, c.entries) << what;
    EXPECT_EQ(stats.entries, c.entries) << what;
    EXPECT_EQ(stats.hits, c.entries) << what << ": the second frame finds what the first made";
    if (c.method == std::string("rays")) {
      EXPECT_GT(first.report.timings.shadow_ms, 0.0) << what << ": the first frame builds the tree (timed as shadow)";
      EXPECT_EQ(second.report.timings.shadow_ms, 0.0) << what << ": the second builds nothing";
    }
  }
}

// --- Sweet Home 3D homes ----------------------------------------------------------------------------

std::optional<json> import_home(const std::string& name) {
  auto dir = rr::testing::shared_data_dir();
  if (!dir) return std::nullopt;
  return rr::import_sweethome3d(rr::testing::read_file(*dir / "floorplans/sweethome3d" / (name + ".xml"))).request;
}

// A camera high above the middle of the home's walls, looking down.
void look_from_above(json& request, double height) {
  double lo_x = 1e9, hi_x = -1e9, lo_z = 1e9, hi_z = -1e9;
  for (const json& w : request["scene"]["walls"]) {
    for (const char* end : {"start", "end"}) {
      lo_x = std::min(lo_x, w[end][0].get<double>()), hi_x = std::max(hi_x, w[end][0].get<double>());
      lo_z = std::min(lo_z, w[end][1].get<double>()), hi_z = std::max(hi_z, w[end][1].get<double>());
    }
  }
  const double cx = 0.5 * (lo_x + hi_x), cz = 0.5 * (lo_z + hi_z);
  request["camera"] = {
      {"position", {cx, height, cz + 0.3 * height}}, {"target", {cx, 0.0, cz}}, {"far", 200.0}, {"fov_y", 60.0}};
}

TEST(RoomsSh3d, ObserverSeesCeilingsOverheadAndAnAerialViewNone) {
  std::optional<json> request = import_home("3BedroomApartment");
  if (!request) GTEST_SKIP() << "../shared/data is absent";
  (*request)["options"] = {{"width", 160}, {"height", 120}};
  const std::set<uint32_t> ceiling = ceiling_ids(*request);
  const Drawn observer = draw(*request);
  // The top rows look above the walls: ceilings there, no background.
  size_t ceiling_pixels = 0, background = 0;
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < observer.frame.ids.width; ++x) {
      const uint32_t id = observer.frame.ids.at(x, y);
      ceiling_pixels += ceiling.count(id);
      background += id == rr::background_id;
    }
  }
  EXPECT_EQ(background, 0u);
  EXPECT_GT(ceiling_pixels, 160u * 6u / 2u);
  look_from_above(*request, 25.0);
  const Drawn aerial = draw(*request);
  EXPECT_EQ(count_in(aerial.ids, ceiling), 0u);
  EXPECT_GT(aerial.ids.size(), 20u);
}

TEST(LevelsSh3d, GroundLevelAloneShowsNothingOfTheUpperLevel) {
  std::optional<json> request = import_home("3BedroomHouseWithAttic");
  if (!request) GTEST_SKIP() << "../shared/data is absent";
  (*request)["options"] = {{"width", 160}, {"height", 120}};
  look_from_above(*request, 30.0);
  // Polygon id -> its element's level index (level0 = 0, level1 = 1), from the whole soup.
  rr::RenderRequest parsed = parse(*request);
  rr::PolygonSoup soup = rr::tessellate(parsed.scene.geometry);
  std::map<uint32_t, int> level_of;
  for (const rr::Polygon& p : soup.polygons) level_of[p.id] = soup.objects[p.object].level;
  auto pixels_on = [&](const Drawn& d, int level) {
    size_t n = 0;
    for (uint32_t id : d.frame.ids.ids) n += id != rr::background_id && level_of.at(id) == level;
    return n;
  };
  ASSERT_EQ(parsed.scene.geometry.levels[1].id, "level1");
  const Drawn viewable = draw(*request);
  EXPECT_GT(pixels_on(viewable, 1), 500u);
  (*request)["options"]["levels"] = {"level0"};
  const Drawn ground = draw(*request);
  EXPECT_EQ(pixels_on(ground, 1), 0u);
  EXPECT_GT(pixels_on(ground, 0), 500u);
}

}  // namespace

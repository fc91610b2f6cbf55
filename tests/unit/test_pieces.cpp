// Pieces of furniture (render/core/solid_piece.cpp): a piece of one unit-cube part draws the box of
// its placement; mirroring and a part's transform move its points as stated; every polygon knows its
// part; the reader's pointers; the scene id hashes the parts; and the placement checks see a piece
// as one body, warn when faces cross (not when hulls merely overlap) and sort by depth.
#include "render/core/placement.hpp"
#include "render/core/scene_id.hpp"
#include "render/core/tessellate.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

namespace rr {
namespace {

using nlohmann::json;

const json unit_cube = rr::testing::unit_cube_mesh();

// A triangle in the plane x = 0 of the unit box, pointing toward +z.
const json wedge = {{"vertices", {{0, -0.5, -0.5}, {0, 0.5, -0.5}, {0, -0.5, 0.5}}}, {"faces", {{0, 1, 2}}}};

json part(const json& mesh, json extra = json::object()) {
  json out = mesh;
  for (auto& [k, v] : extra.items()) out[k] = v;
  return out;
}

RenderRequest parse_scene(const json& scene) { return request_from_json(json{{"scene", scene}}); }

std::multiset<std::vector<double>> rounded_points(const PolygonSoup& soup) {
  std::multiset<std::vector<double>> out;
  for (const Polygon& p : soup.polygons) {
    for (const Vec3& q : soup.points(p))
      out.insert({std::round(q.x * 1e9), std::round(q.y * 1e9), std::round(q.z * 1e9)});
  }
  return out;
}

TEST(Pieces, OneCubePartDrawsTheBoxOfItsPlacement) {
  const json placement = {{"center", {1.5, -2}}, {"base", 0.25}, {"size", {2, 0.8, 0.6}}, {"rotation_y", 30}};
  json piece = placement;
  piece["type"] = "piece";
  piece["parts"] = {part(unit_cube, {{"color", "#ff0000"}})};
  json box = placement;
  box["type"] = "box";
  const PolygonSoup a = tessellate(parse_scene({{"solids", {piece}}}).scene.geometry);
  const PolygonSoup b = tessellate(parse_scene({{"solids", {box}}}).scene.geometry);
  ASSERT_EQ(a.polygons.size(), 6u);
  EXPECT_EQ(rounded_points(a), rounded_points(b));
  ASSERT_EQ(a.objects.size(), 1u);
  EXPECT_FALSE(a.objects[0].closed);  // a model's parts need not bound a volume
  EXPECT_EQ(a.materials[a.polygons[0].material].color, Color(1.0f, 0.0f, 0.0f));
}

// Mirroring flips the unit box's x; a part's transform maps its mesh into the box first.
TEST(Pieces, MirroringAndAPartTransformMoveItsPoints) {
  json piece = {{"type", "piece"}, {"center", {0, 0}}, {"size", {2, 1, 1}}, {"parts", {wedge}}};
  auto xs = [](const json& p) {
    const PolygonSoup soup = tessellate(parse_scene({{"solids", {p}}}).scene.geometry);
    std::vector<double> out;
    for (const Vec3& q : soup.positions) out.push_back(q.x);
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(xs(piece), (std::vector<double>{0, 0, 0}));
  // x' = y + 0.25: the vertices' y (-0.5, 0.5, -0.5) become unit x -0.25, 0.75, -0.25.
  piece["parts"][0]["transform"] = {{0, 1, 0, 0.25}, {0, 0, 1, 0}, {1, 0, 0, 0}};
  EXPECT_EQ(xs(piece), (std::vector<double>{-0.5, -0.5, 1.5}));  // times the width 2
  piece["mirrored"] = true;
  EXPECT_EQ(xs(piece), (std::vector<double>{-1.5, 0.5, 0.5}));
}

TEST(Pieces, EachPolygonKnowsItsPart) {
  const json piece = {{"type", "piece"},
                      {"center", {0, 0}},
                      {"size", {1, 1, 1}},
                      {"parts", {part(unit_cube, {{"name", "body"}}), part(wedge, {{"name", "fin"}})}}};
  const json box = {{"type", "box"}, {"center", {5, 5}}, {"size", {1, 1, 1}}};
  const RenderRequest r = parse_scene({{"solids", {box, piece}}});
  const PolygonSoup soup = tessellate(r.scene.geometry);
  ASSERT_EQ(soup.polygons.size(), 13u);
  for (uint32_t id = 0; id < 6; ++id) EXPECT_EQ(polygon_part(soup, id), -1);  // the box
  for (uint32_t id = 6; id < 12; ++id) EXPECT_EQ(polygon_part(soup, id), 0);
  EXPECT_EQ(polygon_part(soup, 12), 1);
  EXPECT_EQ(soup.polygons[12].object, soup.polygons[6].object) << "one object for the whole piece";
  EXPECT_EQ(r.scene.geometry.solids[1].parts[1].name, "fin");
  // The estimate is a bound made before tessellating: each quad of the cube counts as two triangles.
  EXPECT_EQ(estimate_polygon_count(r.scene.geometry), 6u + 12u + 1u);
}

TEST(Pieces, TheReaderPointsAtTheBadMember) {
  auto error_at = [](const json& piece) {
    try {
      parse_scene({{"solids", {piece}}});
    } catch (const InputError& e) {
      return e.pointer();
    }
    return std::string("accepted");
  };
  json piece = {{"type", "piece"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"parts", {wedge}}};
  EXPECT_EQ(error_at(piece), "accepted");
  json none = piece;
  none["parts"] = json::array();
  EXPECT_EQ(error_at(none), "/scene/solids/0/parts");
  json flat = piece;
  flat["parts"][0]["transform"] = {{1, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 1, 0}};
  EXPECT_EQ(error_at(flat), "/scene/solids/0/parts/0/transform");
  json short_row = piece;
  short_row["parts"][0]["transform"] = {{1, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  EXPECT_EQ(error_at(short_row), "/scene/solids/0/parts/0/transform/0");
  json unknown = piece;
  unknown["parts"][0]["position"] = {0, 0, 0};
  EXPECT_EQ(error_at(unknown), "/scene/solids/0/parts/0/position");
  json ref = piece;
  ref["parts"][0] = {{"ref", "0123456789abcdef"}};
  EXPECT_EQ(error_at(ref), "/scene/solids/0/parts/0/ref");  // no mesh is stored here
  json no_size = piece;
  no_size.erase("size");
  EXPECT_EQ(error_at(no_size), "/scene/solids/0");  // a missing key is said at its object
}

TEST(Pieces, TheSceneIdHashesTheParts) {
  const json piece = {{"type", "piece"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"parts", {wedge}}};
  const std::string id = scene_id(parse_scene({{"solids", {piece}}}).scene.geometry);
  for (const auto& [key, value] : std::vector<std::pair<std::string, json>>{
           {"color", "#ff0000"}, {"transform", {{1, 0, 0, 0.1}, {0, 1, 0, 0}, {0, 0, 1, 0}}}}) {
    json changed = piece;
    changed["parts"][0][key] = value;
    EXPECT_NE(scene_id(parse_scene({{"solids", {changed}}}).scene.geometry), id) << key;
  }
  json mirrored = piece;
  mirrored["mirrored"] = true;
  EXPECT_NE(scene_id(parse_scene({{"solids", {mirrored}}}).scene.geometry), id);
  json named = piece;
  named["parts"][0]["name"] = "a name draws nothing";
  EXPECT_EQ(scene_id(parse_scene({{"solids", {named}}}).scene.geometry), id);
}

// --- placement checks on pieces --------------------------------------------------------------------

// A table 1.2 x 0.75 x 0.8 m: a 4 cm top on four 5 cm legs, one part each, in its unit box.
json table_piece(double x, double z) {
  const double top = 0.04 / 0.75;  // the top's share of the height
  auto slab = [](double x0, double y0, double z0, double x1, double y1, double z1) {
    return json{
        {"transform",
         {{x1 - x0, 0, 0, 0.5 * (x0 + x1)}, {0, y1 - y0, 0, 0.5 * (y0 + y1)}, {0, 0, z1 - z0, 0.5 * (z0 + z1)}}}};
  };
  json parts = {part(unit_cube, slab(-0.5, 0.5 - top, -0.5, 0.5, 0.5, 0.5))};
  const double lx = 0.05 / 1.2, lz = 0.05 / 0.8;
  for (double sx : {-1.0, 1.0}) {
    for (double sz : {-1.0, 1.0}) {
      const double cx = sx * (0.5 - lx / 2), cz = sz * (0.5 - lz / 2);
      parts.push_back(part(unit_cube, slab(cx - lx / 2, -0.5, cz - lz / 2, cx + lx / 2, 0.5 - top, cz + lz / 2)));
    }
  }
  return {{"type", "piece"}, {"id", "table"}, {"center", {x, z}}, {"size", {1.2, 0.75, 0.8}}, {"parts", parts}};
}

std::vector<WarningText> warnings_of(const json& scene, PlacementLimits limits = {}) {
  const RenderRequest r = parse_scene(scene);
  return describe(placement_warnings(r.scene, tessellate(r.scene.geometry), limits), r.scene);
}

TEST(PlacementOfPieces, AChairTuckedUnderATableIsQuietOneThroughItWarnsOnce) {
  // A 0.4 m stool block under the table top, between its legs: the hulls overlap, no faces cross.
  const json stool = {{"type", "box"}, {"id", "stool"}, {"center", {0.1, 0.1}}, {"size", {0.4, 0.45, 0.4}}};
  EXPECT_TRUE(warnings_of({{"solids", {table_piece(0, 0), stool}}}).empty());
  // A tall one goes through the top: one warning for the pair, not one per part.
  json tall = stool;
  tall["size"] = {0.4, 1.0, 0.4};
  auto warnings = warnings_of({{"solids", {table_piece(0, 0), tall}}});
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].pointer, "/scene/solids/1");
  EXPECT_EQ(warnings[0].other, "/scene/solids/0");
  // The depth is the hulls': the stool stands wholly inside the table's plan (0.4 m).
  EXPECT_EQ(warnings[0].detail, "solid intersects piece /scene/solids/0 (\"table\") by 0.4 m");
  // A higher table pushed into this one (their tops cross): one warning naming pieces on both sides.
  json higher = table_piece(0.5, 0);
  higher["size"][1] = 0.76;
  warnings = warnings_of({{"solids", {table_piece(0, 0), higher}}});
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].pointer, "/scene/solids/1");
  EXPECT_EQ(warnings[0].detail, "piece intersects piece /scene/solids/0 (\"table\") by 0.7 m");
}

TEST(PlacementOfPieces, ABoxInsideAClosedBoxStillWarns) {
  const json outer = {{"type", "box"}, {"center", {0, 0}}, {"size", {2, 2, 2}}};
  const json inner = {{"type", "box"}, {"center", {0.2, 0}}, {"base", 0.5}, {"size", {0.5, 0.5, 0.5}}};
  ASSERT_EQ(warnings_of({{"solids", {outer, inner}}}).size(), 1u);
  // An open piece holds nothing: the same cube as a piece's part, then the small box inside it.
  json open = {{"type", "piece"}, {"center", {0, 0}}, {"size", {2, 2, 2}}, {"parts", {unit_cube}}};
  EXPECT_TRUE(warnings_of({{"solids", {open, inner}}}).empty());
}

TEST(PlacementOfPieces, DeepestFirstCappedWithTheTotal) {
  // Three pairs of 1 m boxes overlapping by 0.1, 0.2 and 0.3 m, the shallowest first in element order.
  json solids = json::array();
  for (double x : {0.0, 0.9, 10.0, 10.8, 20.0, 20.7})
    solids.push_back({{"type", "box"}, {"center", {x, 0}}, {"size", {1, 1, 1}}});
  PlacementLimits limits;
  limits.max_warnings = 2;
  const RenderRequest r = parse_scene({{"solids", solids}});
  const std::vector<PlacementWarning> typed = placement_warnings(r.scene, tessellate(r.scene.geometry), limits);
  ASSERT_EQ(typed.size(), 3u);
  EXPECT_EQ(typed[0].element, ElementRef::solid(5));
  EXPECT_NEAR(typed[0].depth_m, 0.3, 1e-9);
  EXPECT_EQ(typed[1].element, ElementRef::solid(3));
  EXPECT_NEAR(typed[1].depth_m, 0.2, 1e-9);
  EXPECT_EQ(typed[2].issue, PlacementIssue::more_problems);
  EXPECT_EQ(typed[2].count, 1u);
  EXPECT_EQ(placement_problem_count(typed), 3u);
}

}  // namespace
}  // namespace rr

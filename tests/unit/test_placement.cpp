// The placement checks on hand-placed boxes, walls and openings (render/core/placement.hpp): what
// they warn of, deepest first, the cap on their number, and pointers relative to the document
// holding the scene. Pieces of furniture: test_pieces.cpp.
#include "render/core/placement.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "render/scene_io/scene_json.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

std::vector<rr::WarningText> warnings_for(const std::string& scene_json) {
  rr::RenderRequest request = rr::parse_request("{\"scene\": " + scene_json + "}");
  rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  return rr::describe(rr::placement_warnings(request.scene, soup), request.scene);
}

TEST(Placement, OverlappingSolidsWarnTouchingOnesDoNot) {
  auto warnings = warnings_for(R"({"solids": [
      {"type": "box", "center": [0, 0], "size": [1, 1, 1]},
      {"type": "box", "center": [1, 0], "size": [1, 1, 1]},
      {"type": "box", "center": [0, 0.9], "size": [1, 1, 1], "id": "b"},
      {"type": "box", "center": [5, 5], "base": 2, "size": [1, 1, 1]},
      {"type": "box", "center": [5, 5], "size": [1, 1, 1]}]})");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].pointer, "/scene/solids/2");
  EXPECT_EQ(warnings[0].detail, "solid intersects solid /scene/solids/0 by 0.1 m");
}

TEST(Placement, SolidThroughAWallAndBeyondTheFloor) {
  auto warnings = warnings_for(R"({"floor": {"cells": [4, 4]},
      "walls": [{"start": [0, 2], "end": [4, 2]}],
      "solids": [{"type": "cylinder", "center": [1, 2.05], "radius": 0.3, "height": 1, "id": "pillar"},
                 {"type": "box", "center": [3.6, 0.5], "size": [1, 1, 1]},
                 {"type": "box", "center": [3, 3], "size": [1, 1, 1]}]})");
  // Deepest first: the pillar reaches 0.15 m into the wall, the box 0.1 m beyond the floor.
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].pointer, "/scene/solids/0");
  EXPECT_EQ(warnings[0].detail, "solid intersects wall /scene/walls/0 by 0.15 m");
  EXPECT_EQ(warnings[0].other, "/scene/walls/0");
  EXPECT_NEAR(warnings[0].depth_m, 0.15, 1e-9);
  EXPECT_EQ(warnings[1].pointer, "/scene/solids/1");
  EXPECT_EQ(warnings[1].detail, "solid reaches 0.1 m beyond the floor's edge");
  EXPECT_EQ(warnings[1].other, "");
}

TEST(Placement, OpeningsTooCloseToAWallEndOrEachOther) {
  auto warnings = warnings_for(R"({"walls": [{"start": [0, 0], "end": [5, 0], "openings": [
      {"type": "door", "offset": 0.04, "width": 0.9},
      {"type": "window", "offset": 0.97, "width": 1},
      {"type": "window", "offset": 3, "width": 1.97}]}]})");
  // Deepest first (what each lacks of the 5 cm: 2, 2 and 1 cm), ties in wall order.
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_EQ(warnings[0].pointer, "/scene/walls/0/openings/1");
  EXPECT_EQ(warnings[0].detail, "opening is 0.03 m from opening /scene/walls/0/openings/0 (less than 0.05 m)");
  EXPECT_EQ(warnings[0].other, "/scene/walls/0/openings/0");
  EXPECT_EQ(warnings[1].pointer, "/scene/walls/0/openings/2");
  EXPECT_EQ(warnings[1].detail, "opening is 0.03 m from its wall's end (less than 0.05 m)");
  EXPECT_EQ(warnings[2].pointer, "/scene/walls/0/openings/0");
  EXPECT_EQ(warnings[2].detail, "opening is 0.04 m from its wall's start (less than 0.05 m)");
}

TEST(Placement, WarningsAreCappedWithASummary) {
  std::string solids;
  for (int i = 0; i < 20; ++i)
    solids += std::string(i ? "," : "") + R"({"type": "box", "center": [0, 0], "size": [1, 1, 1]})";
  rr::RenderRequest request = rr::parse_request("{\"scene\": {\"solids\": [" + solids + "]}}");
  rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  rr::PlacementLimits limits;
  limits.max_warnings = 5;
  auto warnings = rr::describe(rr::placement_warnings(request.scene, soup, limits), request.scene);
  ASSERT_EQ(warnings.size(), 6u);
  EXPECT_EQ(warnings.back().pointer, "/scene");
  EXPECT_EQ(warnings.back().detail, "placement checks found more problems; 185 further warning(s) not listed");
}

// The same warnings name elements relative to where the scene sits: a stored scene document is the
// scene itself, so its pointers have no "/scene" prefix.
TEST(Placement, PointersFollowTheDocumentThatHoldsTheScene) {
  rr::RenderRequest request =
      rr::parse_request(R"({"scene": {"walls": [{"start": [0, 0], "end": [4, 0], "id": "north"}],
      "solids": [{"type": "box", "center": [1, 0], "size": [1, 1, 1]}]}})");
  rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  auto typed = rr::placement_warnings(request.scene, soup);
  ASSERT_EQ(typed.size(), 1u);
  EXPECT_EQ(typed[0].issue, rr::PlacementIssue::intersects);
  EXPECT_EQ(typed[0].element, rr::ElementRef::solid(0));
  EXPECT_EQ(typed[0].other, rr::ElementRef::wall(0));
  rr::WarningText stored = rr::describe(typed[0], request.scene, "");
  EXPECT_EQ(stored.pointer, "/solids/0");
  // The wall's whole 0.15 m thickness lies inside the box's depth.
  EXPECT_EQ(stored.detail, "solid intersects wall /walls/0 (\"north\") by 0.15 m");
  EXPECT_EQ(stored.other, "/walls/0");
}

}  // namespace

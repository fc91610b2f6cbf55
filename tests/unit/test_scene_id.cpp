// scene_id: the static geometry's canonical binary hash. One scene written differently in JSON
// (number spelling, key order, defaults omitted or spelt out, -0) keeps one id; camera, lights,
// background and names do not count; every member the tessellator reads does.
#include "render/core/scene_id.hpp"
#include "render/scene_io/scene_json.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

namespace rr {
namespace {

std::string id_of(const std::string& text) { return scene_id(parse_request(text).scene.geometry); }

TEST(SceneId, NumberSpellingDoesNotMatter) {
  EXPECT_EQ(id_of(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0],"height":3}]}})"),
            id_of(R"({"scene":{"walls":[{"start":[0.0,0e0],"end":[4.0,0],"height":3.0}]}})"));
  EXPECT_EQ(id_of(R"({"scene":{"walls":[{"start":[-0.0,0],"end":[4,-0]}]}})"),
            id_of(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0]}]}})"))
      << "-0 and 0 draw alike";
  EXPECT_EQ(
      id_of(R"({"scene":{"solids":[{"type":"cylinder","center":[0,0],"radius":1,"height":1,"segments":12}]}})"),
      id_of(R"({"scene":{"solids":[{"type":"cylinder","center":[0,0],"radius":1,"height":1,"segments":12.0}]}})"));
}

TEST(SceneId, SpeltOutDefaultsEqualOmittedOnes) {
  EXPECT_EQ(id_of(R"({"scene":{"floor":{"cells":[2,2]}}})"),
            id_of(R"({"scene":{"floor":{"cells":[2,2],"cell_size":1,"colors":["#D9D4C7","#8c8579"],
                                       "material":{"specular":0,"shininess":32}}}})"));
  EXPECT_EQ(id_of(R"({"scene":{"solids":[{"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2]]}]}})"),
            id_of(R"({"scene":{"solids":[{"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2]],
                                          "smooth":false,"closed":false,"scale":[1,1,1],"position":[0,0,0]}]}})"));
  // Empty members behave as absent ones.
  EXPECT_EQ(id_of(R"({"scene":{},"camera":{},"options":{}})"), id_of("{}"));
}

TEST(SceneId, KeyOrderAndNamesDoNotMatter) {
  EXPECT_EQ(id_of(R"({"scene":{"walls":[{"id":"north","start":[0,0],"end":[4,0],"height":3}]}})"),
            id_of(R"({"scene":{"walls":[{"height":3,"end":[4,0],"start":[0,0],"id":"south"}]}})"));
  EXPECT_EQ(id_of(R"({"scene":{"solids":[{"type":"box","id":"a","center":[1,2],"size":[1,1,1]}]}})"),
            id_of(R"({"scene":{"solids":[{"size":[1,1,1],"center":[1,2],"type":"box"}]}})"));
}

TEST(SceneId, CameraLightsAndBackgroundDoNotMatter) {
  const std::string walls = R"("walls":[{"start":[0,0],"end":[4,0]}])";
  EXPECT_EQ(id_of("{\"scene\":{" + walls + "}}"),
            id_of("{\"scene\":{" + walls + R"(,"background":"#ff0000","ambient":{"intensity":1},
                  "lights":[{"type":"point","position":[0,2,0]}]},
                  "camera":{"position":[3,3,3]},"options":{"width":10}})"));
}

TEST(SceneId, GeometryChangesDoMatter) {
  std::string base = id_of(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0]}]}})");
  EXPECT_NE(base, id_of(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0.5]}]}})"));
  EXPECT_NE(base, id_of(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0],"color":"#000000"}]}})"));
  EXPECT_NE(base, id_of(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0]}],"floor":{"cells":[1,1]}}})"));
  EXPECT_NE(base, id_of(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0]},{"start":[0,0],"end":[4,0]}]}})"));
  EXPECT_EQ(base.size(), 16u);
  EXPECT_EQ(base.find_first_not_of("0123456789abcdef"), std::string::npos) << base;
}

// The same indices in the same order, grouped into faces differently, are different meshes.
TEST(SceneId, LengthsSeparateNeighbouringLists) {
  auto mesh = [](std::vector<std::vector<uint32_t>> faces) {
    StaticGeometry g;
    Solid s;
    s.type = SolidType::mesh;
    std::vector<Vec3> vertices(6, Vec3(0.0));
    for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = Vec3(double(i), double(i * i), 1.0);
    s.mesh = make_mesh_data(vertices, std::move(faces), {});
    g.solids.push_back(s);
    return scene_id(g);
  };
  EXPECT_NE(mesh({{0, 1, 2}, {3, 4, 5}}), mesh({{0, 1, 2, 3}, {4, 5}}));
  EXPECT_NE(mesh({{0, 1, 2, 3, 4}, {5}}), mesh({{0, 1, 2}, {3, 4, 5}}));
  EXPECT_EQ(mesh({{0, 1, 2}, {3, 4, 5}}), mesh({{0, 1, 2}, {3, 4, 5}}));
}

// A geometry using every struct: floor, a wall with a door and a window, and one solid of each type (a
// piece of two parts).
StaticGeometry every_kind() {
  StaticGeometry g;
  g.has_floor = true;
  g.floor.colors = {Color(0.1f), Color(0.9f)};
  Wall wall;
  wall.end = {5.0, 0.0};
  Opening door, window;
  window.type = OpeningType::window;
  window.sill = 0.9;
  window.offset = 2.5;
  wall.openings = {door, window};
  g.walls = {wall};
  for (SolidType type :
       {SolidType::box, SolidType::cylinder, SolidType::pyramid, SolidType::prism, SolidType::mesh, SolidType::piece}) {
    Solid s;
    s.type = type;
    s.points = {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
    if (type == SolidType::mesh)
      s.mesh = make_mesh_data({{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}}, {{0, 1, 2}}, {});
    if (type == SolidType::piece) {
      PiecePart part;
      part.mesh = make_mesh_data({{0.0, 0.0, 0.0}, {0.5, 0.0, 0.0}, {0.0, 0.5, 0.0}}, {{0, 1, 2}}, {});
      s.parts = {part, part};
    }
    g.solids.push_back(s);
  }
  return g;
}

// Every member the tessellator reads changes the id, for each struct it sits in: a struct-level
// test, so a member dropped from the hash fails here even where the parser cannot reach it.
TEST(SceneId, EveryDrawnMemberCounts) {
  using Edit = std::function<void(StaticGeometry&)>;
  auto solid = [](size_t i, std::function<void(Solid&)> edit) {
    return Edit([=](StaticGeometry& g) { edit(g.solids[i]); });
  };
  auto opening = [](size_t i, std::function<void(Opening&)> edit) {
    return Edit([=](StaticGeometry& g) { edit(g.walls[0].openings[i]); });
  };
  const std::vector<std::pair<const char*, Edit>> edits = {
      {"has_floor", [](StaticGeometry& g) { g.has_floor = false; }},
      {"floor.origin", [](StaticGeometry& g) { g.floor.origin.x = 0.5; }},
      {"floor.cells_x", [](StaticGeometry& g) { g.floor.cells_x = 2; }},
      {"floor.cells_z", [](StaticGeometry& g) { g.floor.cells_z = 2; }},
      {"floor.cell_size", [](StaticGeometry& g) { g.floor.cell_size = 0.5; }},
      {"floor.elevation", [](StaticGeometry& g) { g.floor.elevation = 0.1; }},
      {"floor.colors", [](StaticGeometry& g) { g.floor.colors.push_back(Color(0.5f)); }},
      {"floor.material.specular", [](StaticGeometry& g) { g.floor.material.specular = 0.5f; }},
      {"floor.material.specular_color", [](StaticGeometry& g) { g.floor.material.specular_color.g = 0.0f; }},
      {"floor.material.shininess", [](StaticGeometry& g) { g.floor.material.shininess = 8.0f; }},
      {"wall.start", [](StaticGeometry& g) { g.walls[0].start.y = -1.0; }},
      {"wall.end", [](StaticGeometry& g) { g.walls[0].end.x = 6.0; }},
      {"wall.thickness", [](StaticGeometry& g) { g.walls[0].thickness = 0.2; }},
      {"wall.height", [](StaticGeometry& g) { g.walls[0].height = 3.0; }},
      {"wall.base", [](StaticGeometry& g) { g.walls[0].base = 0.1; }},
      {"wall.color", [](StaticGeometry& g) { g.walls[0].color.r = 0.0f; }},
      {"wall.material", [](StaticGeometry& g) { g.walls[0].material.specular = 0.2f; }},
      {"door.type", opening(0, [](Opening& o) { o.type = OpeningType::window; })},
      {"door.offset", opening(0, [](Opening& o) { o.offset = 0.2; })},
      {"door.width", opening(0, [](Opening& o) { o.width = 1.0; })},
      {"door.height", opening(0, [](Opening& o) { o.height = 2.1; })},
      {"door.color", opening(0, [](Opening& o) { o.color.b = 1.0f; })},
      {"door.leaf", opening(0, [](Opening& o) { o.leaf = false; })},
      {"window.sill", opening(1, [](Opening& o) { o.sill = 1.0; })},
      {"window.opacity", opening(1, [](Opening& o) { o.opacity = 0.5f; })},
      {"box.type", solid(0, [](Solid& s) { s.type = SolidType::pyramid; })},
      {"box.color", solid(0, [](Solid& s) { s.color.r = 0.1f; })},
      {"box.material", solid(0, [](Solid& s) { s.material.shininess = 4.0f; })},
      {"box.center", solid(0, [](Solid& s) { s.center.y = 1.0; })},
      {"box.base", solid(0, [](Solid& s) { s.base = 1.0; })},
      {"box.rotation_y", solid(0, [](Solid& s) { s.rotation_y_deg = 45.0; })},
      {"box.size", solid(0, [](Solid& s) { s.size.y = 2.0; })},
      {"cylinder.radius", solid(1, [](Solid& s) { s.radius = 0.25; })},
      {"cylinder.height", solid(1, [](Solid& s) { s.height = 2.0; })},
      {"cylinder.segments", solid(1, [](Solid& s) { s.segments = 16; })},
      {"cylinder.smooth", solid(1, [](Solid& s) { s.smooth = false; })},
      {"cylinder.caps", solid(1, [](Solid& s) { s.caps = false; })},
      {"prism.points", solid(3, [](Solid& s) { s.points[2].x = 0.5; })},
      {"mesh.vertices", solid(4,
                              [](Solid& s) {
                                s.mesh = make_mesh_data({{0, 0, 0}, {1, 0, 0.5}, {0, 1, 0}}, {{0, 1, 2}}, {});
                              })},
      {"mesh.faces", solid(4,
                           [](Solid& s) {
                             s.mesh = make_mesh_data({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 2, 1}}, {});
                           })},
      {"mesh.normals", solid(4,
                             [](Solid& s) {
                               s.mesh = make_mesh_data({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}},
                                                       std::vector<Vec3>(3, Vec3(0, 0, 1)));
                             })},
      {"mesh.position", solid(4, [](Solid& s) { s.position.x = 1.0; })},
      {"mesh.scale", solid(4, [](Solid& s) { s.scale.z = 2.0; })},
      {"mesh.closed", solid(4, [](Solid& s) { s.closed = true; })},
      {"piece.mirrored", solid(5, [](Solid& s) { s.mirrored = true; })},
      {"piece.parts", solid(5, [](Solid& s) { s.parts.pop_back(); })},
      {"part.mesh", solid(5,
                          [](Solid& s) {
                            s.parts[1].mesh = make_mesh_data({{0, 0, 0}, {0.5, 0, 0}, {0, 0, 0.5}}, {{0, 1, 2}}, {});
                          })},
      {"part.color", solid(5, [](Solid& s) { s.parts[1].color.g = 0.1f; })},
      {"part.material", solid(5, [](Solid& s) { s.parts[1].material.specular = 0.3f; })},
      {"part.transformed", solid(5, [](Solid& s) { s.parts[1].transformed = true; })},
      {"part.linear", solid(5, [](Solid& s) { s.parts[1].linear[2][0] = 0.5; })},
      {"part.offset", solid(5, [](Solid& s) { s.parts[1].offset.y = 0.25; })},
      {"solids order", [](StaticGeometry& g) { std::swap(g.solids[0], g.solids[1]); }},
  };
  const std::string base = scene_id(every_kind());
  for (const auto& [name, edit] : edits) {
    StaticGeometry g = every_kind();
    edit(g);
    EXPECT_NE(scene_id(g), base) << name;
  }
}

TEST(SceneId, WhatDrawsNothingDoesNotCount) {
  const std::string base = scene_id(every_kind());
  StaticGeometry renamed = every_kind();
  renamed.floor.id = "floor";
  renamed.walls[0].id = "north";
  renamed.walls[0].openings[1].id = "window";
  renamed.solids[2].id = "pyramid";
  renamed.solids[5].parts[0].name = "seat";
  EXPECT_EQ(scene_id(renamed), base);
  StaticGeometry no_floor = every_kind(), other_unused_floor = every_kind();
  no_floor.has_floor = other_unused_floor.has_floor = false;
  other_unused_floor.floor.cells_x = 7;
  EXPECT_EQ(scene_id(no_floor), scene_id(other_unused_floor));
  StaticGeometry negative_zero = every_kind();
  negative_zero.walls[0].start = {-0.0, -0.0};
  negative_zero.solids[0].color.g = -0.0f;  // not a valid colour, but it must hash as 0 does
  StaticGeometry zero = every_kind();
  zero.solids[0].color.g = 0.0f;
  EXPECT_EQ(scene_id(negative_zero), scene_id(zero));
}

}  // namespace
}  // namespace rr

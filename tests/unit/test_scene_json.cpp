// scene_json: JSON text -> RenderRequest. Checks the documented defaults (docs/scene-format.md), that
// every class of error carries its exact kind and JSON Pointer, and that hostile bodies (deep nesting,
// huge images) are refused quickly. The scene id's properties are tested in test_scene_id.cpp.
#include "render/core/scene_id.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace rr {
namespace {

using Kind = InputError::Kind;
using nlohmann::json;

struct Failure {
  Kind kind = Kind::malformed;
  std::string pointer;
  std::string detail;
};

// The error parse_request raises for `text`; a test failure when it accepts the text.
Failure failure_of(std::string_view text, const ParseLimits& limits = {}) {
  try {
    parse_request(text, limits);
  } catch (const InputError& e) {
    return {e.kind(), e.pointer(), e.what()};
  }
  ADD_FAILURE() << "accepted: " << text.substr(0, 200);
  return {Kind::malformed, "<accepted>", ""};
}

void expect_error(std::string_view text, Kind kind, const std::string& pointer, const std::string& detail_part = "",
                  const ParseLimits& limits = {}) {
  SCOPED_TRACE(std::string(text.substr(0, 200)));
  Failure f = failure_of(text, limits);
  EXPECT_EQ(f.kind, kind) << f.detail;
  EXPECT_EQ(f.pointer, pointer) << f.detail;
  EXPECT_NE(f.detail.find(detail_part), std::string::npos) << f.detail;
}

// A request whose scene holds one wall from (0,0) to (5,0), 2.5 m high, with the given openings.
std::string wall_with_openings(const std::string& openings) {
  return R"({"scene":{"walls":[{"start":[0,0],"end":[5,0],"openings":[)" + openings + "]}]}}";
}

std::string one_solid(const std::string& solid) { return R"({"scene":{"solids":[)" + solid + "]}}"; }

std::string camera(const std::string& members) { return R"({"camera":{)" + members + "}}"; }

Color hex_color(int r, int g, int b) { return Color(float(r) / 255.f, float(g) / 255.f, float(b) / 255.f); }

// CPU milliseconds this thread has spent since `start` (a thread_cpu_ms() reading).
double cpu_ms_since(double start) { return rr::testing::thread_cpu_ms() - start; }

// --- defaults ------------------------------------------------------------------------------------------

TEST(SceneJson, EmptyRequestGetsDocumentedDefaults) {
  RenderRequest r = parse_request("{}");
  EXPECT_FALSE(r.scene.geometry.has_floor);
  EXPECT_TRUE(r.scene.geometry.walls.empty());
  EXPECT_TRUE(r.scene.geometry.solids.empty());
  EXPECT_TRUE(r.scene.lights.empty());
  EXPECT_EQ(r.scene.background, Color(0.0f));
  EXPECT_EQ(r.scene.ambient.color, Color(1.0f));
  EXPECT_FLOAT_EQ(r.scene.ambient.intensity, 0.2f);
  EXPECT_EQ(r.camera.position, Vec3(0.0, 1.6, 5.0));
  EXPECT_EQ(r.camera.target, Vec3(0.0, 1.0, 0.0));
  EXPECT_EQ(r.camera.up, Vec3(0.0, 1.0, 0.0));
  EXPECT_EQ(r.camera.fov_y_deg, 60.0);
  EXPECT_EQ(r.camera.near, 0.1);
  EXPECT_EQ(r.camera.far, 100.0);
  EXPECT_EQ(r.options.width, 640);
  EXPECT_EQ(r.options.height, 480);
  EXPECT_EQ(r.options.pipeline, pipeline_id("zbuffer"));
  EXPECT_EQ(r.options.shading, ShadingMode::flat);
  // Empty members behave as absent ones.
  RenderRequest empty_members = parse_request(R"({"scene":{},"camera":{},"options":{}})");
  EXPECT_EQ(scene_id(empty_members.scene.geometry), scene_id(r.scene.geometry));
  EXPECT_EQ(empty_members.options.width, 640);
}

TEST(SceneJson, MinimalFloorGetsDefaults) {
  Floor f = parse_request(R"({"scene":{"floor":{"cells":[2,3]}}})").scene.geometry.floor;
  EXPECT_EQ(f.cells_x, 2);
  EXPECT_EQ(f.cells_z, 3);
  EXPECT_EQ(f.origin, Vec2(0.0, 0.0));
  EXPECT_EQ(f.cell_size, 1.0);
  EXPECT_EQ(f.elevation, 0.0);
  ASSERT_EQ(f.colors.size(), 2u);
  EXPECT_EQ(f.colors[0], hex_color(0xd9, 0xd4, 0xc7));
  EXPECT_EQ(f.colors[1], hex_color(0x8c, 0x85, 0x79));
  EXPECT_EQ(f.material.specular, 0.0f);
  EXPECT_EQ(f.material.shininess, 32.0f);
}

TEST(SceneJson, MinimalWallGetsDefaults) {
  RenderRequest r = parse_request(R"({"scene":{"walls":[{"start":[0,0],"end":[4,0]}]}})");
  ASSERT_EQ(r.scene.geometry.walls.size(), 1u);
  const Wall& w = r.scene.geometry.walls[0];
  EXPECT_EQ(w.end, Vec2(4.0, 0.0));
  EXPECT_EQ(w.thickness, 0.15);
  EXPECT_EQ(w.height, 2.5);
  EXPECT_EQ(w.base, 0.0);
  EXPECT_EQ(w.color, hex_color(0xe6, 0xe1, 0xd6));
  EXPECT_TRUE(w.openings.empty());
}

TEST(SceneJson, DoorAndWindowDefaultsDependOnType) {
  RenderRequest r = parse_request(
      wall_with_openings(R"({"type":"door","offset":0.5,"width":0.9},{"type":"window","offset":2,"width":1})"));
  const auto& openings = r.scene.geometry.walls.at(0).openings;
  ASSERT_EQ(openings.size(), 2u);
  const Opening& door = openings[0];
  EXPECT_EQ(door.type, OpeningType::door);
  EXPECT_EQ(door.height, 2.0);
  EXPECT_EQ(door.sill, 0.0);
  EXPECT_EQ(door.color, hex_color(0x8b, 0x5a, 0x2b));
  EXPECT_EQ(door.opacity, 1.0f);
  EXPECT_TRUE(door.leaf);
  const Opening& window = openings[1];
  EXPECT_EQ(window.type, OpeningType::window);
  EXPECT_EQ(window.height, 1.2);
  EXPECT_EQ(window.sill, 0.9);
  EXPECT_EQ(window.color, hex_color(0xa8, 0xc8, 0xe8));
  EXPECT_FLOAT_EQ(window.opacity, 0.35f);
}

TEST(SceneJson, SolidDefaultsDependOnType) {
  RenderRequest r = parse_request(R"({"scene":{"solids":[
    {"type":"box","center":[1,2],"size":[1,2,3]},
    {"type":"cylinder","center":[0,0],"radius":0.5,"height":1},
    {"type":"pyramid","center":[0,0],"size":[1,1,1]},
    {"type":"prism","points":[[0,0],[1,0],[0,1]],"height":2},
    {"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2]]}]}})");
  const auto& s = r.scene.geometry.solids;
  ASSERT_EQ(s.size(), 5u);
  EXPECT_EQ(s[0].type, SolidType::box);
  EXPECT_EQ(s[0].center, Vec2(1.0, 2.0));
  EXPECT_EQ(s[0].base, 0.0);
  EXPECT_EQ(s[0].rotation_y_deg, 0.0);
  EXPECT_EQ(s[0].size, Vec3(1.0, 2.0, 3.0));
  EXPECT_EQ(s[1].segments, 32);
  EXPECT_TRUE(s[1].smooth);
  EXPECT_TRUE(s[1].caps);
  EXPECT_EQ(s[2].type, SolidType::pyramid);
  EXPECT_EQ(s[3].points.size(), 3u);
  EXPECT_EQ(s[3].base, 0.0);
  EXPECT_EQ(s[4].type, SolidType::mesh);
  EXPECT_FALSE(s[4].smooth);
  EXPECT_FALSE(s[4].closed);
  EXPECT_EQ(s[4].scale, Vec3(1.0));
  EXPECT_EQ(s[4].position, Vec3(0.0));
  EXPECT_EQ(s[4].mesh->faces, (std::vector<std::vector<uint32_t>>{{0, 1, 2}}));
  for (const Solid& solid : s) EXPECT_EQ(solid.material.shininess, 32.0f);
}

TEST(SceneJson, LightDefaultsAndUnitDirection) {
  RenderRequest r = parse_request(R"({"scene":{"lights":[
    {"type":"directional","direction":[0,-3,4]},
    {"type":"directional"},
    {"type":"point","position":[1,2,3]}]}})");
  const auto& lights = r.scene.lights;
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_NEAR(lights[0].direction.y, -0.6, 1e-15);
  EXPECT_NEAR(lights[0].direction.z, 0.8, 1e-15);
  EXPECT_EQ(lights[0].intensity, 1.0f);
  EXPECT_EQ(lights[0].color, Color(1.0f));
  EXPECT_EQ(lights[1].direction, Vec3(0.0, -1.0, 0.0));
  EXPECT_EQ(lights[2].type, LightType::point);
  EXPECT_EQ(lights[2].position, Vec3(1.0, 2.0, 3.0));
  EXPECT_EQ(lights[2].attenuation, Vec3(1.0, 0.0, 0.0));
}

TEST(SceneJson, ColoursAsHexInAnyCaseOrArrays) {
  RenderRequest r = parse_request(R"({"scene":{"background":"#FF8000","ambient":{"color":[1,0.5,0]},
    "floor":{"cells":[1,1],"colors":["#ff8000","#0a0B0c"]}}})");
  EXPECT_EQ(r.scene.background, hex_color(255, 128, 0));
  EXPECT_EQ(r.scene.ambient.color, Color(1.0f, 0.5f, 0.0f));
  EXPECT_EQ(r.scene.geometry.floor.colors[0], hex_color(255, 128, 0));
  EXPECT_EQ(r.scene.geometry.floor.colors[1], hex_color(10, 11, 12));
  expect_error(R"({"scene":{"background":"#ff800"}})", Kind::invalid, "/scene/background", "#rrggbb");
  expect_error(R"({"scene":{"background":"#gg8000"}})", Kind::invalid, "/scene/background");
  expect_error(R"({"scene":{"background":[1,2,0]}})", Kind::invalid, "/scene/background/1", "at most 1");
  expect_error(R"({"scene":{"background":[1,0]}})", Kind::invalid, "/scene/background");
}

TEST(SceneJson, EveryExampleParses) {
  auto files = testing::example_files();
  EXPECT_FALSE(files.empty());
  for (const auto& file : files) {
    SCOPED_TRACE(file.string());
    EXPECT_NO_THROW(parse_request(testing::read_file(file)));
  }
}

// --- schema errors -------------------------------------------------------------------------------------

TEST(SceneJsonErrors, UnknownKeysAnywhere) {
  expect_error(R"({"scene":{},"extra":1})", Kind::invalid, "/extra", "unknown key");
  expect_error(wall_with_openings(R"({"type":"door","offset":0,"width":1,"frame":"oak"})"), Kind::invalid,
               "/scene/walls/0/openings/0/frame", "unknown key");
  // A door has no sill: the key belongs to windows only.
  expect_error(wall_with_openings(R"({"type":"door","offset":0,"width":1,"sill":0.5})"), Kind::invalid,
               "/scene/walls/0/openings/0/sill", "unknown key");
  expect_error(R"({"scene":{"a/b~c":1}})", Kind::invalid, "/scene/a~1b~0c", "unknown key");
  expect_error(one_solid(R"({"type":"box","center":[0,0],"size":[1,1,1],"material":{"gloss":1}})"), Kind::invalid,
               "/scene/solids/0/material/gloss", "unknown key");
}

TEST(SceneJsonErrors, WrongTypes) {
  expect_error("[]", Kind::invalid, "", "must be an object");
  expect_error(R"({"scene":{"walls":[{"start":[0,0],"end":[1,0],"thickness":"thick"}]}})", Kind::invalid,
               "/scene/walls/0/thickness", "must be a number");
  expect_error(R"({"scene":{"walls":{}}})", Kind::invalid, "/scene/walls", "must be an array");
  expect_error(R"({"scene":{"walls":[{"start":[0,"0"],"end":[1,0]}]}})", Kind::invalid, "/scene/walls/0/start/1",
               "must be a number");
  expect_error(one_solid(R"({"type":"cylinder","center":[0,0],"radius":1,"height":1,"caps":1})"), Kind::invalid,
               "/scene/solids/0/caps", "true or false");
  expect_error(one_solid(R"({"type":"sphere"})"), Kind::invalid, "/scene/solids/0/type");
  expect_error(R"({"options":{"width":640.5}})", Kind::invalid, "/options/width", "integer");
  expect_error(R"({"options":{"pipeline":"raytrace"}})", Kind::invalid, "/options/pipeline", "zbuffer");
  expect_error(R"({"options":{"shading":"toon"}})", Kind::invalid, "/options/shading", "flat");
  expect_error(R"({"options":{"shadow":{"method":"exact"}}})", Kind::invalid, "/options/shadow/method",
               "must be one of: map, rays");
  EXPECT_EQ(parse_request(R"({"options":{"shadow":{"method":"rays"}}})").options.shadow.method, ShadowMethod::rays);
  EXPECT_EQ(parse_request(R"({})").options.shadow.method, ShadowMethod::map);
  expect_error(R"({"scene":{"version":2}})", Kind::invalid, "/scene/version");
}

TEST(SceneJsonErrors, MissingRequiredKeysNameTheKey) {
  expect_error(R"({"scene":{"walls":[{"end":[1,0]}]}})", Kind::invalid, "/scene/walls/0", "\"start\"");
  expect_error(R"({"scene":{"floor":{}}})", Kind::invalid, "/scene/floor", "\"cells\"");
  expect_error(one_solid(R"({"center":[0,0]})"), Kind::invalid, "/scene/solids/0", "\"type\"");
}

TEST(SceneJsonErrors, OutOfRange) {
  expect_error(wall_with_openings(R"({"type":"window","offset":0,"width":1,"opacity":1.5})"), Kind::invalid,
               "/scene/walls/0/openings/0/opacity", "must be at most 1");
  expect_error(R"({"scene":{"walls":[{"start":[0,0],"end":[1,0],"height":0}]}})", Kind::invalid,
               "/scene/walls/0/height", "must be greater than 0");
  expect_error(R"({"scene":{"walls":[{"start":[0,0],"end":[2e7,0]}]}})", Kind::invalid, "/scene/walls/0/end/0",
               "at most 10000000");
  expect_error(R"({"scene":{"walls":[{"start":[1,1],"end":[1,1]}]}})", Kind::invalid, "/scene/walls/0/end",
               "from start");
  expect_error(R"({"scene":{"ambient":{"intensity":-1}}})", Kind::invalid, "/scene/ambient/intensity", "at least 0");
  expect_error(R"({"scene":{"floor":{"cells":[0,3]}}})", Kind::invalid, "/scene/floor/cells/0");
  expect_error(R"({"scene":{"floor":{"cells":[2,2],"colors":["#ffffff"]}}})", Kind::invalid, "/scene/floor/colors",
               "at least 2");
  expect_error(one_solid(R"({"type":"box","center":[0,0],"size":[1,1,1],
                             "material":{"shininess":0.5}})"),
               Kind::invalid, "/scene/solids/0/material/shininess", "at least 1");
  expect_error(one_solid(R"({"type":"cylinder","center":[0,0],"radius":1,"height":1,"segments":2})"), Kind::invalid,
               "/scene/solids/0/segments", "at least 3");
  expect_error(R"({"scene":{"lights":[{"type":"directional","direction":[0,0,0]}]}})", Kind::invalid,
               "/scene/lights/0/direction", "zero");
}

// JSON Schema's "integer" is any number with a zero fraction; the parser must agree with the schema.
TEST(SceneJsonErrors, IntegersMayBeSpelledWithAZeroFraction) {
  RenderRequest r = parse_request(one_solid(R"({"type":"cylinder","center":[0,0],"radius":1,"height":1,
                                         "segments":16.0})"));
  EXPECT_EQ(r.scene.geometry.solids.at(0).segments, 16);
  expect_error(one_solid(R"({"type":"cylinder","center":[0,0],"radius":1,"height":1,"segments":16.5})"), Kind::invalid,
               "/scene/solids/0/segments", "must be an integer");
  expect_error(one_solid(R"({"type":"cylinder","center":[0,0],"radius":1,"height":1,"segments":"16"})"), Kind::invalid,
               "/scene/solids/0/segments", "must be an integer");
}

// Every integer member, not just one: they are all read by read_integer.
TEST(SceneJsonErrors, EveryIntegerMemberAcceptsAZeroFraction) {
  RenderRequest r = parse_request(R"({"scene":{"version":1.0,"floor":{"cells":[2.0,3.0]},
      "solids":[{"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0.0,1.0,2.0]]}]},
      "options":{"width":320.0,"height":240.0,"bsp":{"max_candidates":8.0},
                 "shadow":{"size":512.0,"pcf":3.0}}})");
  EXPECT_EQ(r.scene.geometry.floor.cells_x, 2);
  EXPECT_EQ(r.scene.geometry.floor.cells_z, 3);
  EXPECT_EQ(r.scene.geometry.solids.at(0).mesh->faces.at(0), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(r.options.width, 320);
  EXPECT_EQ(r.options.height, 240);
  EXPECT_EQ(r.options.bsp.max_candidates, 8);
  EXPECT_EQ(r.options.shadow.size, 512);
  EXPECT_EQ(r.options.shadow.pcf, 3);
  // The same request spelled with plain integers is the same scene.
  RenderRequest plain = parse_request(R"({"scene":{"version":1,"floor":{"cells":[2,3]},
      "solids":[{"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2]]}]},
      "options":{"width":320,"height":240,"bsp":{"max_candidates":8},"shadow":{"size":512,"pcf":3}}})");
  EXPECT_EQ(scene_id(plain.scene.geometry), scene_id(r.scene.geometry));
}

TEST(SceneJsonErrors, FractionalIntegersNameTheirPointerAndValue) {
  const std::string mesh = R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1.5,2]]})";
  expect_error(one_solid(mesh), Kind::invalid, "/scene/solids/0/faces/0/1", "must be an integer (got 1.5)");
  expect_error(R"({"options":{"width":16.5}})", Kind::invalid, "/options/width", "must be an integer (got 16.5)");
  expect_error(R"({"scene":{"floor":{"cells":[2,2.25]}}})", Kind::invalid, "/scene/floor/cells/1",
               "must be an integer");
  expect_error(R"({"options":{"shadow":{"pcf":3.0000001}}})", Kind::invalid, "/options/shadow/pcf",
               "must be an integer");
  // Out-of-range exact integers keep their own messages, whichever way they are spelled.
  expect_error(one_solid(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,3.0]]})"), Kind::invalid,
               "/scene/solids/0/faces/0/2", "out of range");
  expect_error(one_solid(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,1e300]]})"),
               Kind::invalid, "/scene/solids/0/faces/0/2", "at most");
  expect_error(R"({"options":{"width":1e300}})", Kind::too_large, "/options/width", "at most");
}

// --- semantic rules ------------------------------------------------------------------------------------

TEST(SceneJsonRules, OpeningMustFitItsWall) {
  expect_error(wall_with_openings(R"({"type":"door","offset":0,"width":1},
                                     {"type":"window","offset":4.2,"width":1})"),
               Kind::invalid, "/scene/walls/0/openings/1",
               "window extends past the end of its wall (offset + width = 5.2 m > length 5 m)");
  expect_error(wall_with_openings(R"({"type":"window","offset":0,"width":1,"sill":1.5,"height":1.2})"), Kind::invalid,
               "/scene/walls/0/openings/0", "window extends above its wall (sill + height");
  expect_error(wall_with_openings(R"({"type":"door","offset":0,"width":1,"height":2.6})"), Kind::invalid,
               "/scene/walls/0/openings/0", "door is taller than its wall (height 2.6 m > wall height 2.5 m)");
  // Exactly reaching the end and the top is allowed.
  EXPECT_NO_THROW(
      parse_request(wall_with_openings(R"({"type":"window","offset":4,"width":1,"sill":1.3,"height":1.2})")));
}

TEST(SceneJsonRules, OpeningsMustNotOverlap) {
  expect_error(wall_with_openings(R"({"type":"window","offset":3,"width":1},
                                     {"type":"door","offset":0,"width":1},
                                     {"type":"door","offset":1.5,"width":2})"),
               Kind::invalid, "/scene/walls/0/openings/2", "overlaps opening 0");
  // Touching is allowed.
  EXPECT_NO_THROW(parse_request(
      wall_with_openings(R"({"type":"door","offset":0,"width":1},{"type":"window","offset":1,"width":1})")));
}

TEST(SceneJsonRules, MeshFacesMustBeValid) {
  const std::string vertices = R"("vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,0]])";
  expect_error(one_solid(R"({"type":"mesh",)" + vertices + R"(,"faces":[[0,1,2],[0,2,4]]})"), Kind::invalid,
               "/scene/solids/0/faces/1/2", "out of range");
  expect_error(one_solid(R"({"type":"mesh",)" + vertices + R"(,"faces":[[0,1,-1]]})"), Kind::invalid,
               "/scene/solids/0/faces/0/2", "out of range");
  expect_error(one_solid(R"({"type":"mesh",)" + vertices + R"(,"faces":[[0,1,1.5]]})"), Kind::invalid,
               "/scene/solids/0/faces/0/2", "integer");
  expect_error(one_solid(R"({"type":"mesh",)" + vertices + R"(,"faces":[[0,1,2,1]]})"), Kind::invalid,
               "/scene/solids/0/faces/0/3", "twice");
  expect_error(one_solid(R"({"type":"mesh",)" + vertices + R"(,"faces":[[0,1]]})"), Kind::invalid,
               "/scene/solids/0/faces/0", "at least 3");
  // Lift one corner of the quad 1 mm: far more than 1e-6 of a ~1.4 m mesh.
  expect_error(one_solid(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[1,1,0.001],[0,1,0]],
                             "faces":[[0,1,2],[0,1,2,3]]})"),
               Kind::invalid, "/scene/solids/0/faces/1", "not planar");
  expect_error(one_solid(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[2,0,0]],"faces":[[0,1,2]]})"), Kind::invalid,
               "/scene/solids/0/faces/0", "zero area");
  // Within tolerance: 1e-9 m off a ~1.4 m mesh.
  EXPECT_NO_THROW(parse_request(
      one_solid(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[1,1,1e-9],[0,1,0]],"faces":[[0,1,2,3]]})")));
}

TEST(SceneJsonRules, MeshFromJsonBuiltInCodeAcceptsSignedIndices) {
  json request = {
      {"scene",
       {{"solids", {{{"type", "mesh"}, {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"faces", {{0, 1, 2}}}}}}}}};
  ASSERT_TRUE(request["scene"]["solids"][0]["faces"][0][1].is_number_integer());
  EXPECT_EQ(request_from_json(request).scene.geometry.solids.at(0).mesh->faces.at(0).at(2), 2u);
}

TEST(SceneJsonRules, PrismMustBeSimplePolygon) {
  expect_error(one_solid(R"({"type":"prism","points":[[0,0],[1,1],[1,0],[0,1]],"height":1})"), Kind::invalid,
               "/scene/solids/0/points", "intersect");
  expect_error(one_solid(R"({"type":"prism","points":[[0,0],[1,0],[1,0],[0,1]],"height":1})"), Kind::invalid,
               "/scene/solids/0/points", "repeats");
  expect_error(one_solid(R"({"type":"prism","points":[[0,0],[1,0],[2,0]],"height":1})"), Kind::invalid,
               "/scene/solids/0/points");
  expect_error(one_solid(R"({"type":"prism","points":[[0,0],[1,0]],"height":1})"), Kind::invalid,
               "/scene/solids/0/points", "at least 3");
  // Non-convex but simple (an L), in either winding.
  EXPECT_NO_THROW(
      parse_request(one_solid(R"({"type":"prism","points":[[0,0],[2,0],[2,1],[1,1],[1,2],[0,2]],"height":1})")));
  EXPECT_NO_THROW(
      parse_request(one_solid(R"({"type":"prism","points":[[0,2],[1,2],[1,1],[2,1],[2,0],[0,0]],"height":1})")));
}

TEST(SceneJsonRules, CameraMustBeUsable) {
  expect_error(camera(R"("fov_y":0)"), Kind::invalid, "/camera/fov_y", "greater than 1");
  expect_error(camera(R"("fov_y":1)"), Kind::invalid, "/camera/fov_y", "greater than 1");
  expect_error(camera(R"("fov_y":170)"), Kind::invalid, "/camera/fov_y", "less than 170");
  EXPECT_NO_THROW(parse_request(camera(R"("fov_y":169.9)")));
  expect_error(camera(R"("near":1,"far":1)"), Kind::invalid, "/camera/far", "greater than 1");
  expect_error(camera(R"("near":2,"far":1)"), Kind::invalid, "/camera/far");
  expect_error(camera(R"("near":0)"), Kind::invalid, "/camera/near", "greater than 0");
  expect_error(camera(R"("near":1e-6,"far":100)"), Kind::invalid, "/camera/far", "exceeds");
  expect_error(camera(R"("position":[0,5,0],"target":[0,0,0])"), Kind::invalid, "/camera/up", "parallel");
  expect_error(camera(R"("position":[0,0,0],"target":[0,0,-1],"up":[0,0,2])"), Kind::invalid, "/camera/up", "parallel");
  expect_error(camera(R"("position":[1,2,3],"target":[1,2,3])"), Kind::invalid, "/camera/target", "coincide");
}

// --- limits --------------------------------------------------------------------------------------------

TEST(SceneJsonLimits, HugeImageIsTooLargeAndRefusedFast) {
  const double start = rr::testing::thread_cpu_ms();
  expect_error(R"({"options":{"width":100000}})", Kind::too_large, "/options/width", "at most 4096");
  EXPECT_LT(cpu_ms_since(start), 100.0);
  expect_error(R"({"options":{"height":4097}})", Kind::too_large, "/options/height");
  expect_error(R"({"options":{"width":0}})", Kind::invalid, "/options/width");
  EXPECT_NO_THROW(parse_request(R"({"options":{"width":4096,"height":4096}})"));
  ParseLimits limits;
  limits.max_pixels = 1000;
  expect_error(R"({"options":{"width":100,"height":11}})", Kind::too_large, "/options/width", "1100 pixels", limits);
}

TEST(SceneJsonLimits, WorkLimitsAreTooLarge) {
  expect_error(one_solid(R"({"type":"cylinder","center":[0,0],"radius":1,"height":1,"segments":1025})"),
               Kind::too_large, "/scene/solids/0/segments", "at most 1024");
  expect_error(R"({"scene":{"floor":{"cells":[1001,1000]}}})", Kind::too_large, "/scene/floor/cells");
  expect_error(R"({"scene":{"floor":{"cells":[1000001,1]}}})", Kind::too_large, "/scene/floor/cells/0");
  EXPECT_NO_THROW(parse_request(R"({"scene":{"floor":{"cells":[1000,1000]}}})"));
  ParseLimits limits;
  limits.max_polygons = 50;
  expect_error(R"({"scene":{"floor":{"cells":[10,10]}}})", Kind::too_large, "/scene", "polygons", limits);
  std::string faces = "[0,1,2]";
  for (int i = 0; i < 60; ++i) faces += ",[0,1,2]";
  expect_error(one_solid(R"({"type":"mesh","vertices":[[0,0,0],[1,0,0],[0,1,0]],"faces":[)" + faces + "]}"),
               Kind::too_large, "/scene/solids/0/faces", "61 faces", limits);
}

// --- malformed text ------------------------------------------------------------------------------------

TEST(SceneJsonMalformed, DeepNestingIsRefusedFastWhileParsing) {
  std::string deep = std::string(100000, '[') + std::string(100000, ']');
  std::string pointer_at_65th_level;
  for (int level = 0; level < 64; ++level) pointer_at_65th_level += "/0";
  const double start = rr::testing::thread_cpu_ms();
  expect_error(deep, Kind::malformed, pointer_at_65th_level, "deeper than 64");
  EXPECT_LT(cpu_ms_since(start), 100.0);
  // Exactly at the limit is fine; one more level is not.
  ParseLimits limits;
  limits.max_depth = 3;
  EXPECT_NO_THROW(parse_json_text("[[[1]]]", limits));
  EXPECT_NO_THROW(parse_json_text(R"({"a":{"b":[]}})", limits));
  try {
    parse_json_text(R"({"a":{"b":[{}]}})", limits);
    ADD_FAILURE() << "accepted 4 levels";
  } catch (const InputError& e) {
    EXPECT_EQ(e.kind(), Kind::malformed);
    EXPECT_EQ(e.pointer(), "/a/b/0");
  }
}

TEST(SceneJsonMalformed, DuplicateKeys) {
  expect_error(R"({"scene":{"walls":[{"start":[0,0],"end":[1,0],"start":[2,2]}]}})", Kind::malformed,
               "/scene/walls/0/start", "duplicate key");
  expect_error(R"({"camera":{},"camera":{}})", Kind::malformed, "/camera", "duplicate key");
}

TEST(SceneJsonMalformed, NonFiniteNumbers) {
  expect_error(R"({"camera":{"fov_y":NaN}})", Kind::malformed, "");
  expect_error(R"({"camera":{"fov_y":Infinity}})", Kind::malformed, "");
  // nlohmann itself reports the overflow as a parse error, so there is no pointer.
  expect_error(R"({"camera":{"fov_y":1e999}})", Kind::malformed, "", "overflow");
  expect_error(R"({"camera":{"position":[0,-1e999,0]}})", Kind::malformed, "", "overflow");
  // In JSON built in code NaN can exist; it is refused as invalid there.
  json request = {{"camera", {{"fov_y", std::nan("")}}}};
  try {
    request_from_json(request);
    ADD_FAILURE() << "accepted NaN";
  } catch (const InputError& e) {
    EXPECT_EQ(e.kind(), Kind::invalid);
    EXPECT_EQ(e.pointer(), "/camera/fov_y");
  }
}

TEST(SceneJsonMalformed, SyntaxErrorsReportTheByteOffset) {
  Failure truncated = failure_of(R"({"scene":{"walls":[)");
  EXPECT_EQ(truncated.kind, Kind::malformed);
  EXPECT_EQ(truncated.pointer, "");
  EXPECT_NE(truncated.detail.find("byte 20"), std::string::npos) << truncated.detail;
  expect_error("", Kind::malformed, "", "byte");
  expect_error("{} {}", Kind::malformed, "", "byte");
  expect_error(R"({"a":1,})", Kind::malformed, "", "byte");
}

// nlohmann's lexer ends its input at a NUL byte; the parser must not let that hide what follows.
TEST(SceneJsonMalformed, NothingButWhitespaceAfterTheValue) {
  using namespace std::string_literals;
  const std::string after_nul = "{}\0{\"options\":{\"width\":100000}}"s;
  ASSERT_EQ(after_nul.size(), 31u);
  expect_error(after_nul, Kind::malformed, "", "byte 3: a NUL byte");
  expect_error("{}\0"s, Kind::malformed, "", "byte 3: a NUL byte");
  expect_error("{} \n\t\0  "s, Kind::malformed, "", "byte 6: a NUL byte");
  // A NUL inside the text is the error too, not the end of input it would otherwise look like.
  expect_error("{\"scene\":\0}"s, Kind::malformed, "", "byte 10: a NUL byte");
  expect_error("{\"a\0\":1}"s, Kind::malformed, "", "NUL");
  // An earlier syntax error is still the one reported.
  expect_error("{x\0}"s, Kind::malformed, "", "byte 2: parse error");
  // Other trailing bytes, and trailing whitespace is fine.
  expect_error("{}x", Kind::malformed, "", "byte 3");
  expect_error("{}\x01", Kind::malformed, "", "byte 3");
  EXPECT_NO_THROW(parse_request("{} \r\n\t "));
}

TEST(SceneJsonMalformed, InvalidUtf8) {
  Failure f = failure_of("{\"scene\":{\"walls\":[{\"id\":\"caf\xE9\"}]}}");
  EXPECT_EQ(f.kind, Kind::malformed);
  EXPECT_NE(f.detail.find("byte"), std::string::npos) << f.detail;
  // The detail goes into a JSON problem body, so it must itself be valid UTF-8.
  EXPECT_NO_THROW((void)json(f.detail).dump()) << f.detail;
  expect_error("{\"scene\":{\"\xC0\xAF\":1}}", Kind::malformed, "");
}

// --- pointers ------------------------------------------------------------------------------------------

// --- quoting client text in errors ---------------------------------------------------------------------

TEST(QuoteInput, ShortTextIsQuotedWhole) {
  EXPECT_EQ(quote_input(""), "");
  EXPECT_EQ(quote_input(std::string(64, 'k')), std::string(64, 'k'));
}

TEST(QuoteInput, LongTextIsCutVisiblyAtACharacterBoundary) {
  EXPECT_EQ(quote_input(std::string(65, 'k')), std::string(64, 'k') + "\u2026(65 bytes)");
  // Byte 64 is the second byte of a two-byte character: the cut falls before that character.
  std::string two_byte = "a";
  for (int i = 0; i < 100; ++i) two_byte += "\u00e9";
  std::string expected = "a";
  for (int i = 0; i < 31; ++i) expected += "\u00e9";
  EXPECT_EQ(quote_input(two_byte), expected + "\u2026(201 bytes)");
  // Three- and four-byte characters, at every alignment: the kept text is whole characters.
  for (const std::string character : {"\u20ac", "\U0001F600"}) {
    for (size_t pad = 0; pad < 4; ++pad) {
      std::string text(pad, 'p');
      for (int i = 0; i < 40; ++i) text += character;
      std::string quoted = quote_input(text);
      size_t kept = quoted.find("\u2026(");
      ASSERT_NE(kept, std::string::npos);
      EXPECT_LE(kept, 64u);
      EXPECT_GT(kept, 64u - character.size());
      EXPECT_EQ((kept - pad) % character.size(), 0u) << "cut inside a character, pad " << pad;
      EXPECT_NO_THROW((void)json(quoted).dump()) << "not valid UTF-8";
    }
  }
}

TEST(QuoteInput, PointersCutLongTokens) {
  EXPECT_EQ(pointer_append("/scene", std::string(100, 'x')), "/scene/" + std::string(64, 'x') + "\u2026(100 bytes)");
  // Cut first, then escaped: the marker holds no '/' or '~' to escape.
  std::string escaped_slashes;
  for (int i = 0; i < 64; ++i) escaped_slashes += "~1";
  EXPECT_EQ(pointer_append("", std::string(70, '/')), "/" + escaped_slashes + "\u2026(70 bytes)");
}

TEST(QuoteInput, ErrorsQuoteAtMost64BytesOfTheRequest) {
  const std::string key(1 << 20, 'k');
  Failure unknown = failure_of(R"({"scene":{")" + key + R"(":1}})");
  EXPECT_EQ(unknown.kind, Kind::invalid);
  EXPECT_EQ(unknown.pointer, "/scene/" + std::string(64, 'k') + "\u2026(1048576 bytes)");
  EXPECT_LT(unknown.detail.size(), 512u) << unknown.detail.substr(0, 200);
  Failure duplicate = failure_of(R"({"camera":{")" + key + R"(":1,")" + key + R"(":1}})");
  EXPECT_EQ(duplicate.kind, Kind::malformed);
  EXPECT_EQ(duplicate.pointer, "/camera/" + std::string(64, 'k') + "\u2026(1048576 bytes)");
  Failure value = failure_of(R"({"options":{"pipeline":")" + key + R"("}})");
  EXPECT_EQ(value.pointer, "/options/pipeline");
  EXPECT_LT(value.detail.size(), 512u) << value.detail.substr(0, 200);
  // A syntax error quotes the token it stopped in: an unterminated megabyte string.
  Failure syntax = failure_of(R"({"scene":{")" + key);
  EXPECT_EQ(syntax.kind, Kind::malformed);
  EXPECT_LT(syntax.detail.size(), 512u) << syntax.detail.substr(0, 200);
  EXPECT_NE(syntax.detail.find("\u2026("), std::string::npos) << syntax.detail.substr(0, 200);
  EXPECT_NO_THROW((void)json(syntax.detail).dump());
}

TEST(JsonPointer, AppendEscapesTildeAndSlash) {
  EXPECT_EQ(pointer_append("", "a/b~c"), "/a~1b~0c");
  EXPECT_EQ(pointer_append("/scene", "~1"), "/scene/~01");
  EXPECT_EQ(pointer_append("/scene/walls", size_t(3)), "/scene/walls/3");
  EXPECT_EQ(pointer_append("", ""), "/");
}

}  // namespace
}  // namespace rr

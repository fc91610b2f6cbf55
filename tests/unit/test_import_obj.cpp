// OBJ import on small inline files: groups and materials become separate coloured meshes, negative
// and v/vt/vn indices resolve, quads stay quads, a non-planar face is triangulated, normals are kept
// (and reach the tessellated soup), zero-area faces are dropped; bad input is an InputError naming
// its line. Also the optional mesh "normals" of the scene format, which this importer fills.
#include "import_test_util.hpp"
#include "render/core/tessellate.hpp"
#include "render/import/import.hpp"

#include <gtest/gtest.h>

namespace {

using nlohmann::json;
using rr::ImportResult;
using rr::InputError;

rr::ImportOptions with_mtl(const std::string& name, const std::string& text) {
  rr::ImportOptions options;
  options.read_companion = [name, text](const std::string& asked) -> std::optional<std::string> {
    if (asked == name) return text;
    return std::nullopt;
  };
  return options;
}

TEST(ImportObj, GroupsAndMaterialsAreSeparateColouredMeshes) {
  const char* obj =
      "mtllib room.mtl\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "o table\nusemtl red\nf 1 2 3\n"
      "usemtl blue\nf 1 3 4\n"
      "o chair\nusemtl red\nf 2 3 4\n"
      "o table\nusemtl red\nf 4 1 2\n";  // the first group again: appended to it
  ImportResult r = rr::import_obj(obj, with_mtl("room.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n"));
  EXPECT_TRUE(r.warnings.empty());
  const json& solids = r.request["scene"]["solids"];
  ASSERT_EQ(solids.size(), 3u);
  EXPECT_EQ(solids[0]["id"], "table / red");
  EXPECT_EQ(solids[0]["color"], json::array({1.0, 0.0, 0.0}));
  EXPECT_EQ(solids[0]["faces"], json::parse("[[0,1,2],[3,0,1]]"));  // re-indexed per group
  EXPECT_EQ(solids[0]["vertices"].size(), 4u);
  EXPECT_EQ(solids[1]["id"], "table / blue");
  EXPECT_EQ(solids[1]["color"], json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(solids[2]["id"], "chair / red");
  EXPECT_NO_THROW(rr::request_from_json(r.request));
}

TEST(ImportObj, NegativeIndicesAndSlashFormsResolve) {
  const char* obj =
      "v 0 0 0\nv 2 0 0\nv 2 0 -2\nv 0 0 -2\n"
      "vt 0 0\nvt 1 0\n"
      "f -4/1 -3/2 -2/1 -1/2\n";  // a quad, given from the end
  ImportResult r = rr::import_obj(obj);
  const json& mesh = r.request["scene"]["solids"][0];
  EXPECT_EQ(mesh["faces"], json::parse("[[0,1,2,3]]"));  // planar: kept as one quad
  EXPECT_EQ(mesh["vertices"][2], json::array({2.0, 0.0, -2.0}));
  EXPECT_FALSE(mesh.contains("normals"));
}

TEST(ImportObj, NonPlanarFaceIsTriangulated) {
  ImportResult r = rr::import_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\nf 1 2 3 4\n");
  const json& faces = r.request["scene"]["solids"][0]["faces"];
  EXPECT_EQ(faces, json::parse("[[0,1,2],[0,2,3]]"));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "1 non-planar faces were split into triangles");
  EXPECT_NO_THROW(rr::request_from_json(r.request));
}

TEST(ImportObj, ZeroAreaAndRepeatedCornersAreRepaired) {
  ImportResult r = rr::import_obj("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 2 4\nf 1 2 4\n");
  // f 1 2 3 is a line (dropped); f 1 2 2 4 loses its repeated corner and stays.
  EXPECT_EQ(r.request["scene"]["solids"][0]["faces"], json::parse("[[0,1,2],[0,1,2]]"));
  EXPECT_EQ(r.warnings.back(), "1 faces of zero area were dropped");
}

TEST(ImportObj, NormalsSplitVerticesAndReachTheSoup) {
  const char* obj =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "vn 0 0 2\nvn 0.6 0 0.8\n"
      "f 1//1 2//1 3//1\nf 2//2 4//2 3//2\n";  // vertices 2 and 3 have two normals each
  ImportResult r = rr::import_obj(obj);
  const json& mesh = r.request["scene"]["solids"][0];
  EXPECT_EQ(mesh["vertices"].size(), 6u);
  ASSERT_EQ(mesh["normals"].size(), 6u);
  EXPECT_EQ(mesh["normals"][0], json::array({0.0, 0.0, 1.0}));  // normalised
  EXPECT_EQ(mesh["normals"][3], json::array({0.6, 0.0, 0.8}));
  rr::RenderRequest parsed = rr::request_from_json(r.request);
  rr::PolygonSoup soup = rr::tessellate(parsed.scene.geometry);
  ASSERT_EQ(soup.polygons.size(), 2u);
  for (const glm::vec3& n : soup.vertex_normals(soup.polygons[1])) {
    EXPECT_NEAR(n.x, 0.6f, 1e-6f);
    EXPECT_NEAR(n.z, 0.8f, 1e-6f);
  }
}

TEST(MeshNormals, FollowScaleAndRotationAndAreChecked) {
  json request = json::parse(R"({"scene": {"solids": [{"type": "mesh",
      "vertices": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,2]],
      "normals": [[1,0,1],[1,0,1],[1,0,1]], "scale": [2, 1, 1], "rotation_y": 90}]}})");
  rr::RenderRequest parsed = rr::request_from_json(request);
  rr::PolygonSoup soup = rr::tessellate(parsed.scene.geometry);
  // Scale by the inverse transpose: (1/2, 0, 1) normalised; then +90 degrees turns +X toward -Z.
  const glm::vec3 n = soup.vertex_normals(soup.polygons[0])[0];
  const float s = 1.0f / std::sqrt(1.25f);
  EXPECT_NEAR(n.x, 1.0f * s, 1e-6f);
  EXPECT_NEAR(n.z, -0.5f * s, 1e-6f);
  request["scene"]["solids"][0]["normals"] = json::parse("[[1,0,0]]");
  try {
    rr::request_from_json(request);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/scene/solids/0/normals");
  }
  request["scene"]["solids"][0]["normals"] = json::parse("[[1,0,0],[0,0,0],[1,0,0]]");
  EXPECT_THROW(rr::request_from_json(request), InputError);
}

void expect_line_error(const std::string& obj, size_t line, const std::string& words) {
  try {
    rr::import_obj(obj);
    ADD_FAILURE() << "no error; expected: " << words;
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/line/" + std::to_string(line)) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(ImportObj, BadInputNamesTheLine) {
  expect_line_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4,
                    "line 4: vertex index 4 is out of range (3 vertices defined before this line");
  expect_line_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", 4, "vertex index -4 is out of range");
  expect_line_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "vertex index 0 is out of range");
  expect_line_error("v 0 0 0\nv nan 0 0\n", 2, "line 2: vertex coordinate 'nan' is not a finite number");
  expect_line_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//2 2//1 3//1\n", 5, "normal index 2 is out of range");
  expect_line_error("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "a face needs at least 3 vertices");
  expect_line_error("v 0 0\n", 1, "vertex needs 3 numbers");
  expect_line_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", 4, "vertex index 'x' is not an integer");
  EXPECT_THROW(rr::import_obj("# nothing\n"), InputError);
}

TEST(ImportObj, MissingLibraryAndMaterialsWarn) {
  ImportResult r = rr::import_obj("mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl wood\nf 1 2 3\n");
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_EQ(r.warnings[0], "material library 'gone.mtl' is not available: its groups are grey");
  EXPECT_EQ(r.warnings[1], "materials without a Kd colour, drawn grey: wood");
  EXPECT_EQ(r.request["scene"]["solids"][0]["color"], json::array({0.7, 0.7, 0.7}));
}

TEST(ImportObj, ScaleAndCameraFrameTheModel) {
  rr::ImportOptions options;
  options.scale = 0.5;
  ImportResult r = rr::import_obj("v 0 0 0\nv 4 0 0\nv 4 4 0\nf 1 2 3\n", options);
  EXPECT_EQ(r.request["scene"]["solids"][0]["scale"], 0.5);
  EXPECT_EQ(r.request["camera"]["target"], json::array({1.0, 1.0, 0.0}));  // the scaled box's centre
  EXPECT_GT(rr::testing::covered_share(r.request, "zbuffer"), 0.05);
}

// A box room in millimetres, 6 m along x, 4 m along z, 3 m high: the floor as two triangles, a
// table top at 0.8 m over the centre, the ceiling and four walls.
constexpr const char* box_room_mm =
    "v 0 0 0\nv 6000 0 0\nv 6000 0 4000\nv 0 0 4000\n"
    "v 0 3000 0\nv 6000 3000 0\nv 6000 3000 4000\nv 0 3000 4000\n"
    "v 2500 800 1500\nv 3500 800 1500\nv 3500 800 2500\nv 2500 800 2500\n"
    "g floor\nf 1 4 3\nf 1 3 2\ng ceiling\nf 5 6 7 8\n"
    "g walls\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\ng table\nf 9 12 11 10\n";

TEST(ImportObj, InteriorOpensFromInsideAtEyeHeight) {
  rr::ImportOptions options;
  options.scale = 0.001;
  ImportResult r = rr::import_obj(box_room_mm, options);
  // 1.6 m above the floor (not the table) at the plan centre, looking along x, the longer side.
  EXPECT_EQ(r.request["camera"]["position"], json::array({3.0, 1.6, 2.0}));
  EXPECT_EQ(r.request["camera"]["target"], json::array({6.0, 1.6, 2.0}));
  EXPECT_EQ(r.request["camera"]["near"], 0.05);
  EXPECT_GT(rr::testing::covered_share(r.request, "zbuffer"), 0.99);  // walls all round: no background
}

TEST(ImportObj, LowRoomPutsTheEyeAtThreeFifthsOfItsHeight) {
  rr::ImportOptions options;
  options.scale = 1.0 / 3000.0;  // 2 m x 1.33 m, 1 m high
  ImportResult r = rr::import_obj(box_room_mm, options);
  EXPECT_EQ(r.request["camera"]["position"], json::array({1.0, 0.6, 0.666667}));
  EXPECT_EQ(r.request["camera"]["target"], json::array({2.0, 0.6, 0.666667}));
}

TEST(ImportObj, ModelWithoutCeilingIsFramedFromOutside) {
  std::string open_top = box_room_mm;
  open_top.replace(open_top.find("g ceiling\nf 5 6 7 8\n"), 20, "");
  rr::ImportOptions options;
  options.scale = 0.001;
  ImportResult r = rr::import_obj(open_top, options);
  EXPECT_EQ(r.request["camera"]["target"], json::array({3.0, 1.5, 2.0}));  // the box's centre
}

TEST(ImportFormat, RecognisedFromContentThenName) {
  EXPECT_EQ(rr::detect_import_format("<?xml version='1.0'?>\n<home>", ""), rr::ImportFormat::sweethome3d);
  EXPECT_EQ(rr::detect_import_format("1\t2\t3\t4\twall\t1\t1\n", ""), rr::ImportFormat::r2v);
  EXPECT_EQ(rr::detect_import_format("# x\nv 1 2 3\n", ""), rr::ImportFormat::obj);
  EXPECT_EQ(rr::detect_import_format("", "model.OBJ"), rr::ImportFormat::obj);
  EXPECT_EQ(rr::detect_import_format("", "plan.txt"), rr::ImportFormat::r2v);
  EXPECT_EQ(rr::detect_import_format("hello", "notes"), std::nullopt);
  EXPECT_EQ(rr::find_import_format("sh3d")->format, rr::ImportFormat::sweethome3d);
  EXPECT_EQ(rr::find_import_format("dxf"), nullptr);
}

}  // namespace

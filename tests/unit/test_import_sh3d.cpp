// Sweet Home 3D import: a hand-made Home.xml whose every mapping is computed by hand (cm -> m,
// centre-based door positions -> offsets, sloped and arc walls, rotation sign, observer camera), the
// errors (malformed XML, an opening wider than its wall, a missing attribute), a .sh3d zip, furniture
// models as pieces (groups, the default material library), and the nine example homes of
// ../shared/data: one checked against its XML read independently with pugixml, each giving one piece
// per top-level piece of its XML, all of them imported and rendered with every pipeline; textures on
// rooms and wall sides, from the archive or the bundled default catalogue.
#include "import_test_util.hpp"
#include "render/core/tessellate.hpp"
#include "render/import/import.hpp"
#include "render/import/import_obj.hpp"
#include "render/import/import_sh3d.hpp"
#include "support/image_bytes.hpp"
#include "support/zip_builder.hpp"

#include <gtest/gtest.h>
#include <zip.h>
#include <pugixml.hpp>

#include <cmath>
#include <functional>
#include <map>

namespace {

using nlohmann::json;
using rr::ImportResult;
using rr::InputError;

const char* small_home = R"(<?xml version='1.0'?>
<home version='5500' wallHeight='250.0'>
  <observerCamera attribute='observerCamera' x='100' y='200' z='170' yaw='0' pitch='0' fieldOfView='1.5707964'/>
  <wall id='w0' xStart='0' yStart='0' xEnd='400' yEnd='0' height='250' thickness='10'/>
  <wall id='w1' xStart='400' yStart='0' xEnd='400' yEnd='300' height='250' heightAtEnd='150' thickness='10'/>
  <wall id='w2' xStart='400' yStart='300' xEnd='0' yEnd='300' height='250' thickness='20' arcExtent='1.0471976'/>
  <room name='Room' floorColor='FF0000FF'><point x='0' y='0'/><point x='400' y='0'/><point x='400' y='300'/><point x='0' y='300'/></room>
  <doorOrWindow name='Door' catalogId='eTeks#door' x='100' y='2' angle='0' width='80' depth='10' height='210'/>
  <doorOrWindow name='Window' catalogId='eTeks#window' x='300' y='0' elevation='100' angle='3.1415927' width='60' depth='12' height='100'/>
  <pieceOfFurniture name='Table' x='200' y='150' angle='1.5707964' width='120' depth='80' height='75' color='FFFF0000'/>
  <light name='Lamp' x='50' y='50' elevation='200' width='20' depth='20' height='40' power='0.5'>
    <lightSource x='0.5' y='0.5' z='0' color='00FFFFFF'/>
  </light>
</home>
)";

const json* find_by_id(const json& items, const std::string& id) {
  for (const json& item : items) {
    if (item.value("id", "") == id) return &item;
  }
  return nullptr;
}

TEST(ImportSh3d, SmallHomeMapsEveryElement) {
  ImportResult r = rr::import_sweethome3d(small_home);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  const json& scene = r.request["scene"];
  // w0 + w1 + the 60 degree arc in 6 segments of 10 degrees.
  ASSERT_EQ(scene["walls"].size(), 8u) << scene["walls"].dump();
  const json& w0 = *find_by_id(scene["walls"], "w0");
  EXPECT_EQ(w0["start"], json::array({0.0, 0.0}));
  EXPECT_EQ(w0["end"], json::array({4.0, 0.0}));
  EXPECT_DOUBLE_EQ(w0["thickness"].get<double>(), 0.1);
  ASSERT_EQ(w0["openings"].size(), 2u);
  // The door's centre is 1 m along the wall, so its near edge is at 1 - 0.8 / 2.
  const json& door = w0["openings"][0];
  EXPECT_EQ(door["type"], "door");
  EXPECT_EQ(door["leaf"], true);
  EXPECT_NEAR(door["offset"].get<double>(), 0.6, 1e-9);
  EXPECT_NEAR(door["width"].get<double>(), 0.8, 1e-9);
  EXPECT_NEAR(door["height"].get<double>(), 2.1, 1e-9);
  // A window turned by 180 degrees still spans its width along the wall; elevation becomes the sill.
  const json& window = w0["openings"][1];
  EXPECT_EQ(window["type"], "window");
  EXPECT_NEAR(window["offset"].get<double>(), 2.7, 1e-6);
  EXPECT_NEAR(window["width"].get<double>(), 0.6, 1e-6);
  EXPECT_NEAR(window["sill"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(window["height"].get<double>(), 1.0, 1e-9);
  // Sloped top: a wall as high as its lower end and a wedge up to 2.5 m at its start.
  const json& w1 = *find_by_id(scene["walls"], "w1");
  EXPECT_DOUBLE_EQ(w1["height"].get<double>(), 1.5);
  const json* wedge = find_by_id(scene["solids"], "w1 (sloped top)");
  ASSERT_NE(wedge, nullptr);
  double top = 0.0;
  for (const json& v : (*wedge)["vertices"]) top = std::max(top, v[1].get<double>());
  EXPECT_DOUBLE_EQ(top, 2.5);
  // The arc from (4, 3) to (0, 3) bulges toward +z: radius 4, sagitta 4 (1 - cos 30 deg).
  const json& first = *find_by_id(scene["walls"], "w2 #1");
  const json& middle = *find_by_id(scene["walls"], "w2 #3");
  const json& last = *find_by_id(scene["walls"], "w2 #6");
  EXPECT_EQ(first["start"], json::array({4.0, 3.0}));
  EXPECT_EQ(last["end"], json::array({0.0, 3.0}));
  EXPECT_NEAR(middle["end"][0].get<double>(), 2.0, 1e-5);
  EXPECT_NEAR(middle["end"][1].get<double>(), 3.0 + 4.0 * (1.0 - std::cos(rr::pi / 6.0)), 1e-5);
}

TEST(ImportSh3d, SmallHomeFurnitureRoomLightAndCamera) {
  ImportResult r = rr::import_sweethome3d(small_home);
  const json& scene = r.request["scene"];
  const json* table = find_by_id(scene["solids"], "Table (/home/pieceOfFurniture/0)");
  ASSERT_NE(table, nullptr);
  EXPECT_EQ((*table)["center"], json::array({2.0, 1.5}));
  EXPECT_EQ((*table)["size"], json::array({1.2, 0.75, 0.8}));
  // Sweet Home 3D turns clockwise on the plan (y down); rotation_y turns counter-clockwise.
  EXPECT_NEAR((*table)["rotation_y"].get<double>(), -90.0, 1e-4);
  EXPECT_EQ((*table)["color"], json::array({1.0, 0.0, 0.0}));
  const json* room = find_by_id(scene["rooms"], "room Room (/home/room/0)");
  ASSERT_NE(room, nullptr);
  EXPECT_EQ((*room)["points"].size(), 4u);
  EXPECT_DOUBLE_EQ((*room)["elevation"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ((*room)["ceiling_height"].get<double>(), 2.5);  // the home's wall height: it has no levels
  EXPECT_EQ((*room)["floor_color"], json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ((*room)["ceiling"], true);
  EXPECT_FALSE(room->contains("ceiling_color"));  // the format's default then
  // The lamp's light source sits at the bottom centre of its 20 x 20 x 40 cm box, 2 m up.
  ASSERT_EQ(scene["lights"].size(), 2u);  // the default sun and the lamp
  EXPECT_EQ(scene["lights"][1]["position"], json::array({0.5, 2.0, 0.5}));
  // Power 0.5, white source, no <environment>: the default light colour 208/255, 5 x 255^2 / 100^2 x 0.25,
  // and a source with no diameter is a 3.25 cm sphere.
  EXPECT_EQ(scene["lights"][1]["color"], json::array({0.816, 0.816, 0.816}));
  EXPECT_DOUBLE_EQ(scene["lights"][1]["intensity"].get<double>(), 8.128125);
  EXPECT_EQ(scene["lights"][1]["attenuation"], json::array({0.0325 * 0.0325, 0.0, 1.0}));
  // The observer at (100, 200) cm, eyes 170 cm up, yaw 0 looks toward +y of the plan (+z here).
  const json& camera = r.request["camera"];
  EXPECT_EQ(camera["position"], json::array({1.0, 1.7, 2.0}));
  EXPECT_EQ(camera["target"], json::array({1.0, 1.7, 3.0}));
  // 90 degrees horizontally at 4:3 is 2 atan(3/4) vertically.
  EXPECT_NEAR(camera["fov_y"].get<double>(), 2.0 * std::atan(0.75) * 180.0 / rr::pi, 1e-3);
  EXPECT_NO_THROW(rr::request_from_json(r.request));
}

TEST(ImportSh3d, LampLightFollowsThePhotoRenderer) {
  using rr::import_detail::sh3d_lamp_light;
  const rr::Color white{1.0f}, home_default{208.0f / 255.0f};
  // Intensity 5 x 255^2 / 100^2 x power^2 = 32.5125 power^2, whatever the colours.
  EXPECT_DOUBLE_EQ(sh3d_lamp_light(0.0, white, home_default, std::nullopt, 0.3).intensity, 0.0);
  EXPECT_DOUBLE_EQ(sh3d_lamp_light(0.5, white, home_default, std::nullopt, 0.3).intensity, 8.128125);
  EXPECT_DOUBLE_EQ(sh3d_lamp_light(1.0, white, home_default, std::nullopt, 0.3).intensity, 32.5125);
  // The colour is the source's times the home's, channel by channel: 0x998764 x 0xD0D0D0.
  const rr::Color source{153.0f / 255.0f, 135.0f / 255.0f, 100.0f / 255.0f};
  const auto lamp = sh3d_lamp_light(0.5, source, home_default, 0.29166666, 0.48);
  EXPECT_FLOAT_EQ(lamp.color.r, 31824.0f / 65025.0f);  // 153 x 208 / 255^2
  EXPECT_FLOAT_EQ(lamp.color.g, 28080.0f / 65025.0f);  // 135 x 208 / 255^2
  EXPECT_FLOAT_EQ(lamp.color.b, 20800.0f / 65025.0f);  // 100 x 208 / 255^2
  EXPECT_DOUBLE_EQ(lamp.intensity, 8.128125);
  // The diameter is a fraction of the lamp's width: 0.29166666 x 0.48 m / 2 = 0.0699999984 m.
  EXPECT_NEAR(lamp.radius_m, 0.0699999984, 1e-15);
  // No diameter: 3.25 cm, whatever the width.
  EXPECT_DOUBLE_EQ(sh3d_lamp_light(1.0, white, white, std::nullopt, 2.0).radius_m, 0.0325);
  // A coloured home light tints every source: white x (1, 0.5, 0) and green x (1, 0.5, 0).
  const rr::Color orange{1.0f, 0.5f, 0.0f};
  const auto tinted = sh3d_lamp_light(1.0, white, orange, std::nullopt, 0.4);
  EXPECT_EQ(tinted.color, rr::Color(1.0f, 0.5f, 0.0f));
  const auto green = sh3d_lamp_light(1.0, rr::Color(0.0f, 1.0f, 0.0f), orange, std::nullopt, 0.4);
  EXPECT_EQ(green.color, rr::Color(0.0f, 0.5f, 0.0f));
}

TEST(ImportSh3d, LampsWithSeveralSourcesAndTheHomeLightColour) {
  ImportResult r = rr::import_sweethome3d(R"(<home wallHeight='250'>
  <environment lightColor='00FF8000'/>
  <light name='Two bulbs' x='200' y='100' elevation='100' width='40' depth='40' height='40' power='1'>
    <lightSource x='0.25' y='0.5' z='1' color='00FFFFFF' diameter='0.5'/>
    <lightSource x='0.75' y='0.25' z='1' color='0000FF00'/>
  </light>
  <light name='Off' x='300' y='100' width='40' depth='40' height='40' power='0'>
    <lightSource x='0.5' y='0.5' z='0.5' color='00FFFFFF'/>
  </light>
</home>)");
  const json& lights = r.request["scene"]["lights"];
  ASSERT_EQ(lights.size(), 3u) << lights.dump();  // the sun and the two sources; the lamp at power 0 is off
  const json& bulb = lights[1];
  const json& green = lights[2];
  EXPECT_EQ(bulb["position"], json::array({1.9, 1.4, 1.0}));
  // y 0.25 of the depth is 0.1 m in front of the centre, toward the plan's +y (our +z).
  EXPECT_EQ(green["position"], json::array({2.1, 1.4, 1.1}));
  // Home light 0xFF8000: (1, 128/255 = 0.502, 0); power 1: 32.5125.
  EXPECT_EQ(bulb["color"], json::array({1.0, 0.502, 0.0}));
  EXPECT_EQ(green["color"], json::array({0.0, 0.502, 0.0}));
  EXPECT_DOUBLE_EQ(bulb["intensity"].get<double>(), 32.5125);
  EXPECT_DOUBLE_EQ(green["intensity"].get<double>(), 32.5125);
  // Radius 0.5 x 0.4 m / 2 = 0.1 m; the second source has the default 3.25 cm.
  EXPECT_NEAR(bulb["attenuation"][0].get<double>(), 0.01, 1e-12);
  EXPECT_EQ(bulb["attenuation"][1], 0.0);
  EXPECT_EQ(bulb["attenuation"][2], 1.0);
  EXPECT_EQ(green["attenuation"], json::array({0.0325 * 0.0325, 0.0, 1.0}));
  EXPECT_NO_THROW(rr::request_from_json(r.request));
}

void expect_input_error(const std::string& xml, InputError::Kind kind, const std::string& pointer,
                        const std::string& words) {
  try {
    rr::import_sweethome3d(xml);
    ADD_FAILURE() << "no error; expected: " << words;
  } catch (const InputError& e) {
    EXPECT_EQ(e.kind(), kind) << e.what();
    EXPECT_EQ(e.pointer(), pointer) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(ImportSh3d, MalformedXmlNamesTheLine) {
  expect_input_error("<?xml version='1.0'?>\n<home>\n  <wall id='w0' xStart='0'\n</home>\n",
                     InputError::Kind::malformed, "/line/4", "line 4: not well-formed XML");
  expect_input_error("<plan/>", InputError::Kind::malformed, "/plan", "not Sweet Home 3D's <home>");
}

TEST(ImportSh3d, OpeningWiderThanItsWallIsAnError) {
  expect_input_error(R"(<home>
    <wall id='short' xStart='0' yStart='0' xEnd='50' yEnd='0' thickness='10' height='250'/>
    <doorOrWindow name='Wide window' x='25' y='0' elevation='90' width='100' depth='10' height='100'/>
  </home>)",
                     InputError::Kind::invalid, "/home/doorOrWindow/0",
                     "line 3: window 'Wide window' is 1.000000 m wide, wider than the wall 'short'");
}

TEST(ImportSh3d, MissingOrBadAttributeNamesIt) {
  expect_input_error("<home>\n<wall id='w' yStart='0' xEnd='50' yEnd='0'/></home>", InputError::Kind::invalid,
                     "/home/wall/0", "line 2: <wall> attribute xStart is missing");
  expect_input_error("<home><wall id='w' xStart='zero' yStart='0' xEnd='50' yEnd='0'/></home>",
                     InputError::Kind::invalid, "/home/wall/0", "attribute xStart 'zero' is not a number");
  expect_input_error("<home><wall level='nowhere' xStart='0' yStart='0' xEnd='50' yEnd='0'/></home>",
                     InputError::Kind::invalid, "/home/wall/0", "names level 'nowhere'");
}

TEST(ImportSh3d, OpeningPastTheWallEndIsClampedWithAWarning) {
  ImportResult r = rr::import_sweethome3d(R"(<home>
    <wall id='w' xStart='0' yStart='0' xEnd='200' yEnd='0' thickness='10' height='250'/>
    <doorOrWindow name='Window' x='180' y='0' elevation='90' width='80' depth='10' height='100'/>
  </home>)");
  ASSERT_EQ(r.warnings.size(), 2u);  // clamped, and no observer camera
  EXPECT_NE(r.warnings[0].find("reaches past the end of its wall; clamped"), std::string::npos) << r.warnings[0];
  const json& o = r.request["scene"]["walls"][0]["openings"][0];
  EXPECT_NEAR(o["offset"].get<double>(), 1.4, 1e-9);
  EXPECT_NEAR(o["width"].get<double>(), 0.6, 1e-9);  // 1.4 .. 2.0, the wall's end
  EXPECT_NO_THROW(rr::request_from_json(r.request));
}

TEST(ImportSh3d, HiddenLevelsAreImportedButNotViewable) {
  ImportResult r = rr::import_sweethome3d(R"(<home>
    <level id='l0' name='Ground' elevation='0' floorThickness='12' height='250'/>
    <level id='l1' name='Roof' elevation='250' floorThickness='12' height='180' visible='false'/>
    <wall level='l0' xStart='0' yStart='0' xEnd='200' yEnd='0'/>
    <wall level='l1' xStart='0' yStart='0' xEnd='200' yEnd='0'/>
    <room level='l1' ceilingColor='FF00FF00'><point x='0' y='0'/><point x='200' y='0'/><point x='200' y='100'/></room>
  </home>)");
  const json& scene = r.request["scene"];
  ASSERT_EQ(scene["walls"].size(), 2u);
  EXPECT_EQ(scene["walls"][0]["level"], "l0");
  EXPECT_EQ(scene["walls"][1]["level"], "l1");
  EXPECT_DOUBLE_EQ(scene["walls"][1]["base"].get<double>(), 2.5);
  EXPECT_EQ(scene["levels"], json::parse(R"([{"id": "l0", "elevation": 0.0, "height": 2.5, "viewable": true},
                                             {"id": "l1", "elevation": 2.5, "height": 1.8, "viewable": false}])"));
  const json& room = scene["rooms"][0];
  EXPECT_EQ(room["level"], "l1");
  EXPECT_DOUBLE_EQ(room["elevation"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(room["ceiling_height"].get<double>(), 1.8);  // the level's height, as Sweet Home 3D
  EXPECT_EQ(room["ceiling_color"], json::array({0.0, 1.0, 0.0}));
  EXPECT_NO_THROW(rr::request_from_json(r.request));
}

TEST(ImportSh3d, Sh3dZipIsReadThroughItsHomeXml) {
  auto path = rr::testing::output_dir("unit") / "small.sh3d";
  int error = 0;
  zip_t* archive = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  ASSERT_NE(archive, nullptr);
  zip_source_t* source = zip_source_buffer(archive, small_home, std::strlen(small_home), 0);
  ASSERT_GE(zip_file_add(archive, "Home.xml", source, ZIP_FL_ENC_UTF_8), 0);
  ASSERT_EQ(zip_close(archive), 0);
  std::string bytes = rr::testing::read_file(path);
  EXPECT_EQ(rr::detect_import_format(bytes, "x.bin"), rr::ImportFormat::sweethome3d);
  EXPECT_EQ(rr::import_file_text(bytes, rr::ImportFormat::sweethome3d).request,
            rr::import_sweethome3d(small_home).request);
  std::string broken = bytes.substr(0, 40);
  EXPECT_THROW(rr::import_file_text(broken, rr::ImportFormat::sweethome3d), InputError);
}

// A model 2 x 1 x 4 units, its x face group in material "red"; the piece turns it by 90 degrees.
TEST(ImportSh3d, FurnitureModelsArePlacedOnThePiecesBox) {
  const std::string model =
      "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 0 0 4\nv 2 0 4\nv 2 1 4\nv 0 1 4\n"
      "usemtl red\nf 2 3 7 6\nusemtl plain\nf 1 5 8 4\n";
  const char* home = R"(<home>
    <pieceOfFurniture name='Box' model='models/thing.obj' x='300' y='400' elevation='10' angle='1.5707963'
        width='100' depth='50' height='200'><material name='red' color='FFFF0000'/></pieceOfFurniture>
    <pieceOfFurniture name='Lost' model='models/lost.obj' x='0' y='0' width='10' depth='10' height='10'/>
  </home>)";
  rr::ImportOptions options;
  options.furniture_models = true;
  std::vector<std::string> asked;
  options.read_companion = [&](const std::string& name) -> std::optional<std::string> {
    asked.push_back(name);
    if (name == "furniture/thing.obj") return model;  // found in the fallback place only
    return std::nullopt;
  };
  ImportResult r = rr::import_sweethome3d(home, options);
  EXPECT_EQ(asked, (std::vector<std::string>{"models/thing.obj", "furniture/thing.obj", "models/lost.obj",
                                             "furniture/lost.obj"}));
  const json& solids = r.request["scene"]["solids"];
  ASSERT_EQ(solids.size(), 2u);  // one piece of the model's two groups, and a box for the missing one
  EXPECT_EQ(solids[0]["type"], "piece");
  EXPECT_EQ(solids[0]["id"], "Box (/home/pieceOfFurniture/0)");
  ASSERT_EQ(solids[0]["parts"].size(), 2u);
  EXPECT_EQ(solids[0]["parts"][0]["name"], "red");
  EXPECT_EQ(solids[0]["parts"][0]["color"], json::array({1.0, 0.0, 0.0}));
  EXPECT_EQ(solids[0]["center"], json::array({3.0, 4.0}));
  EXPECT_EQ(solids[0]["size"], json::array({1.0, 2.0, 0.5}));
  EXPECT_EQ(solids[1]["type"], "box");
  ASSERT_EQ(r.warnings.size(), 2u);  // the missing model, then the missing observer camera
  EXPECT_EQ(
      r.warnings[0],
      "1 furniture models were not found and 0 could not be read: those pieces are boxes (not found: models/lost.obj)");
  // Width (model x, 2 units -> 1 m) turned by the angle runs along +z; depth (4 units -> 0.5 m)
  // along -x; height 1 unit -> 2 m from the elevation up. Measured on the tessellated piece, since
  // each part is the unit model stretched to the piece's size, turned and placed.
  json models = r.request;
  models["scene"]["solids"] = json::array({solids[0]});
  models["scene"]["walls"] = json::array();
  const rr::PolygonSoup soup = rr::tessellate(rr::request_from_json(models).scene.geometry);
  rr::Vec3 lo{1e9}, hi{-1e9};
  for (const rr::Polygon& polygon : soup.polygons) {
    for (const rr::Vec3& p : soup.points(polygon)) lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  EXPECT_EQ(soup.polygons.size(), 2u);
  EXPECT_EQ(soup.objects.size(), 1u);
  EXPECT_NEAR(lo.x, 2.75, 1e-6);
  EXPECT_NEAR(hi.x, 3.25, 1e-6);
  EXPECT_NEAR(lo.y, 0.1, 1e-6);
  EXPECT_NEAR(hi.y, 2.1, 1e-6);
  EXPECT_NEAR(lo.z, 3.5, 1e-6);
  EXPECT_NEAR(hi.z, 4.5, 1e-6);
  EXPECT_NO_THROW(rr::request_from_json(r.request));
}

// Models name materials without an .mtl: Sweet Home 3D's default library colours them (with its
// specular terms); a name it does not have stays grey.
TEST(ImportSh3d, MaterialsWithoutAnMtlComeFromTheDefaultLibrary) {
  const std::string model =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
      "usemtl white\nf 1 2 3 4\nusemtl flblonde\nf 1 5 6 2\nusemtl no_such\nf 1 4 5\n";
  const char* home =
      R"(<home><pieceOfFurniture name='A' model='a.obj' x='0' y='0' width='10' depth='10' height='10'/></home>)";
  rr::ImportOptions options;
  options.furniture_models = true;
  options.read_companion = [&](const std::string& name) -> std::optional<std::string> {
    return name == "a.obj" ? std::optional<std::string>(model) : std::nullopt;
  };
  const json parts = rr::import_sweethome3d(home, options).request["scene"]["solids"][0]["parts"];
  ASSERT_EQ(parts.size(), 3u);
  // catalogue/default-materials.mtl: white Kd 1 1 1, Ks 0.3, Ns 60; flblonde Kd 0.5714 0.3283 0.0443.
  EXPECT_EQ(parts[0]["color"], json::array({1.0, 1.0, 1.0}));
  EXPECT_EQ(parts[0]["material"], json({{"specular", 0.3}, {"specular_color", {1.0, 1.0, 1.0}}, {"shininess", 60.0}}));
  EXPECT_EQ(parts[1]["color"], json::array({0.571, 0.328, 0.044}));
  EXPECT_FALSE(parts[1].contains("material"));  // no Ks or Ns in the library
  EXPECT_EQ(parts[2]["color"], json::array({0.7, 0.7, 0.7}));
}

// A furniture group is one piece in the group's box: each member's model is a part placed by its
// transform, and the piece draws the points the members would draw placed one by one.
TEST(ImportSh3d, AFurnitureGroupIsOnePieceOfItsMembers) {
  const std::string model =
      "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 0 0 4\nv 2 0 4\nv 2 1 4\nv 0 1 4\n"
      "usemtl red\nf 2 3 7 6\nusemtl plain\nf 1 5 8 4\n";
  const char* members = R"(
      <pieceOfFurniture name='A' model='thing.obj' x='100' y='100' angle='0.3' width='100' depth='50' height='200'/>
      <pieceOfFurniture name='B' model='thing.obj' x='260' y='140' elevation='20' angle='2.1' width='60' depth='30' height='80'/>)";
  const std::string grouped = std::string(
                                  "<home><furnitureGroup name='G' x='180' y='120' angle='0.5' width='260' "
                                  "depth='190' height='220'>") +
                              members + "</furnitureGroup></home>";
  const std::string separate = std::string("<home>") + members + "</home>";
  rr::ImportOptions options;
  options.furniture_models = true;
  options.read_companion = [&](const std::string& name) -> std::optional<std::string> {
    return name == "thing.obj" ? std::optional<std::string>(model) : std::nullopt;
  };
  const ImportResult group = rr::import_sweethome3d(grouped, options);
  const json& solids = group.request["scene"]["solids"];
  ASSERT_EQ(solids.size(), 1u);
  EXPECT_EQ(solids[0]["id"], "G (/home/furnitureGroup/0)");
  ASSERT_EQ(solids[0]["parts"].size(), 4u);
  EXPECT_EQ(solids[0]["parts"][2]["name"], "B red");
  EXPECT_EQ(solids[0]["parts"][0]["transform"], solids[0]["parts"][1]["transform"]);
  auto points = [](const json& request) {
    json scene = request["scene"];
    scene["walls"] = json::array();
    const rr::PolygonSoup soup = rr::tessellate(rr::request_from_json(json{{"scene", scene}}).scene.geometry);
    return soup;
  };
  const rr::PolygonSoup a = points(group.request), b = points(rr::import_sweethome3d(separate, options).request);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.polygons.size(), b.polygons.size());
  double worst = 0.0;
  for (size_t i = 0; i < a.positions.size(); ++i) worst = std::max(worst, glm::length(a.positions[i] - b.positions[i]));
  EXPECT_LT(worst, 1e-12) << "the group's parts are where its members stand";
}

// Three pieces of one model: two plain ones share its meshes, the mirrored one has its own; every
// piece stretches them to its size, and inlining gives the request made without refs.
TEST(ImportSh3d, EachDistinctModelIsOneMeshPlacedByRef) {
  const std::string model =
      "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 0 0 4\nv 2 0 4\nv 2 1 4\nv 0 1 4\n"
      "usemtl red\nf 2 3 7 6\nusemtl plain\nf 1 5 8 4\n";
  const char* home = R"(<home>
    <pieceOfFurniture name='A' model='thing.obj' x='100' y='100' width='100' depth='50' height='200'/>
    <pieceOfFurniture name='B' model='thing.obj' x='300' y='100' angle='1' width='60' depth='30' height='80'/>
    <pieceOfFurniture name='C' model='thing.obj' x='500' y='100' width='100' depth='50' height='200' modelMirrored='true'/>
  </home>)";
  rr::ImportOptions options;
  options.furniture_models = true;
  options.mesh_refs = true;
  options.read_companion = [&](const std::string& name) -> std::optional<std::string> {
    return name == "thing.obj" ? std::optional<std::string>(model) : std::nullopt;
  };
  ImportResult refs = rr::import_sweethome3d(home, options);
  const json& solids = refs.request["scene"]["solids"];
  ASSERT_EQ(solids.size(), 3u);       // one piece each, of two parts
  EXPECT_EQ(refs.meshes.size(), 4u);  // two groups x (plain, mirrored)
  auto ref = [&](size_t s, size_t p) { return solids[s]["parts"][p]["ref"]; };
  EXPECT_EQ(ref(0, 0), ref(1, 0));
  EXPECT_NE(ref(0, 0), ref(2, 0));
  EXPECT_EQ(solids[1]["size"], json::array({0.6, 0.8, 0.3}));
  EXPECT_NEAR(solids[1]["rotation_y"].get<double>(), -180.0 / rr::pi, 1e-9);
  for (const auto& [key, mesh] : refs.meshes) {
    for (const json& v : mesh["vertices"]) {
      for (const json& c : v) EXPECT_LE(std::abs(c.get<double>()), 0.5 + 1e-12) << key;  // the unit box
    }
  }
  // The mirrored mesh is the plain one with x negated and every face reversed.
  const json &plain = refs.meshes.at(ref(0, 0)), &mirrored = refs.meshes.at(ref(2, 0));
  ASSERT_EQ(plain["faces"].size(), 1u);
  ASSERT_EQ(mirrored["faces"].size(), 1u);
  const json& f0 = plain["faces"][0];
  const json& f1 = mirrored["faces"][0];
  ASSERT_EQ(f0.size(), f1.size());
  for (size_t k = 0; k < f0.size(); ++k) {
    const json& a = plain["vertices"][f0[k].get<size_t>()];
    const json& b = mirrored["vertices"][f1[f1.size() - 1 - k].get<size_t>()];
    EXPECT_EQ(a[0].get<double>(), -b[0].get<double>());
    EXPECT_EQ(a[1], b[1]);
    EXPECT_EQ(a[2], b[2]);
  }
  ImportResult inlined = refs;
  rr::inline_mesh_refs(inlined);
  options.mesh_refs = false;
  EXPECT_EQ(inlined.request, rr::import_sweethome3d(home, options).request);
  EXPECT_NO_THROW(rr::request_from_json(inlined.request));
}

// --- the example homes -------------------------------------------------------------------------------

struct XmlWall {
  std::string id;
  double x0, y0, x1, y1, thickness;
};

// 3BedroomApartment.xml has one storey, no arc walls and every door or window inside one wall, so
// each <wall> is one wall and each <doorOrWindow> one opening.
TEST(ImportSh3d, ExampleHomeMatchesItsXml) {
  auto dir = rr::testing::shared_data_dir();
  if (!dir) GTEST_SKIP() << "../shared/data is absent";
  std::string xml = rr::testing::read_file(*dir / "floorplans/sweethome3d/3BedroomApartment.xml");
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(xml.c_str()));
  std::vector<XmlWall> walls;
  double total_length_m = 0.0;
  for (pugi::xpath_node n : doc.select_nodes("//wall")) {
    pugi::xml_node w = n.node();
    walls.push_back({w.attribute("id").value(), w.attribute("xStart").as_double(), w.attribute("yStart").as_double(),
                     w.attribute("xEnd").as_double(), w.attribute("yEnd").as_double(),
                     w.attribute("thickness").as_double()});
    total_length_m += std::hypot(walls.back().x1 - walls.back().x0, walls.back().y1 - walls.back().y0) / 100.0;
  }
  size_t pieces = doc.select_nodes("//doorOrWindow").size();
  ImportResult r = rr::import_sweethome3d(xml);
  const json& out = r.request["scene"]["walls"];
  ASSERT_EQ(out.size(), walls.size());
  double imported_length = 0.0;
  size_t openings = 0;
  for (const json& w : out) {
    imported_length += std::hypot(w["end"][0].get<double>() - w["start"][0].get<double>(),
                                  w["end"][1].get<double>() - w["start"][1].get<double>());
    openings += w["openings"].size();
  }
  EXPECT_EQ(openings, pieces);
  EXPECT_NEAR(imported_length, total_length_m, 1e-4);  // endpoints are rounded to the micrometre
  // Each door or window is an opening of the wall whose centreline crosses its footprint (the
  // nearest such wall), centred where its centre projects onto that wall.
  for (pugi::xpath_node n : doc.select_nodes("//doorOrWindow")) {
    pugi::xml_node d = n.node();
    const double x = d.attribute("x").as_double(), y = d.attribute("y").as_double();
    const XmlWall* best = nullptr;
    double best_distance = 1e9, along = 0.0;
    for (const XmlWall& w : walls) {
      const double length = std::hypot(w.x1 - w.x0, w.y1 - w.y0);
      const double ux = (w.x1 - w.x0) / length, uy = (w.y1 - w.y0) / length;
      const double t = (x - w.x0) * ux + (y - w.y0) * uy, distance = std::abs((x - w.x0) * uy - (y - w.y0) * ux);
      const double reach = d.attribute("depth").as_double() / 2.0 + w.thickness / 2.0;
      if (t < 0 || t > length || distance > reach || distance >= best_distance) continue;
      best = &w, best_distance = distance, along = t / 100.0;
    }
    ASSERT_NE(best, nullptr) << d.attribute("name").value() << " at " << x << ", " << y;
    const json* wall = find_by_id(out, best->id);
    ASSERT_NE(wall, nullptr) << best->id;
    bool found = false;
    for (const json& o : (*wall)["openings"]) {
      const double centre = o["offset"].get<double>() + 0.5 * o["width"].get<double>();
      found = found || (std::abs(centre - along) < 1e-3 &&
                        std::abs(o["width"].get<double>() - d.attribute("width").as_double() / 100.0) < 1e-3);
    }
    EXPECT_TRUE(found) << d.attribute("name").value() << " is not an opening of " << best->id << " at " << along;
  }
}

// Models multiply the polygons (Studio: 513 -> ~35,000), so only one home renders them here.
TEST(ImportSh3d, ExampleHomeWithFurnitureModels) {
  auto dir = rr::testing::shared_data_dir();
  if (!dir) GTEST_SKIP() << "../shared/data is absent";
  const auto home_dir = *dir / "floorplans/sweethome3d";
  rr::ImportOptions options;
  options.furniture_models = true;
  options.read_companion = [&](const std::string& name) -> std::optional<std::string> {
    if (!std::filesystem::exists(home_dir / name)) return std::nullopt;
    return rr::testing::read_file(home_dir / name);
  };
  std::string xml = rr::testing::read_file(home_dir / "Studio.xml");
  ImportResult boxes = rr::import_sweethome3d(xml);
  ImportResult models = rr::import_sweethome3d(xml, options);
  for (const std::string& w : models.warnings) EXPECT_EQ(w.find("not found"), std::string::npos) << w;
  // One solid per piece either way: a box, or a piece of its model's parts.
  const json& pieces = models.request["scene"]["solids"];
  ASSERT_EQ(pieces.size(), boxes.request["scene"]["solids"].size());
  size_t parts = 0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    EXPECT_EQ(pieces[i]["type"], "piece") << pieces[i]["id"];
    EXPECT_EQ(pieces[i]["id"], boxes.request["scene"]["solids"][i]["id"]);
    EXPECT_EQ(pieces[i]["center"], boxes.request["scene"]["solids"][i]["center"]);
    parts += pieces[i]["parts"].size();
  }
  EXPECT_GT(parts, 2 * pieces.size());
  EXPECT_EQ(models.request["scene"]["walls"], boxes.request["scene"]["walls"]);
  EXPECT_GT(rr::testing::covered_share(models.request, "zbuffer"), 0.5);
}

class ExampleHome : public ::testing::TestWithParam<std::filesystem::path> {};

// The top-level pieces of furniture, lamps and groups of a Home.xml, read with pugixml: those shown
// (visible), with a size, and groups holding a shown piece or lamp at any depth (not only doors and
// windows, which become openings).
std::vector<std::string> top_level_furniture(const std::string& xml) {
  pugi::xml_document doc;
  EXPECT_TRUE(doc.load_string(xml.c_str()));
  std::function<bool(pugi::xml_node)> holds_furniture = [&](pugi::xml_node group) {
    for (pugi::xml_node m : group.children()) {
      if (!m.attribute("visible").as_bool(true)) continue;
      const std::string kind = m.name();
      if (kind == "pieceOfFurniture" || kind == "light" || (kind == "furnitureGroup" && holds_furniture(m)))
        return true;
    }
    return false;
  };
  std::vector<std::string> out;
  std::map<std::string, size_t> count;
  for (pugi::xml_node e : doc.document_element().children()) {
    const std::string kind = e.name();
    if (kind != "pieceOfFurniture" && kind != "light" && kind != "furnitureGroup") continue;
    const std::string pointer = "/home/" + kind + "/" + std::to_string(count[kind]++);
    if (!e.attribute("visible").as_bool(true) || !(e.attribute("width").as_double() > 0.01)) continue;
    if (kind == "furnitureGroup" && !holds_furniture(e)) continue;
    out.push_back(pointer);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Each top-level piece, lamp and group of the home is one piece of its models (every model is in
// furniture/, so none falls back to a box), named by its pointer; no other solid comes from
// furniture (the rest are sloped wall tops).
TEST_P(ExampleHome, GivesOnePiecePerTopLevelPiece) {
  const std::string xml = rr::testing::read_file(GetParam());
  rr::ImportOptions options;
  options.furniture_models = true;
  options.mesh_refs = true;
  const auto dir = GetParam().parent_path();
  options.read_companion = [&](const std::string& name) -> std::optional<std::string> {
    if (!std::filesystem::exists(dir / name)) return std::nullopt;
    return rr::testing::read_file(dir / name);
  };
  const ImportResult r = rr::import_sweethome3d(xml, options);
  std::vector<std::string> pieces;
  for (const json& s : r.request["scene"]["solids"]) {
    if (s["type"] == "mesh") continue;
    EXPECT_EQ(s["type"], "piece") << s["id"];
    const std::string id = s["id"];
    pieces.push_back(id.substr(id.rfind(" (/home/") + 2, id.size() - id.rfind(" (/home/") - 3));
  }
  std::sort(pieces.begin(), pieces.end());
  const std::vector<std::string> expected = top_level_furniture(xml);
  EXPECT_EQ(pieces, expected);
  std::printf("[ pieces ] %-32s %3zu pieces for %3zu top-level pieces, lamps and groups\n",
              GetParam().stem().string().c_str(), pieces.size(), expected.size());
}

TEST_P(ExampleHome, ImportsAndRendersWithEveryPipeline) {
  ImportResult r = rr::import_sweethome3d(rr::testing::read_file(GetParam()));
  EXPECT_GT(r.request["scene"]["walls"].size(), 10u);
  for (const std::string& pipeline : rr::testing::pipeline_names()) {
    // The observer stands inside the home: walls, floors and furniture fill most of the view.
    EXPECT_GT(rr::testing::covered_share(r.request, pipeline), 0.5) << pipeline;
  }
}

INSTANTIATE_TEST_SUITE_P(SharedData, ExampleHome,
                         ::testing::ValuesIn(rr::testing::shared_files("floorplans/sweethome3d", ".xml")),
                         [](const auto& param_info) { return rr::testing::test_name_of(param_info.param); });
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ExampleHome);

}  // namespace

namespace {

// A 4 m x 3 m room and one wall along its north edge (from (0, 0) to (4, 0): its left side faces
// -z, away from the room), with the textures given, seen from inside the room toward the wall.
std::string textured_home(const std::string& room_textures, const std::string& wall_textures) {
  return "<home wallHeight='250'><observerCamera attribute='observerCamera' x='200' y='280' z='160' "
         "yaw='3.1415927' pitch='0.3' fieldOfView='1.2'/>\n"
         "  <wall id='w' xStart='0' yStart='0' xEnd='400' yEnd='0' height='250' thickness='10' "
         "leftSideColor='FF00FF00'>" +
         wall_textures +
         "</wall>\n"
         "  <room name='R' floorColor='FF0000FF'><point x='0' y='0'/><point x='400' y='0'/>"
         "<point x='400' y='300'/><point x='0' y='300'/>" +
         room_textures + "</room>\n</home>\n";
}

std::string data_uri_of_file(const std::filesystem::path& path) {
  return *rr::import_detail::image_data_uri(rr::testing::read_file(path));
}

const std::filesystem::path catalogue_textures =
    std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "catalogue" / "textures";

}  // namespace

// Without the images in the file, catalogue ids resolve to the bundled default textures. Sizes in cm
// times `scale` become metres, angles radians -> degrees, offsets stay fractions of a tile; a textured
// side loses its colour (white under the image).
TEST(ImportSh3d, CatalogueTexturesOnRoomsAndWallSides) {
  const std::string home = textured_home(
      "<texture attribute='floorTexture' catalogId='eTeks#redTiles' name='Red tiles' width='40' height='40' "
      "xOffset='0.25' angle='0.5235988' scale='2' image='redTiles.jpg'/>"
      "<texture attribute='ceilingTexture' catalogId='eTeks#roughcast' name='Roughcast' width='20' height='20' "
      "image='roughcast.jpg'/>",
      "<texture attribute='leftSideTexture' catalogId='eTeks#smallBricks' name='Bricks' width='23' height='14.9' "
      "yOffset='0.5' image='smallBricks.jpg'/>");
  ImportResult r = rr::import_sweethome3d(home);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  const json& room = r.request["scene"]["rooms"][0];
  ASSERT_TRUE(room.contains("floor_texture")) << room.dump().substr(0, 300);
  const json& floor = room["floor_texture"];
  EXPECT_EQ(floor["image"], data_uri_of_file(catalogue_textures / "redTiles.jpg"));
  EXPECT_DOUBLE_EQ(floor["width"].get<double>(), 0.8);
  EXPECT_DOUBLE_EQ(floor["height"].get<double>(), 0.8);
  EXPECT_DOUBLE_EQ(floor["x_offset"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(floor["y_offset"].get<double>(), 0.0);
  EXPECT_NEAR(floor["angle"].get<double>(), 30.0, 1e-5);
  EXPECT_FALSE(room.contains("floor_color"));
  EXPECT_EQ(room["ceiling_texture"]["image"], data_uri_of_file(catalogue_textures / "roughcast.jpg"));
  const json& wall = r.request["scene"]["walls"][0];
  ASSERT_TRUE(wall.contains("left_texture"));
  EXPECT_FALSE(wall.contains("right_texture"));
  EXPECT_EQ(wall["left_texture"]["image"], data_uri_of_file(catalogue_textures / "smallBricks.jpg"));
  EXPECT_DOUBLE_EQ(wall["left_texture"]["width"].get<double>(), 0.23);
  EXPECT_DOUBLE_EQ(wall["left_texture"]["y_offset"].get<double>(), 0.5);
  // The request is valid and its textured polygons are the floor, the ceiling and the wall's left side.
  const rr::RenderRequest request = rr::request_from_json(r.request);
  const rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  size_t textured = 0;
  for (const rr::Polygon& p : soup.polygons) textured += p.uv_map != 0;
  EXPECT_GE(textured, 3u);
  // Every one of the 26 catalogue ids resolves, and only those.
  size_t bundled = 0;
  for (const auto& entry : std::filesystem::directory_iterator(catalogue_textures)) {
    const std::string id = "eTeks#" + entry.path().stem().string();
    ASSERT_TRUE(rr::import_detail::catalogue_texture(id)) << id;
    EXPECT_EQ(*rr::import_detail::catalogue_texture(id), rr::testing::read_file(entry.path())) << id;
    ++bundled;
  }
  EXPECT_EQ(bundled, 26u);
  EXPECT_FALSE(rr::import_detail::catalogue_texture("eTeks#nothing"));
  EXPECT_FALSE(rr::import_detail::catalogue_texture("redTiles"));
}

// The file's own image comes first (a .sh3d names its entries "0", "1", ...; the format is told from
// the bytes); a missing image without a known catalogue id, or bytes that are no image, leave the
// surface untextured with a warning naming the line; fittingArea stretches one tile over the room.
TEST(ImportSh3d, TextureImagesComeFromTheArchiveThenTheCatalogue) {
  const std::string png = rr::encode_png(rr::testing::random_image(8, 8, 3));
  const std::string home = textured_home(
      "<texture attribute='floorTexture' catalogId='eTeks#redTiles' name='Mine' width='40' height='40' "
      "fittingArea='true' image='0'/>"
      "<texture attribute='ceilingTexture' name='Lost' width='40' height='40' image='7'/>",
      "<texture attribute='rightSideTexture' name='Text' width='40' height='40' image='1'/>");
  const std::string zip = rr::testing::make_zip({{"Home.xml", home}, {"0", png}, {"1", "not an image"}});
  ImportResult r = rr::import_file_text(zip, rr::ImportFormat::sweethome3d);
  const json& room = r.request["scene"]["rooms"][0];
  EXPECT_EQ(room["floor_texture"]["image"], *rr::import_detail::image_data_uri(png));
  EXPECT_DOUBLE_EQ(room["floor_texture"]["width"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(room["floor_texture"]["height"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(room["floor_texture"]["x_offset"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(room["floor_texture"]["y_offset"].get<double>(), -1.0);  // the image's bottom at z = 3
  EXPECT_FALSE(room.contains("ceiling_texture"));
  EXPECT_FALSE(r.request["scene"]["walls"][0].contains("right_texture"));
  ASSERT_EQ(r.warnings.size(), 2u) << json(r.warnings).dump();
  EXPECT_NE(r.warnings[0].find("line 2: <wall> rightSideTexture image '1' is neither a PNG nor a JPEG"),
            std::string::npos)
      << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("line 3: <room> ceilingTexture image '7' is neither in the file nor in the default"),
            std::string::npos)
      << r.warnings[1];
}

// A piece's <texture> goes on every part of its model with no colour of its own (white under the
// image); a <material>'s texture only on the parts of that material; the piece's colour wins over
// both, as in Sweet Home 3D; a piece drawn as a box takes its texture too. Tile sizes as for rooms.
TEST(ImportSh3d, PieceAndMaterialTexturesGoOnTheirParts) {
  const std::string chair =
      "mtllib chair.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
      "usemtl seat\nf 1 2 3 4\nusemtl legs\nf 1 2 6 5\n";
  const std::string mtl = "newmtl seat\nKd 1 0 0\nnewmtl legs\nKd 0 0 1\n";
  auto piece = [](const std::string& name, const std::string& attributes, const std::string& children) {
    return "<pieceOfFurniture name='" + name + "' model='furniture/chair.obj' x='100' y='100' width='50' " +
           "depth='50' height='90' " + attributes + ">" + children + "</pieceOfFurniture>\n";
  };
  const std::string tiles =
      "<texture catalogId='eTeks#blueTiles' name='Blue tiles' width='30' height='30' "
      "image='blueTiles.jpg'/>";
  const std::string home =
      "<home wallHeight='250'>\n" + piece("Whole", "", tiles) +
      piece("Seat", "",
            "<material name='seat'><texture catalogId='eTeks#oldWoodenFloor' name='Wood' width='60' "
            "height='60' image='2'/></material><material name='legs' color='FF00FF00'/>") +
      piece("Painted", "color='FF808080'", tiles) +
      "<pieceOfFurniture name='Crate' model='furniture/missing.obj' x='300' y='100' width='50' depth='50' "
      "height='50'>" +
      tiles + "</pieceOfFurniture>\n</home>\n";
  const std::string zip =
      rr::testing::make_zip({{"Home.xml", home}, {"furniture/chair.obj", chair}, {"furniture/chair.mtl", mtl}});
  rr::ImportOptions options;
  options.furniture_models = true;
  ImportResult r = rr::import_file_text(zip, rr::ImportFormat::sweethome3d, options);
  const json& solids = r.request["scene"]["solids"];
  ASSERT_EQ(solids.size(), 4u) << solids.dump().substr(0, 400);
  const std::string blue = data_uri_of_file(catalogue_textures / "blueTiles.jpg");
  const std::string wood = data_uri_of_file(catalogue_textures / "oldWoodenFloor.jpg");
  auto part = [&](size_t solid, const std::string& name) {
    for (const json& p : solids[solid]["parts"]) {
      if (p["name"] == name) return p;
    }
    ADD_FAILURE() << "no part " << name << " in " << solids[solid].dump().substr(0, 300);
    return json();
  };
  for (const char* name : {"seat", "legs"}) {
    const json whole = part(0, name);
    EXPECT_EQ(whole["texture"]["image"], blue) << name;
    EXPECT_DOUBLE_EQ(whole["texture"]["width"].get<double>(), 0.3);
    EXPECT_FALSE(whole.contains("color")) << name;
  }
  EXPECT_EQ(part(1, "seat")["texture"]["image"], wood);  // "2" is not in the archive: the catalogue's
  EXPECT_DOUBLE_EQ(part(1, "seat")["texture"]["height"].get<double>(), 0.6);
  EXPECT_FALSE(part(1, "legs").contains("texture"));
  EXPECT_EQ(part(1, "legs")["color"], json::array({0.0, 1.0, 0.0}));
  for (const char* name : {"seat", "legs"}) EXPECT_FALSE(part(2, name).contains("texture")) << name;
  EXPECT_EQ(solids[3]["type"], "box");
  EXPECT_EQ(solids[3]["texture"]["image"], blue);
  EXPECT_FALSE(solids[3].contains("color"));
  // The request reads, and the textured parts are drawn textured.
  const rr::RenderRequest request = rr::request_from_json(r.request);
  const rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  size_t textured = 0;
  for (const rr::Polygon& p : soup.polygons) textured += p.uv_map != 0;
  EXPECT_EQ(textured, 2u + 1u + 6u);  // both faces of Whole, Seat's seat, the crate's six
}

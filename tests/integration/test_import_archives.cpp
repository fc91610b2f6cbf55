// Zips over POST /v1/import/{sh3d,obj} on the real server: every Sweet Home 3D home of ../shared
// zipped with the furniture it names (skipped without ../shared) imports with its models, stores and
// renders with every pipeline (zbuffer and bsp under sanitizers); its furniture polygons equal those of `roomrender
// import --furniture models`; a .sh3d laid out as Sweet Home 3D writes it (numbered model entries) imports the same; an
// OBJ zip brings its .mtl colours; a .sh3d with textures on a room floor, a wall side and a piece (one
// image in the archive, two from the bundled catalogue) and an OBJ zip with its map_Kd images store
// each image once and render textured; hostile and broken archives
// get the documented 4xx naming the entry, quickly.
#include "render/core/hash.hpp"
#include "render/core/image.hpp"
#include "render/core/tessellate.hpp"
#include "render/import/import.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server_fixture.hpp"
#include "support/image_bytes.hpp"
#include "support/sweet_homes.hpp"
#include "support/zip_builder.hpp"

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <regex>
#include <set>

namespace {

using nlohmann::json;
using namespace rr::testing;
using rr::testing::make_zip;
using rr::testing::ZipEntry;
namespace fs = std::filesystem;

fs::path home_dir() { return *rr::testing::shared_data_dir() / "floorplans/sweethome3d"; }

std::vector<fs::path> homes() { return rr::testing::sweet_home_files(); }

std::string base_name(const std::string& path) { return path.substr(path.rfind('/') + 1); }

std::string home_zip(const fs::path& home) { return rr::testing::sweet_home_zip(home); }

// Sweet Home 3D's own layout: Home.xml naming each model by its entry, "0", "1", ... for a model of
// one file, "N/name.obj" beside "N/name.mtl" for a model with a material library.
std::string sh3d_archive(const fs::path& home) {
  std::string xml = rr::testing::read_file(home);
  std::vector<ZipEntry> models;
  int next = 0;
  for (const std::string& model : rr::testing::sweet_home_model_names(xml)) {
    const fs::path file = home.parent_path() / "furniture" / base_name(model);
    if (!fs::exists(file)) continue;
    std::string obj = rr::testing::read_file(file);
    std::vector<std::string> libraries = rr::testing::obj_material_libraries(obj);
    std::string entry = std::to_string(next++);
    if (!libraries.empty()) {
      entry += '/';  // appended apart: GCC 12's -Wrestrict misfires on "/" + std::string here
      entry += file.filename().string();
      for (const std::string& mtl : libraries) {
        models.push_back(
            {entry.substr(0, entry.find('/') + 1) + mtl, rr::testing::read_file(file.parent_path() / mtl)});
      }
    }
    models.push_back({entry, std::move(obj)});
    for (const char quote : {'\'', '"'}) {
      const std::string from = std::string("model=") + quote + model + quote,
                        to = std::string("model=") + quote + entry + quote;
      for (size_t at = xml.find(from); at != std::string::npos; at = xml.find(from, at + to.size()))
        xml.replace(at, from.size(), to);
    }
  }
  models.insert(models.begin(), {"Home", "Java-serialised home: not read"});
  models.insert(models.begin(), {"Home.xml", xml});
  return make_zip(models);
}

struct Furniture {
  size_t polygons = 0;
  rr::Vec3 lo{1e18}, hi{-1e18};
};

// The polygons of a request's furniture (solids that come from <pieceOfFurniture>, <light> or
// <furnitureGroup>).
Furniture furniture_of(const json& request) {
  json only = request;
  json solids = json::array();
  for (const json& s : request["scene"]["solids"]) {
    const std::string id = s.value("id", "");
    for (const char* kind : {"/pieceOfFurniture/", "/light/", "/furnitureGroup/"}) {
      if (id.find(kind) != std::string::npos) {
        solids.push_back(s);
        break;
      }
    }
  }
  only["scene"]["solids"] = solids;
  only["scene"]["walls"] = json::array();
  rr::PolygonSoup soup = rr::tessellate(rr::request_from_json(only).scene.geometry);
  Furniture f;
  f.polygons = soup.polygons.size();
  for (const rr::Polygon& p : soup.polygons) {
    for (const rr::Vec3& v : soup.points(p)) f.lo = glm::min(f.lo, v), f.hi = glm::max(f.hi, v);
  }
  return f;
}

void expect_same_furniture(const Furniture& a, const Furniture& b, const std::string& what) {
  EXPECT_EQ(a.polygons, b.polygons) << what;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.lo[k], b.lo[k], 1e-3) << what << " axis " << k;
    EXPECT_NEAR(a.hi[k], b.hi[k], 1e-3) << what << " axis " << k;
  }
}

// zbuffer and bsp always; every other pipeline too outside sanitizer builds, where the slow ones on
// 200,000 polygons would take minutes.
std::vector<std::string> pipelines() {
  std::vector<std::string> names{"zbuffer", "bsp"};
#ifndef __SANITIZE_ADDRESS__
  for (const rr::PipelineInfo& info : rr::pipeline_table()) {
    if (std::find(names.begin(), names.end(), info.name) == names.end()) names.push_back(info.name);
  }
#endif
  return names;
}

httplib::Result post_zip(httplib::Client& client, const std::string& path, const std::string& zip) {
  return client.Post(path.c_str(), zip, "application/zip");
}

TEST(ArchiveImport, EveryHomeImportsWithItsModelsStoresAndRenders) {
  if (homes().empty()) GTEST_SKIP() << "../shared/data is absent";
  // A cold BSP build of the largest home (218k polygons) passes the default 10 s deadline under
  // sanitizers; this test checks that the homes render, not how fast.
  rr::server::ServerConfig config = test_server_config();
  config.render_timeout_ms = 110000;
  TestServer server(config);
  auto client = server.client(120);
  const fs::path dir = rr::testing::output_dir("integration") / "archive_homes";
  fs::create_directories(dir);
  for (const fs::path& home : homes()) {
    const std::string name = home.stem().string();
    const std::string zip = home_zip(home);
    rr::testing::write_file(dir / (name + ".zip"), zip);  // the zip a user would send
    auto stored = post_zip(client, "/v1/import/sh3d?store=1&width=96&height=72", zip);
    ASSERT_TRUE(stored) << name;
    ASSERT_EQ(stored->status, 201) << name << ": " << stored->body.substr(0, 400);
    json receipt = json::parse(stored->body);
    for (const json& w : receipt["warnings"])
      EXPECT_EQ(w.get<std::string>().find("not found"), std::string::npos) << name << ": " << w;
    auto scene = client.Get(receipt["location"].get<std::string>().c_str());
    ASSERT_TRUE(scene);
    ASSERT_EQ(scene->status, 200);
    const json document = json::parse(scene->body);
    size_t pieces = 0, meshes = 0;
    for (const json& s : document["solids"]) {
      meshes += s.contains("ref");
      pieces += s["type"] == "piece";
      for (const json& part : s.value("parts", json::array())) meshes += part.contains("ref");
    }
    EXPECT_GT(meshes, 20u) << name;
    EXPECT_LT(scene->body.size(), 1u << 20) << name;  // each mesh is stored once, apart from the scene
    std::printf("[ archive ] %-34s zip %8zu B, stored scene %9zu B, %zu pieces, %zu placements of a stored mesh\n",
                name.c_str(), zip.size(), scene->body.size(), pieces, meshes);
    for (const std::string& pipeline : pipelines()) {
      json view = {{"camera", receipt["camera"]}, {"options", {{"width", 96}, {"height", 72}, {"pipeline", pipeline}}}};
      auto png =
          client.Post((receipt["location"].get<std::string>() + "/render").c_str(), view.dump(), "application/json");
      ASSERT_TRUE(png) << name << " " << pipeline;
      ASSERT_EQ(png->status, 200) << name << " " << pipeline << ": " << png->body.substr(0, 300);
      EXPECT_EQ(png_size(png->body).width, 96u);
    }
    // The stored scene draws the polygons of the request answered without store=1.
    auto inline_import = post_zip(client, "/v1/import/sh3d?width=96&height=72", zip);
    ASSERT_TRUE(inline_import);
    ASSERT_EQ(inline_import->status, 200);
    const size_t inline_polygons =
        rr::tessellate(rr::request_from_json(json::parse(inline_import->body)).scene.geometry).polygons.size();
    // Every level and every ceiling, so that the view leaves no polygon out of the count.
    json all_levels = json::array();
    for (const json& level : document.value("levels", json::array())) all_levels.push_back(level["id"]);
    json options = {{"width", 96}, {"height", 72}, {"ceilings", "on"}};
    if (!all_levels.empty()) options["levels"] = all_levels;
    json view = {{"camera", receipt["camera"]}, {"options", options}};
    httplib::Headers accept_json = {{"Accept", "application/json"}};
    auto counted = client.Post((receipt["location"].get<std::string>() + "/render").c_str(), accept_json, view.dump(),
                               "application/json");
    ASSERT_TRUE(counted);
    ASSERT_EQ(counted->status, 200) << counted->body.substr(0, 300);
    EXPECT_EQ(json::parse(counted->body)["counts"]["polygons"].get<size_t>(), inline_polygons) << name;
    // The next home's meshes and scene fit beside it; deleting keeps the store small all the same.
    auto deleted = client.Delete(receipt["location"].get<std::string>().c_str());
    ASSERT_TRUE(deleted);
    EXPECT_EQ(deleted->status, 204);
  }
  expect_healthy(server);
}

// The mesh form (distinct meshes + "ref" placements) is what store=1 will keep; its size per home.
TEST(ArchiveImport, RefFormPlacesEachDistinctMeshOnceAndInlinesToTheSamePolygons) {
  if (homes().empty()) GTEST_SKIP() << "../shared/data is absent";
  for (const fs::path& home : homes()) {
    rr::ImportOptions options;
    options.furniture_models = true;
    options.mesh_refs = true;
    rr::ImportResult refs = rr::import_file_text(home_zip(home), rr::ImportFormat::sweethome3d, options);
    size_t placed = 0, mesh_bytes = 0;
    rr::for_each_mesh_holder(refs.request["scene"]["solids"], [&](json& holder) {
      if (!holder.contains("ref")) return;
      ++placed;
      EXPECT_TRUE(refs.meshes.contains(holder["ref"].get<std::string>())) << holder["ref"];
      EXPECT_FALSE(holder.contains("vertices"));
    });
    for (const auto& [key, mesh] : refs.meshes) mesh_bytes += mesh.dump().size();
    const size_t scene_bytes = refs.request["scene"].dump().size();
    std::printf("[ archive ] %-34s scene with refs %7zu B (%zu placements), %3zu distinct meshes %8zu B\n",
                home.stem().string().c_str(), scene_bytes, placed, refs.meshes.size(), mesh_bytes);
    EXPECT_LT(scene_bytes, 1u << 20) << home;
    EXPECT_LT(refs.meshes.size(), placed) << home;  // some model is placed more than once in every home
    rr::ImportResult inlined = refs;
    rr::inline_mesh_refs(inlined);
    EXPECT_TRUE(inlined.meshes.empty());
    options.mesh_refs = false;
    rr::ImportResult direct = rr::import_file_text(home_zip(home), rr::ImportFormat::sweethome3d, options);
    EXPECT_EQ(inlined.request, direct.request) << home;
  }
}

// The furniture of an HTTP import of the zip equals that of the CLI reading the home from disk.
TEST(ArchiveImport, FurnitureEqualsTheCliImportWithModels) {
  if (homes().empty()) GTEST_SKIP() << "../shared/data is absent";
  TestServer server;
  auto client = server.client(120);
  const fs::path dir = rr::testing::output_dir("integration") / "archive_cli";
  fs::create_directories(dir);
  for (const std::string name : {"3BedroomHouseWithMezzanine", "Studio"}) {
    const fs::path home = home_dir() / (name + ".xml");
    auto res = post_zip(client, "/v1/import/sh3d?width=96&height=72", home_zip(home));
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body.substr(0, 400);
    const std::string command = "'" ROOMRENDER_BINARY_DIR "/roomrender' import '" + home.string() +
                                "' --furniture models --width 96 --height 72 >'" + (dir / "out.json").string() +
                                "' 2>/dev/null";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command;
    const json cli = json::parse(rr::testing::read_file(dir / "out.json"));
    const Furniture http = furniture_of(json::parse(res->body)), disk = furniture_of(cli);
    EXPECT_GT(http.polygons, 1000u) << name;
    expect_same_furniture(http, disk, name);
    // The CLI reads the same zip as the server does.
    rr::testing::write_file(dir / "home.zip", home_zip(home));
    const std::string zipped = "'" ROOMRENDER_BINARY_DIR "/roomrender' import '" + (dir / "home.zip").string() +
                               "' --furniture models >'" + (dir / "zip.json").string() + "' 2>/dev/null";
    const int zip_status = std::system(zipped.c_str());
    ASSERT_TRUE(WIFEXITED(zip_status) && WEXITSTATUS(zip_status) == 0) << zipped;
    expect_same_furniture(furniture_of(json::parse(rr::testing::read_file(dir / "zip.json"))), disk, name + " zip");
    std::printf("[ archive ] %s: %zu furniture polygons over HTTP and from the CLI\n", name.c_str(), http.polygons);
  }
}

TEST(ArchiveImport, Sh3dLayoutWithNumberedModelEntriesImportsTheSameFurniture) {
  if (homes().empty()) GTEST_SKIP() << "../shared/data is absent";
  TestServer server;
  auto client = server.client(120);
  for (const std::string name : {"Studio", "2BedroomApartment"}) {
    const fs::path home = home_dir() / (name + ".xml");
    const std::string sh3d = sh3d_archive(home);
    rr::testing::write_file(rr::testing::output_dir("integration") / (name + ".sh3d"), sh3d);
    auto numbered = client.Post("/v1/import/sh3d?width=96&height=72", sh3d, "application/vnd.sweethome3d");
    auto plain = post_zip(client, "/v1/import/sh3d?width=96&height=72", home_zip(home));
    ASSERT_TRUE(numbered && plain);
    ASSERT_EQ(numbered->status, 200) << numbered->body.substr(0, 400);
    ASSERT_EQ(plain->status, 200);
    const json request = json::parse(numbered->body);
    EXPECT_EQ(numbered->get_header_value("X-Warning-Count"), plain->get_header_value("X-Warning-Count"));
    expect_same_furniture(furniture_of(request), furniture_of(json::parse(plain->body)), name);
    auto png = client.Post("/v1/render", request.dump(), "application/json");
    if (request.dump().size() < 8u << 20) {
      ASSERT_TRUE(png);
      EXPECT_EQ(png->status, 200);
    }
  }
}

// How many distinct RGB colours a PNG holds: a textured surface shows hundreds where a plain one shows
// a few shades.
size_t distinct_colours(const std::string& png) {
  const rr::Image image = rr::decode_png(png);
  std::set<uint32_t> colours;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* p = image.pixel(x, y);
      colours.insert(uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]);
    }
  }
  return colours.size();
}

const char* kHome = R"(<home><wall id='w' xStart='0' yStart='0' xEnd='400' yEnd='0' thickness='10' height='250'/>
<pieceOfFurniture name='Chair' model='furniture/chair.obj' x='100' y='100' width='50' depth='50' height='90'/>
</home>)";
const char* kChair = "mtllib chair.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf 1 2 3 4\n";

// A room whose floor names the default catalogue's red tiles (no image in the archive: the bundled
// one is used), a wall whose inner (right) side carries the archive's entry "0" (a PNG of noise),
// and a piece with the blue tiles over its model, seen from inside. Stored with
// store=1, the scene names each image by the id of its bytes, stored once in the image store; rendered,
// it shows far more colours than the same home without its <texture> elements.
TEST(ArchiveImport, Sh3dTexturesOnAFloorAWallSideAndAPieceStoreEachImageOnceAndRenderTextured) {
  const fs::path catalogue = rr::testing::source_dir() / "catalogue/textures";
  // The archive's own image: not one of the catalogue's, which the server holds from the start.
  const std::string noise = rr::encode_png(rr::testing::random_image(64, 64, 11));
  auto home = [](const std::string& floor, const std::string& wall, const std::string& piece) {
    return "<home wallHeight='250'><observerCamera attribute='observerCamera' x='200' y='280' z='160' "
           "yaw='3.1415927' pitch='0.25' fieldOfView='1.2'/>\n"
           "<wall id='w' xStart='0' yStart='0' xEnd='400' yEnd='0' height='250' thickness='10'>" +
           wall +
           "</wall>\n<room name='R'><point x='0' y='0'/><point x='400' y='0'/><point x='400' y='300'/>"
           "<point x='0' y='300'/>" +
           floor +
           "</room>\n<pieceOfFurniture name='Panel' model='furniture/panel.obj' x='200' y='150' width='120' "
           "depth='10' height='120'>" +
           piece + "</pieceOfFurniture>\n</home>\n";
  };
  const std::string panel = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 0.1\nf 1 2 3 4\nf 1 5 2\n";
  const std::string floor =
      "<texture attribute='floorTexture' catalogId='eTeks#redTiles' name='Red tiles' width='40' height='40' "
      "image='redTiles.jpg'/>";
  const std::string wall =
      "<texture attribute='rightSideTexture' catalogId='eTeks#smallBricks' name='Bricks' width='23' "
      "height='14.9' image='0'/>";
  const std::string piece =
      "<texture catalogId='eTeks#blueTiles' name='Blue tiles' width='30' height='30' image='blueTiles.jpg'/>";
  TestServer server;
  auto client = server.client(60);
  auto import_and_draw = [&](const std::string& xml, const std::vector<ZipEntry>& more, json* stored_scene) {
    std::vector<ZipEntry> entries{{"Home.xml", xml}, {"furniture/panel.obj", panel}};
    entries.insert(entries.end(), more.begin(), more.end());
    auto stored =
        client.Post("/v1/import/sh3d?store=1&width=160&height=120", make_zip(entries), "application/vnd.sweethome3d");
    EXPECT_TRUE(stored && stored->status == 201) << (stored ? stored->body.substr(0, 300) : "no answer");
    if (!stored || stored->status != 201) return size_t{0};
    const json receipt = json::parse(stored->body);
    EXPECT_TRUE(receipt["warnings"].empty()) << receipt["warnings"];
    auto scene = client.Get(receipt["location"].get<std::string>().c_str());
    EXPECT_TRUE(scene && scene->status == 200);
    if (scene && stored_scene) *stored_scene = json::parse(scene->body);
    const json view = {{"camera", receipt["camera"]}, {"options", {{"width", 160}, {"height", 120}}}};
    auto png =
        client.Post((receipt["location"].get<std::string>() + "/render").c_str(), view.dump(), "application/json");
    EXPECT_TRUE(png && png->status == 200) << (png ? png->body.substr(0, 300) : "no answer");
    if (!png || png->status != 200) return size_t{0};
    return distinct_colours(png->body);
  };
  const size_t plain = import_and_draw(home("", "", ""), {}, nullptr);
  json scene;
  const size_t textured = import_and_draw(home(floor, wall, piece), {{"0", noise}}, &scene);
  std::printf("[ textures ] distinct colours: %zu untextured, %zu textured; stored scene %zu B\n", plain, textured,
              scene.dump().size());
  EXPECT_GT(plain, 0u);
  EXPECT_GT(textured, 10 * plain);
  // Each image is named by the id of its bytes and served by the image store as they were.
  const std::string text = scene.dump();
  EXPECT_EQ(text.find("data:"), std::string::npos);
  std::map<std::string, std::string> images = {
      {"/rooms/0/floor_texture/image", rr::testing::read_file(catalogue / "redTiles.jpg")},
      {"/walls/0/right_texture/image", noise},
      {"/solids/0/parts/0/texture/image", rr::testing::read_file(catalogue / "blueTiles.jpg")}};
  std::set<std::string> ids;
  for (const auto& [pointer, bytes] : images) {
    const json::json_pointer at(pointer);
    ASSERT_TRUE(scene.contains(at)) << pointer << " in " << text.substr(0, 400);
    const std::string id = scene.at(at).get<std::string>();
    EXPECT_EQ(id, rr::hash_hex(bytes)) << pointer;
    ids.insert(id);
    auto served = client.Get(("/v1/textures/" + id).c_str());
    ASSERT_TRUE(served);
    EXPECT_EQ(served->status, 200) << pointer;
    EXPECT_TRUE(served->body == bytes) << pointer;
  }
  EXPECT_EQ(ids.size(), 3u);
  // The archive's image stays while the scene names it; the catalogue's are read-only.
  auto refused = client.Delete(("/v1/textures/" + rr::hash_hex(noise)).c_str());
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 409);
  auto catalogue_image = client.Delete(("/v1/textures/" + rr::hash_hex(images.begin()->second)).c_str());
  ASSERT_TRUE(catalogue_image);
  EXPECT_EQ(catalogue_image->status, 403);
}

// The fireplace room's OBJ with its .mtl and the images its map_Kd lines name, zipped as a user
// would, imported with store=1: four images stored once each, and the stored scene drawn from inside
// shows far more colours than the same zip without its images.
TEST(ArchiveImport, ObjZipWithItsImagesStoresThemOnceAndRendersTextured) {
  const std::optional<fs::path> shared = rr::testing::shared_data_dir();
  if (!shared) GTEST_SKIP() << "../shared/data is absent";
  const fs::path room = *shared / "meshes/fireplace_room";
  std::vector<ZipEntry> entries = {{"fireplace_room_uv.obj", rr::testing::read_file(room / "fireplace_room_uv.obj")},
                                   {"fireplace_room_uv.mtl", rr::testing::read_file(room / "fireplace_room_uv.mtl")}};
  const std::vector<ZipEntry> without_images = entries;
  for (const auto& file : fs::directory_iterator(room / "textures")) {
    entries.push_back({"textures/" + file.path().filename().string(), rr::testing::read_file(file.path())});
  }
  TestServer server;
  auto client = server.client(120);
  // The accuracy bench's camera of this room (its box: x -0.51 .. 5.12, y 0 .. 2.88, z -3.64 .. 0.59):
  // inside, near the +x wall, looking along -x.
  const json view = {{"camera", {{"position", {4.67, 1.58, -1.52}}, {"target", {0.05, 1.0, -1.52}}, {"fov_y", 60}}},
                     {"options", {{"width", 160}, {"height", 120}}}};
  auto import_and_draw = [&](const std::vector<ZipEntry>& files, json* stored_scene) {
    auto stored = client.Post("/v1/import/obj?store=1", make_zip(files), "application/zip");
    EXPECT_TRUE(stored && stored->status == 201) << (stored ? stored->body.substr(0, 300) : "no answer");
    if (!stored || stored->status != 201) return size_t{0};
    const std::string location = json::parse(stored->body)["location"];
    if (stored_scene) *stored_scene = json::parse(client.Get(location.c_str())->body);
    auto png = client.Post((location + "/render").c_str(), view.dump(), "application/json");
    EXPECT_TRUE(png && png->status == 200) << (png ? png->body.substr(0, 300) : "no answer");
    if (!png || png->status != 200) return size_t{0};
    return distinct_colours(png->body);
  };
  json scene;
  const size_t textured = import_and_draw(entries, &scene);
  const size_t plain = import_and_draw(without_images, nullptr);
  std::set<std::string> ids;
  size_t textures = 0;
  for (const json& solid : scene["solids"]) {
    if (!solid.contains("texture")) continue;
    ++textures;
    ids.insert(solid["texture"]["image"].get<std::string>());
  }
  std::printf(
      "[ textures ] fireplace room: %zu colours textured, %zu without images; %zu textured solids, %zu "
      "images; stored scene %zu B\n",
      textured, plain, textures, ids.size(), scene.dump().size());
  EXPECT_EQ(scene.dump().find("data:"), std::string::npos);
  EXPECT_EQ(ids.size(), 4u);
  for (const std::string& id : ids) {
    auto served = client.Get(("/v1/textures/" + id).c_str());
    ASSERT_TRUE(served);
    EXPECT_EQ(served->status, 200) << id;
  }
  EXPECT_GT(textured, 5 * plain);
}

// Images a request could not use, in a .sh3d laid out as Sweet Home 3D writes it: a header claiming
// 100,000 x 100,000 pixels, a JPEG cut in its first 20 bytes, a GIF, an entry over the 4 MiB a request
// takes per image (all refused from their first bytes by the importer), and a JPEG cut inside its
// scan data (its header reads; storing it decodes it, which fails). Each surface stays untextured
// with a warning naming its line and entry or pointer; the home imports, inline and stored, quickly,
// and the server stays healthy. Inline, the cut JPEG reaches the render, which refuses it at its pointer.
TEST(ArchiveImport, BadImagesInAnArchiveLeaveTheirSurfacesUntexturedWithAWarning) {
  const std::string jpeg = rr::testing::read_file(rr::testing::source_dir() / "catalogue/textures/smallBricks.jpg");
  auto texture = [](const char* attribute, const char* entry) {
    return std::string("<texture attribute='") + attribute + "' name='T' width='40' height='40' image='" + entry +
           "'/>";
  };
  const std::string xml =
      "<home wallHeight='250'><observerCamera attribute='observerCamera' x='200' y='280' z='160' "
      "yaw='3.1415927' pitch='0.25' fieldOfView='1.2'/>\n"
      "<wall id='w' xStart='0' yStart='0' xEnd='400' yEnd='0' height='250' thickness='10'>" +
      texture("rightSideTexture", "2") + texture("leftSideTexture", "3") +
      "</wall>\n<room name='R'><point x='0' y='0'/><point x='400' y='0'/><point x='400' y='300'/>"
      "<point x='0' y='300'/>" +
      texture("floorTexture", "0") + texture("ceilingTexture", "1") +
      "</room>\n<room name='S'><point x='0' y='300'/><point x='400' y='300'/><point x='400' y='400'/>"
      "<point x='0' y='400'/>" +
      texture("floorTexture", "4") + "</room>\n</home>\n";
  std::string oversized = rr::testing::png_head(64, 64);
  oversized.resize((4u << 20) + 1, '\0');
  const std::string body = make_zip({{"Home", "serialized Java objects we do not read"},
                                     {"Home.xml", xml},
                                     {"ContentDigests", ""},
                                     {"0", rr::testing::png_head(100000, 100000)},
                                     {"1", jpeg.substr(0, 20)},
                                     {"2", "GIF89a\x01\x00\x01\x00 not an image we take"},
                                     {"3", oversized, false},  // stored: zeros would deflate past the bomb ratio
                                     {"4", jpeg.substr(0, jpeg.size() * 6 / 10)}});
  TestServer server;
  auto client = server.client(60);
  const std::vector<std::pair<std::string, std::string>> said_by_importer = {
      {"rightSideTexture image '2'", "is neither a PNG nor a JPEG"},
      {"leftSideTexture image '3'", "has 4194305 bytes, more than the 4194304"},
      {"floorTexture image '0'", "is refused: PNG header says 100000 x 100000 pixels"},
      {"ceilingTexture image '1'", "is refused: JPEG header unreadable"}};
  auto expect_said = [&](const json& warnings, const std::string& what, const std::string& says) {
    for (const json& w : warnings) {
      const std::string text = w.get<std::string>();
      if (text.find(what) != std::string::npos && text.find(says) != std::string::npos) return;
    }
    ADD_FAILURE() << "no warning on " << what << " saying " << says << " in " << warnings.dump();
  };
  for (const bool store : {false, true}) {
    const auto start = std::chrono::steady_clock::now();
    auto imported =
        client.Post(store ? "/v1/import/sh3d?store=1&width=96&height=72" : "/v1/import/sh3d?width=96&height=72", body,
                    "application/vnd.sweethome3d");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(imported);
    ASSERT_EQ(imported->status, store ? 201 : 200) << imported->body.substr(0, 400);
    EXPECT_LT(seconds, 5.0);
    const json answer = json::parse(imported->body);
    const json warnings = store ? answer["warnings"] : json();
    std::printf("[ bad images ] %s: %d in %.2f s, %s\n", store ? "store=1" : "inline", imported->status, seconds,
                imported->get_header_value("X-Warning-Count").c_str());
    if (!store) {
      EXPECT_EQ(imported->get_header_value("X-Warning-Count"), "4") << answer["scene"]["rooms"].dump().substr(0, 300);
      // The cut JPEG's header reads, so the request carries it; the render decodes it and refuses it there.
      const json& floor = answer["scene"]["rooms"][1]["floor_texture"];
      ASSERT_TRUE(floor.is_object()) << answer["scene"]["rooms"].dump().substr(0, 300);
      json request = answer;
      auto rendered = client.Post("/v1/render", request.dump(), "application/json");
      const json problem = expect_problem(rendered, 422);
      EXPECT_EQ(problem["errors"][0]["pointer"], "/scene/rooms/1/floor_texture/image") << problem.dump();
      EXPECT_NE(problem.dump().find("JPEG data unreadable"), std::string::npos) << problem.dump();
      continue;
    }
    for (const auto& [what, says] : said_by_importer) expect_said(warnings, what, says);
    expect_said(warnings, "/rooms/1/floor_texture", "JPEG data unreadable");
    EXPECT_EQ(warnings.size(), 5u) << warnings.dump();
    // The stored scene names no image and draws.
    const std::string location = answer["location"];
    EXPECT_EQ(client.Get(location.c_str())->body.find("texture"), std::string::npos);
    const json view = {{"camera", answer["camera"]}, {"options", {{"width", 96}, {"height", 72}}}};
    auto png = client.Post((location + "/render").c_str(), view.dump(), "application/json");
    ASSERT_TRUE(png);
    EXPECT_EQ(png->status, 200) << png->body.substr(0, 300);
  }
  expect_healthy(server);
}

TEST(ArchiveImport, ObjZipAppliesItsMaterialLibrary) {
  TestServer server;
  auto client = server.client();
  const std::string obj = kChair;
  auto zipped = post_zip(client, "/v1/import/obj",
                         make_zip({{"models/chair.obj", obj}, {"models/chair.mtl", "newmtl red\nKd 1 0 0\n"}}));
  ASSERT_TRUE(zipped);
  ASSERT_EQ(zipped->status, 200) << zipped->body;
  EXPECT_EQ(json::parse(zipped->body)["scene"]["solids"][0]["color"], json::array({1.0, 0.0, 0.0}));
  EXPECT_EQ(zipped->get_header_value("X-Warning-Count"), "0");
  auto plain = client.Post("/v1/import/obj", obj, "model/obj");  // the .mtl cannot come with plain text
  ASSERT_TRUE(plain);
  ASSERT_EQ(plain->status, 200);
  EXPECT_EQ(json::parse(plain->body)["scene"]["solids"][0]["color"], json::array({0.7, 0.7, 0.7}));
}

struct BadArchive {
  std::string what, format, body;
  int status;
  std::string pointer, says;
};

// OBJ comment lines of seeded pseudo-random letters: text that deflates to a long stream.
std::string comment_lines(size_t lines) {
  std::string out;
  uint32_t state = 12345;
  for (size_t i = 0; i < lines; ++i) {
    out += "# ";
    for (int k = 0; k < 60; ++k) out += char('a' + ((state = state * 1664525u + 1013904223u) >> 24) % 26);
    out += "\n";
  }
  return out;
}

std::vector<BadArchive> bad_archives() {
  const std::string chair = kChair;
  std::string corrupt = make_zip({{"Home.xml", kHome}, {"furniture/chair.obj", chair + comment_lines(400)}});
  const size_t data = corrupt.find("furniture/chair.obj") + 19 + 2000;  // well inside its deflated data
  for (size_t k = 0; k < 32; ++k) corrupt[data + k] = char(~corrupt[data + k]);
  const std::string bomb = make_zip({{"Home.xml", kHome}, {"furniture/chair.obj", std::string(48u << 20, '\n')}});
  std::string over_total = make_zip({{"Home.xml", kHome}, {"a", "1"}, {"b", "2"}, {"c", "3"}});
  for (const char* name : {"a", "b", "c"}) over_total = rr::testing::with_declared_size(over_total, name, 100u << 20);
  std::vector<ZipEntry> many{{"Home.xml", kHome}};
  for (int i = 0; i < 10'000; ++i) many.push_back({"t/" + std::to_string(i), "", false});
  const std::string whole = make_zip({{"Home.xml", kHome}, {"furniture/chair.obj", chair}});
  std::string stored_bad_crc = make_zip({{"Home.xml", kHome, false}});
  const size_t wall = stored_bad_crc.find("<wall");
  stored_bad_crc[wall + 1] = 'W';  // the CRC no longer matches; the XML would still parse
  // libzip will not write a name twice: write two names of one length, then make them equal.
  std::string twice = make_zip({{"Home.xml", kHome}, {"Home.xmm", kHome}});
  for (size_t at = twice.find("Home.xmm"); at != std::string::npos; at = twice.find("Home.xmm"))
    twice.replace(at, 8, "Home.xml");
  const std::string image_home =
      "<home><room><point x='0' y='0'/><point x='100' y='0'/><point x='0' y='100'/>"
      "<texture attribute='floorTexture' name='T' width='40' height='40' image='0'/>"
      "</room></home>";
  const std::string image_bomb = make_zip({{"Home.xml", image_home}, {"0", std::string(48u << 20, '\0')}});
  return {
      {"bomb by ratio", "sh3d", bomb, 413, "/entry/furniture~1chair.obj", "zip bomb"},
      {"image entry a bomb", "sh3d", image_bomb, 413, "/entry/0", "zip bomb"},
      {"bomb with a lying header", "sh3d", rr::testing::with_declared_size(bomb, "furniture/chair.obj", 2000), 413,
       "/entry/furniture~1chair.obj", ""},
      {"total size over the cap", "sh3d", over_total, 413, "/entry/c", "256 MiB"},
      {"more entries than the cap", "sh3d", make_zip(many), 413, "/entry/t~19999", "10000"},
      {"traversal", "sh3d", make_zip({{"Home.xml", kHome}, {"../x", "1"}}), 422, "/entry/..~1x", "traversal"},
      {"absolute name", "obj", make_zip({{"a.obj", chair}, {"/etc/x", "1"}}), 422, "/entry/~1etc~1x", "absolute"},
      {"truncated zip", "sh3d", whole.substr(0, whole.size() - 60), 400, "/entry/furniture~1chair.obj", "truncated"},
      {"not a zip", "sh3d", "PK\x03\x04 this is no archive", 400, "", "zip"},
      {"no XML inside", "sh3d", make_zip({{"readme.txt", "hello"}}), 422, "/entry", "no home"},
      {"two XMLs", "sh3d", make_zip({{"A.xml", kHome}, {"B.xml", kHome}}), 422, "/entry/B.xml", "more than one"},
      {"only the Java-serialised Home", "sh3d", make_zip({{"Home", "\xac\xed"}}), 422, "/entry/Home", "re-save"},
      {"corrupt deflate stream", "sh3d", corrupt, 400, "/entry/furniture~1chair.obj", "corrupt"},
      {"OBJ index out of range", "obj", make_zip({{"m/model.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n"}}), 422,
       "/entry/m~1model.obj/line/3", "vertex index 7"},
      {"two OBJs", "obj", make_zip({{"a.obj", chair}, {"b.obj", chair}}), 422, "/entry/b.obj", "more than one"},
      {"malformed Home.xml", "sh3d", make_zip({{"Home.xml", "<home>\n<wall"}}), 400, "/entry/Home.xml/line/2", "XML"},
      {"duplicate entry", "sh3d", twice, 422, "/entry/Home.xml", "twice"},
      {"NaN vertex", "obj", make_zip({{"a.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"}}), 422, "/entry/a.obj/line/2",
       "finite"},
      {"stored entry failing its CRC", "sh3d", stored_bad_crc, 400, "/entry/Home.xml", "corrupt"},
  };
}

TEST(ArchiveImport, BadArchivesGetTheRight4xxNamingTheEntry) {
  TestServer server;
  auto client = server.client();
  for (const BadArchive& bad : bad_archives()) {
    const auto start = std::chrono::steady_clock::now();
    json problem = expect_problem(post_zip(client, "/v1/import/" + bad.format, bad.body), bad.status);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 10.0) << bad.what;  // generous: the point is that nothing inflates without bound
    EXPECT_EQ(problem["errors"][0]["pointer"], bad.pointer) << bad.what << ": " << problem.dump();
    EXPECT_NE(problem["detail"].get<std::string>().find(bad.says), std::string::npos)
        << bad.what << ": " << problem.dump();
    std::printf("[ archive ] %-30s %d %s (%.2f s, %zu B)\n", bad.what.c_str(), bad.status,
                problem["errors"][0]["pointer"].get<std::string>().c_str(), seconds, bad.body.size());
  }
  expect_healthy(server);
}

TEST(ArchiveImport, MissingOrBrokenModelLeavesThePieceABoxWithAWarning) {
  TestServer server;
  auto client = server.client();
  auto missing = post_zip(client, "/v1/import/sh3d", make_zip({{"Home.xml", kHome}}));
  ASSERT_TRUE(missing);
  ASSERT_EQ(missing->status, 200) << missing->body;
  json request = json::parse(missing->body);
  EXPECT_EQ(request["scene"]["solids"].back()["type"], "box");
  EXPECT_EQ(missing->get_header_value("X-Warning-Count"), "2");  // the model, the missing observer camera
  auto broken = post_zip(client, "/v1/import/sh3d?store=1",
                         make_zip({{"Home.xml", kHome}, {"furniture/chair.obj", "v 0 0 0\nf 1 2 3\n"}}));
  ASSERT_TRUE(broken);
  ASSERT_EQ(broken->status, 201) << broken->body;
  const std::string warnings = json::parse(broken->body)["warnings"].dump();
  EXPECT_NE(warnings.find("line 2: vertex index 2 is out of range"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("furniture/chair.obj"), std::string::npos) << warnings;
  expect_problem(client.Post("/v1/import/sh3d?furniture=chairs", kHome, "application/xml"), 400);
  auto boxes = post_zip(client, "/v1/import/sh3d?furniture=boxes",
                        make_zip({{"Home.xml", kHome}, {"furniture/chair.obj", kChair}}));
  ASSERT_TRUE(boxes);
  EXPECT_EQ(json::parse(boxes->body)["scene"]["solids"].back()["type"], "box");
}

}  // namespace

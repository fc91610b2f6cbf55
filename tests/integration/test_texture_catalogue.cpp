// The texture catalogue over HTTP (server/catalogue*.cpp): GET /v1/catalogue/textures lists the
// shipped images with Sweet Home 3D's ids and tile sizes (cacheable, 304 on its ETag); each image is a
// read-only stored image (served byte for byte, its id the hash of the file's bytes as POST
// /v1/textures gives, stored again as "existed", DELETE 403, counted in no budget); a texture naming
// it by id draws what its data: URI draws, the CLI resolves it too, and a stored scene using it pins
// nothing and survives a restart with --data-dir.
#include "cli/cli.hpp"
#include "render/core/hash.hpp"
#include "render/pipelines/render.hpp"
#include "server_fixture.hpp"
#include "support/image_bytes.hpp"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace {

using nlohmann::json;
using namespace rr::testing;

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

class TextureCatalogue : public SharedServerTest<TextureCatalogue> {
 protected:
  static json entry(const std::string& catalog_id) {
    const json all = json::parse(client().Get("/v1/catalogue/textures")->body);
    for (const json& t : all["textures"]) {
      if (t["catalog_id"] == catalog_id) return t;
    }
    ADD_FAILURE() << "no catalogue texture " << catalog_id;
    return json();
  }
  // small_request with its floor textured by `image` at `size_m` a tile.
  static json textured_request(const std::string& image, double size_m) {
    json request = json::parse(small_request);
    request["scene"]["floor"]["texture"] = {{"image", image}, {"width", size_m}, {"height", size_m}};
    return request;
  }
};

TEST_F(TextureCatalogue, ListsTheShippedImagesWithTheirIdsAndTileSizes) {
  auto res = client().Get("/v1/catalogue/textures");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  const json answer = json::parse(res->body);
  ASSERT_EQ(answer["textures"].size(), 26u);
  EXPECT_NE(answer["attribution"].get<std::string>().find("© Emmanuel Puybaret / eTeks"), std::string::npos);
  EXPECT_NE(answer["licence"].get<std::string>().find("CC BY 3.0"), std::string::npos);
  std::set<std::string> ids, categories;
  for (const json& t : answer["textures"]) {
    const std::string id = t["id"];
    ids.insert(id);
    categories.insert(t["category"].get<std::string>());
    EXPECT_EQ(t["url"], "/v1/textures/" + id);
    EXPECT_EQ(t["catalog_id"].get<std::string>().rfind("eTeks#", 0), 0u);
    // The id is the hash of the shipped file's bytes: what POST /v1/textures of them answers.
    const std::string file = t["catalog_id"].get<std::string>().substr(6) + ".jpg";
    EXPECT_EQ(id, rr::hash_hex(read_bytes(std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "catalogue/textures" / file)));
  }
  EXPECT_EQ(ids.size(), 26u);
  EXPECT_EQ(categories, (std::set<std::string>{"Floor", "Sky", "Wall"}));
  const json wood = entry("eTeks#woodenFloor");
  EXPECT_EQ(wood["name"], "Wooden floor");
  EXPECT_EQ(wood["size_cm"], json({{"width", 42.5}, {"height", 42.5}}));
  EXPECT_EQ(wood["pixels"], json({{"width", 256}, {"height", 256}}));
  EXPECT_EQ(entry("eTeks#smallBricks")["size_cm"], json({{"width", 23.0}, {"height", 14.9}}));

  const std::string etag = res->get_header_value("ETag");
  ASSERT_FALSE(etag.empty());
  EXPECT_EQ(client().Get("/v1/catalogue/textures", {{"If-None-Match", etag}})->status, 304);
}

TEST_F(TextureCatalogue, ItsImagesAreReadOnlyStoredImages) {
  const std::string id = entry("eTeks#redTiles")["id"];
  const double entries_before = server_->metric("roomrender_store_entries", {"store=\"textures\""});
  auto got = client().Get(("/v1/textures/" + id).c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_EQ(got->get_header_value("Content-Type"), "image/jpeg");
  EXPECT_EQ(got->body, read_bytes(std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "catalogue/textures/redTiles.jpg"));
  auto again = client().Post("/v1/textures", got->body, "image/jpeg");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200) << again->body;
  EXPECT_EQ(json::parse(again->body)["id"], id);
  EXPECT_EQ(server_->metric("roomrender_store_entries", {"store=\"textures\""}), entries_before);
  const json problem = expect_problem(client().Delete(("/v1/textures/" + id).c_str()), 403);
  EXPECT_NE(problem["detail"].get<std::string>().find("texture catalogue"), std::string::npos);
  EXPECT_EQ(client().Get(("/v1/textures/" + id).c_str())->status, 200);
}

TEST_F(TextureCatalogue, ATextureNamingItByIdDrawsItsDataUriAndAStoredSceneKeepsIt) {
  const json wood = entry("eTeks#woodenFloor");
  const std::string id = wood["id"];
  const std::string jpeg = client().Get(("/v1/textures/" + id).c_str())->body;
  const json by_id = textured_request(id, 0.425);
  auto rendered = client().Post("/v1/render", by_id.dump(), "application/json");
  ASSERT_TRUE(rendered);
  ASSERT_EQ(rendered->status, 200) << rendered->body;
  auto inline_image =
      client().Post("/v1/render", textured_request("data:image/jpeg;base64," + base64_encode(jpeg), 0.425).dump(),
                    "application/json");
  ASSERT_TRUE(inline_image);
  EXPECT_EQ(inline_image->body, rendered->body);
  EXPECT_NE(client().Post("/v1/render", small_request, "application/json")->body, rendered->body) << "textured";
  // The CLI resolves the same id from the source tree's catalogue: the same bytes.
  rr::RenderRequest parsed = rr::request_from_json(by_id, rr::cli::request_limits());
  rr::PreparedScene prepared = rr::prepare_scene(parsed.scene);
  rr::RenderContext context;
  EXPECT_EQ(rr::render(parsed, prepared, context).png, rendered->body);

  // Stored, the scene pins nothing: the image is read-only, not "used by".
  auto stored = client().Post("/v1/scenes", by_id["scene"].dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string scene = json::parse(stored->body)["id"];
  EXPECT_EQ(client().Delete(("/v1/textures/" + id).c_str())->status, 403);
  json view = by_id;
  view.erase("scene");
  auto again = client().Post(("/v1/scenes/" + scene + "/render").c_str(), view.dump(), "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->body, rendered->body);
  EXPECT_EQ(client().Delete(("/v1/scenes/" + scene).c_str())->status, 204);
}

TEST(TextureCatalogueRestart, AStoredSceneWithACatalogueTextureLoadsAgain) {
  const std::filesystem::path dir = fresh_output_dir();
  auto config = test_server_config();
  config.data_dir = dir;
  json scene;
  std::string id, png;
  {
    TestServer server(config);
    const json answer = json::parse(server.client().Get("/v1/catalogue/textures")->body);
    scene = json::parse(small_request)["scene"];
    scene["floor"]["texture"] = {{"image", answer["textures"][0]["id"]}, {"width", 0.2}, {"height", 0.2}};
    auto stored = server.client().Post("/v1/scenes", scene.dump(), "application/json");
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->status, 201) << stored->body;
    id = json::parse(stored->body)["id"];
    png = server.client().Post(("/v1/scenes/" + id + "/render").c_str(), "{}", "application/json")->body;
  }
  TestServer again(config);
  auto rendered = again.client().Post(("/v1/scenes/" + id + "/render").c_str(), "{}", "application/json");
  ASSERT_TRUE(rendered);
  EXPECT_EQ(rendered->status, 200) << rendered->body;
  EXPECT_EQ(rendered->body, png);
  // No file of a catalogue image was written: they are not the store's.
  EXPECT_FALSE(std::filesystem::exists(dir / "textures") && !std::filesystem::is_empty(dir / "textures"));
}

}  // namespace

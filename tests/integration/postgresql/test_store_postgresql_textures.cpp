// Stored images in the shared store (--store postgresql://...): the encoded bytes in rr_textures as
// bytea, read back byte-identical through another server after the first has gone; a stored scene
// whose texture names the image pins it through rr_texture_placements (409 until the scene is
// deleted), and the fill row counts its bytes; a scene naming a catalogue image pins nothing.
#include "postgres_cluster.hpp"
#include "support/image_bytes.hpp"

namespace {

using nlohmann::json;
using namespace rr::testing;

json scene_textured_by(const std::string& image) {
  json scene = json::parse(small_request)["scene"];
  scene["floor"]["texture"] = {{"image", image}, {"width", 0.5}, {"height", 0.5}};
  return scene;
}

TEST_F(PostgresStoreTest, StoredImagesReadBackByteIdenticalAndStayWhileAStoredSceneUsesThem) {
  const std::string png = rr::encode_png(random_image(16, 8, 5));
  std::string id, scene_id, drawn;
  {
    TestServer first(config());
    auto posted = first.client().Post("/v1/textures", png, "image/png");
    ASSERT_TRUE(posted);
    ASSERT_EQ(posted->status, 201) << posted->body;
    id = json::parse(posted->body).at("id");
    auto again = first.client().Post("/v1/textures", png, "application/octet-stream");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200) << again->body;
    auto stored = first.client().Post("/v1/scenes", scene_textured_by(id).dump(), "application/json");
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->status, 201) << stored->body;
    scene_id = json::parse(stored->body).at("id");
    drawn = first.client().Get(("/v1/scenes/" + scene_id + "/render.png?width=64&height=48").c_str())->body;
  }
  EXPECT_EQ(sql("SELECT count(*) FROM rr_textures"), "1");
  EXPECT_EQ(sql("SELECT length(body) FROM rr_textures"), std::to_string(png.size()));
  EXPECT_EQ(sql("SELECT entries || ' ' || bytes FROM rr_usage WHERE kind = 'texture'"),
            "1 " + std::to_string(png.size()));
  EXPECT_EQ(sql("SELECT texture_id FROM rr_texture_placements WHERE scene_id = '" + scene_id + "'"), id);

  TestServer second(config());  // a new process: nothing in its cache
  auto got = second.client().Get(("/v1/textures/" + id).c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_TRUE(got->body == png) << "GET answered other bytes than were stored";
  EXPECT_EQ(got->get_header_value("Content-Type"), "image/png");
  auto png_again = second.client().Get(("/v1/scenes/" + scene_id + "/render.png?width=64&height=48").c_str());
  ASSERT_TRUE(png_again);
  ASSERT_EQ(png_again->status, 200) << png_again->body;
  EXPECT_TRUE(png_again->body == drawn) << "drawn otherwise through another server";

  const json refused = expect_problem(second.client().Delete(("/v1/textures/" + id).c_str()), 409);
  EXPECT_NE(refused.at("detail").get<std::string>().find(scene_id), std::string::npos) << refused.dump();
  EXPECT_EQ(second.client().Delete(("/v1/scenes/" + scene_id).c_str())->status, 204);
  EXPECT_EQ(second.client().Delete(("/v1/textures/" + id).c_str())->status, 204);
  expect_problem(second.client().Get(("/v1/textures/" + id).c_str()), 404);
  EXPECT_EQ(sql("SELECT entries || ' ' || bytes FROM rr_usage WHERE kind = 'texture'"), "0 0");
  const json unknown =
      expect_problem(second.client().Post("/v1/scenes", scene_textured_by(id).dump(), "application/json"), 422);
  EXPECT_EQ(unknown.at("errors").at(0).at("pointer"), "/floor/texture/image") << unknown.dump();
}

// A scene naming an image of the texture catalogue (GET /v1/catalogue/textures) is stored without a
// row of rr_textures or rr_texture_placements: the server holds the image itself, read-only.
TEST_F(PostgresStoreTest, ASceneNamingACatalogueImageIsStoredWithoutPinningIt) {
  TestServer server(config());
  const json catalogue = json::parse(server.client().Get("/v1/catalogue/textures")->body);
  ASSERT_FALSE(catalogue.at("textures").empty());
  const std::string id = catalogue["textures"][0]["id"];
  auto stored = server.client().Post("/v1/scenes", scene_textured_by(id).dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string scene_id = json::parse(stored->body).at("id");
  EXPECT_EQ(sql("SELECT count(*) FROM rr_textures"), "0");
  EXPECT_EQ(sql("SELECT count(*) FROM rr_texture_placements"), "0");
  auto drawn = server.client().Get(("/v1/scenes/" + scene_id + "/render.png?width=64&height=48").c_str());
  ASSERT_TRUE(drawn);
  EXPECT_EQ(drawn->status, 200) << drawn->body;
  expect_problem(server.client().Delete(("/v1/textures/" + id).c_str()), 403);
}

// A database of the schema before stored images (version 1: scenes and meshes only) is migrated
// when a server first connects: its scenes stay, and images can be stored.
TEST_F(PostgresStoreTest, ADatabaseWithoutTheImageTablesIsMigratedKeepingItsScenes) {
  std::string scene_id;
  {
    TestServer first(config());
    auto stored = first.client().Post("/v1/scenes", json::parse(small_request)["scene"].dump(), "application/json");
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->status, 201) << stored->body;
    scene_id = json::parse(stored->body).at("id");
  }
  // Back to version 1 as that schema had it.
  sql("DROP TABLE rr_texture_placements, rr_texture_owners, rr_textures; DELETE FROM rr_usage WHERE kind = "
      "'texture'; DELETE FROM rr_schema_version WHERE version = 2");
  ASSERT_EQ(sql("SELECT max(version) FROM rr_schema_version"), "1");

  TestServer second(config());
  auto posted = second.client().Post("/v1/textures", rr::encode_png(random_image(4, 4, 9)), "image/png");
  ASSERT_TRUE(posted);
  EXPECT_EQ(posted->status, 201) << posted->body;
  EXPECT_EQ(sql("SELECT max(version) FROM rr_schema_version"), "2");
  auto scene = second.client().Get(("/v1/scenes/" + scene_id).c_str());
  ASSERT_TRUE(scene);
  EXPECT_EQ(scene->status, 200);
}

}  // namespace

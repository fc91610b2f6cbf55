// Stored images over real HTTP: POST /v1/textures (PNG and JPEG bytes, sniffed; the same bytes
// twice are one image), GET byte for byte with its media type and immutable caching, a texture
// naming the image by id drawing the same PNG as its data: URI, DELETE refused while a stored scene
// uses the image, unknown ids refused at the image's pointer, oversized and non-image bodies
// refused from their first bytes, and the image kept across a restart on the same --data-dir.
#include "server_fixture.hpp"
#include "support/image_bytes.hpp"

#include <chrono>
#include <filesystem>

namespace {

using nlohmann::json;
using namespace rr::testing;
namespace fs = std::filesystem;

// A 16 x 8 PNG of seeded random texels.
std::string texture_png() { return rr::encode_png(random_image(16, 8, 7)); }

httplib::Result post_texture(const TestServer& server, const std::string& bytes,
                             const std::string& type = "application/octet-stream") {
  return server.client().Post("/v1/textures", bytes, type);
}

// POSTs `bytes` expecting `status`; the answer's id.
std::string store_texture(const TestServer& server, const std::string& bytes, int status) {
  auto res = post_texture(server, bytes);
  EXPECT_TRUE(res);
  if (!res) return "";
  EXPECT_EQ(res->status, status) << res->body;
  return json::parse(res->body).value("id", "");
}

// small_request with its floor textured by `image` (a data: URI or a stored image's id).
json textured_request(const std::string& image) {
  json request = json::parse(small_request);
  request["scene"]["floor"]["texture"] = {{"image", image}, {"width", 0.5}, {"height", 0.5}};
  return request;
}

std::string data_uri(const std::string& png) { return "data:image/png;base64," + base64_encode(png); }

class TextureApiTest : public SharedServerTest<TextureApiTest> {};

TEST_F(TextureApiTest, PostedPngAnswersItsContentIdAndTheSameBytesAgainAnswerTheSameId) {
  const std::string png = texture_png();
  auto res = post_texture(*server_, png, "image/png");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  const json body = json::parse(res->body);
  const std::string id = body.at("id");
  // The id is the decoder's content id of the bytes, so an inline data: URI of them is the same image.
  EXPECT_EQ(id, decode_ok(as_bytes(png))->content_id);
  EXPECT_EQ(body.at("media_type"), "image/png");
  EXPECT_EQ(body.at("width"), 16);
  EXPECT_EQ(body.at("height"), 8);
  EXPECT_EQ(body.at("created"), true);
  EXPECT_EQ(res->get_header_value("Location"), "/v1/textures/" + id);
  // Sent again, under another media type: the format comes from the bytes, and it is stored already.
  EXPECT_EQ(store_texture(*server_, png, 200), id);

  auto got = client().Get(("/v1/textures/" + id).c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_TRUE(got->body == png) << "GET answered other bytes than were stored";
  EXPECT_EQ(got->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(got->get_header_value("ETag"), "\"" + id + "\"");
  EXPECT_EQ(got->get_header_value("Cache-Control"), "public, max-age=31536000, immutable");
  auto not_modified = client().Get(("/v1/textures/" + id).c_str(), {{"If-None-Match", "\"" + id + "\""}});
  ASSERT_TRUE(not_modified);
  EXPECT_EQ(not_modified->status, 304);
}

TEST_F(TextureApiTest, JpegFromTheSharedTexturesIsStoredAndServedAsJpeg) {
  const std::optional<fs::path> shared = shared_data_dir();
  if (!shared) GTEST_SKIP() << "../shared/data is absent";
  // Not one of Sweet Home 3D's: those are the texture catalogue's, stored from the start.
  const std::string jpeg = read_file(*shared / "meshes" / "fireplace_room" / "textures" / "picture8.jpg");
  // Sent as image/png: the bytes say JPEG, and they win.
  auto res = post_texture(*server_, jpeg, "image/png");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  const json body = json::parse(res->body);
  EXPECT_EQ(body.at("media_type"), "image/jpeg");
  auto got = client().Get(("/v1/textures/" + body.at("id").get<std::string>()).c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_TRUE(got->body == jpeg) << "GET answered other bytes than were stored";
  EXPECT_EQ(got->get_header_value("Content-Type"), "image/jpeg");
}

TEST_F(TextureApiTest, ATextureNamingTheStoredImageDrawsTheSameBytesAsItsDataUri) {
  const std::string png = texture_png();
  auto posted = post_texture(*server_, png);  // 201, or 200 when an earlier test stored it
  ASSERT_TRUE(posted);
  ASSERT_TRUE(posted->status == 201 || posted->status == 200) << posted->body;
  const std::string id = json::parse(posted->body).at("id");
  auto inline_res = client().Post("/v1/render", textured_request(data_uri(png)).dump(), "application/json");
  auto by_id = client().Post("/v1/render", textured_request(id).dump(), "application/json");
  ASSERT_TRUE(inline_res && by_id);
  ASSERT_EQ(inline_res->status, 200) << inline_res->body;
  ASSERT_EQ(by_id->status, 200) << by_id->body;
  EXPECT_EQ(by_id->get_header_value("Content-Type"), "image/png");
  EXPECT_TRUE(by_id->body == inline_res->body) << "the id and the data: URI draw different bytes";
  EXPECT_EQ(by_id->get_header_value("X-Scene-Id"), inline_res->get_header_value("X-Scene-Id"));
  // And untextured, the floor draws otherwise: the comparison above can fail.
  auto plain = client().Post("/v1/render", small_request, "application/json");
  ASSERT_TRUE(plain);
  EXPECT_FALSE(plain->body == by_id->body);
}

TEST_F(TextureApiTest, AStoredSceneUsingTheImageKeepsItUntilTheSceneIsDeleted) {
  const std::string id = store_texture(*server_, rr::encode_png(random_image(8, 8, 11)), 201);
  const json scene = textured_request(id)["scene"];
  auto stored = post_scene(*server_, scene);
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string scene_id = json::parse(stored->body).at("id");

  // small_request's camera and size as query parameters.
  auto png = client().Get(
      ("/v1/scenes/" + scene_id + "/render.png?position=3,2.5,4&target=0,0.5,0&width=64&height=48").c_str());
  ASSERT_TRUE(png);
  ASSERT_EQ(png->status, 200) << png->body;
  auto inline_png = client().Post("/v1/render", textured_request(id).dump(), "application/json");
  ASSERT_TRUE(inline_png);
  EXPECT_TRUE(png->body == inline_png->body) << "the stored scene draws what the same request draws";

  const json refused = expect_problem(client().Delete(("/v1/textures/" + id).c_str()), 409);
  EXPECT_NE(refused.at("detail").get<std::string>().find(scene_id), std::string::npos) << refused.dump();
  auto still = client().Get(("/v1/textures/" + id).c_str());
  ASSERT_TRUE(still);
  EXPECT_EQ(still->status, 200);

  ASSERT_EQ(client().Delete(("/v1/scenes/" + scene_id).c_str())->status, 204);
  EXPECT_EQ(client().Delete(("/v1/textures/" + id).c_str())->status, 204);
  expect_problem(client().Get(("/v1/textures/" + id).c_str()), 404);
  expect_problem(client().Delete(("/v1/textures/" + id).c_str()), 404);
  // Gone: a texture naming it is now refused at its pointer, and so is a scene storing it.
  const json unknown =
      expect_problem(client().Post("/v1/render", textured_request(id).dump(), "application/json"), 422);
  EXPECT_EQ(unknown.at("errors").at(0).at("pointer"), "/scene/floor/texture/image");
  expect_problem(post_scene(*server_, scene), 422);
}

TEST_F(TextureApiTest, UnknownAndMalformedIdsAreRefused) {
  const json unknown =
      expect_problem(client().Post("/v1/render", textured_request("0123456789abcdef").dump(), "application/json"), 422);
  EXPECT_EQ(unknown.at("errors").at(0).at("pointer"), "/scene/floor/texture/image");
  EXPECT_NE(unknown.at("errors").at(0).at("detail").get<std::string>().find("no stored image"), std::string::npos)
      << unknown.dump();
  expect_problem(client().Get("/v1/textures/0123456789abcdef"), 404);
  // Not an id: no route takes it.
  expect_problem(client().Get("/v1/textures/0123456789ABCDEF"), 404);
  expect_problem(client().Get("/v1/textures/12345"), 404);
}

TEST_F(TextureApiTest, AHeaderClaimingAHugeImageIsRefusedFromItsHeader) {
  const auto start = std::chrono::steady_clock::now();
  const json refused = expect_problem(post_texture(*server_, png_head(100000, 100000)), 413);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_NE(refused.dump().find("100000"), std::string::npos) << refused.dump();
}

TEST_F(TextureApiTest, ABodyThatIsNoImageIsRefusedNamingWhatItHolds) {
  const json refused = expect_problem(post_texture(*server_, "GIF89a not an image we take"), 422);
  EXPECT_NE(refused.dump().find("not a PNG or JPEG"), std::string::npos) << refused.dump();
  EXPECT_NE(refused.dump().find("GIF"), std::string::npos) << refused.dump();
  expect_problem(post_texture(*server_, std::string(5u << 20, 'x')), 413);
}

TEST(TextureDataDir, AStoredImageAndTheSceneUsingItOutliveARestart) {
  rr::server::ServerConfig config = test_server_config();
  config.data_dir = fresh_output_dir();
  const std::string png = texture_png();
  std::string id, scene_id, drawn;
  {
    TestServer first(config);
    id = store_texture(first, png, 201);
    auto stored = post_scene(first, textured_request(id)["scene"]);
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->status, 201) << stored->body;
    scene_id = json::parse(stored->body).at("id");
    drawn = first.client().Get(("/v1/scenes/" + scene_id + "/render.png?width=64&height=48").c_str())->body;
  }
  EXPECT_TRUE(fs::exists(config.data_dir / "textures" / (id + ".img")));
  TestServer second(config);
  auto got = second.client().Get(("/v1/textures/" + id).c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_TRUE(got->body == png) << "GET answered other bytes than were stored";
  auto png_again = second.client().Get(("/v1/scenes/" + scene_id + "/render.png?width=64&height=48").c_str());
  ASSERT_TRUE(png_again);
  ASSERT_EQ(png_again->status, 200) << png_again->body;
  EXPECT_TRUE(png_again->body == drawn) << "drawn otherwise after the restart";
  // The scene read at start-up pins the image again.
  expect_problem(second.client().Delete(("/v1/textures/" + id).c_str()), 409);
}

}  // namespace

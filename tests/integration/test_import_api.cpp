// POST /v1/import/{format} over real HTTP: files of other tools in, render requests (or stored
// scenes) out; importer errors as problem+json pointing into the file; the real interiors of
// ../shared/data/meshes imported and rendered with every pipeline at 1280x720 (skipped when
// ../shared is absent), printing their polygon counts, BSP figures and render times.
#include "render/pipelines/pipeline.hpp"
#include "server_fixture.hpp"

#include <cstdio>

namespace {

using nlohmann::json;
using namespace rr::testing;

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST(ImportApi, ObjBecomesARequestTheRenderEndpointAccepts) {
  TestServer server;
  auto client = server.client();
  auto imported = client.Post("/v1/import/obj?width=64&height=48", kTriangleObj, "model/obj");
  ASSERT_TRUE(imported);
  ASSERT_EQ(imported->status, 200) << imported->body;
  json request = json::parse(imported->body);
  EXPECT_EQ(request["options"]["width"], 64);
  EXPECT_EQ(request["scene"]["solids"].size(), 1u);
  auto rendered = client.Post("/v1/render", imported->body, "application/json");
  ASSERT_TRUE(rendered);
  EXPECT_EQ(rendered->status, 200);
  EXPECT_EQ(png_size(rendered->body).width, 64u);
}

TEST(ImportApi, StoreTrueStoresTheSceneAndNamesIt) {
  TestServer server;
  auto client = server.client();
  auto res = client.Post("/v1/import/obj?store=1", kTriangleObj, "model/obj");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  json receipt = json::parse(res->body);
  EXPECT_EQ(res->get_header_value("Location"), "/v1/scenes/" + receipt["id"].get<std::string>());
  EXPECT_TRUE(receipt.contains("camera"));
  auto again = client.Get(res->get_header_value("Location").c_str());
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
}

TEST(ImportApi, ImporterErrorsPointIntoTheFile) {
  TestServer server;
  auto client = server.client();
  json bad_index = expect_problem(client.Post("/v1/import/obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n", "model/obj"), 422);
  EXPECT_EQ(bad_index["errors"][0]["pointer"], "/line/3");
  json bad_xml = expect_problem(client.Post("/v1/import/sh3d", "<home>\n<wall", "application/xml"), 400);
  EXPECT_EQ(bad_xml["errors"][0]["pointer"], "/line/2");
  std::string wide = R"(<home><wall id="w" xStart="0" yStart="0" xEnd="100" yEnd="0" thickness="10" height="250"/>
<doorOrWindow name="Door" x="50" y="0" width="300" depth="10" height="210" doorOrWindow="true" wallId="w"/></home>)";
  json too_wide = expect_problem(client.Post("/v1/import/sh3d", wide, "application/xml"), 422);
  EXPECT_FALSE(too_wide["errors"][0]["pointer"].get<std::string>().empty());
  expect_problem(client.Post("/v1/import/pdf", "x", "application/octet-stream"), 404);
  json scale = expect_problem(client.Post("/v1/import/obj?scale=-1", kTriangleObj, "model/obj"), 400);
  EXPECT_EQ(scale["errors"][0]["parameter"], "scale");
  expect_healthy(server);
}

TEST(ImportApi, ImportBodiesHaveTheirOwnLimit) {
  rr::server::ServerConfig config = test_server_config();
  config.max_body_bytes = 1000;
  config.max_import_bytes = 4000;
  TestServer server(config);
  auto client = server.client();
  std::string obj(3000, '#');  // comments only: fits the import limit, not the render limit
  obj += "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  auto ok = client.Post("/v1/import/obj", obj, "model/obj");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200) << ok->body;
  expect_problem(client.Post("/v1/import/obj", std::string(5000, '#'), "model/obj"), 413);
  expect_problem(client.Post("/v1/render", std::string(3000, ' ') + "{}", "application/json"), 413);
}

// The real interiors through the API with each pipeline (needs ../shared/data/meshes).
TEST(ImportApi, RealInteriorsRenderWithEveryPipeline) {
  auto shared = shared_data_dir();
  if (!shared) GTEST_SKIP() << "../shared/data is absent";
  rr::server::ServerConfig config = test_server_config();
  config.render_timeout_ms = 120'000;  // a cold 331k-polygon BSP build on a loaded 2-core machine
  TestServer server(config);
  auto client = server.client(180);
  for (const char* name :
       {"conference/conference", "fireplace_room/fireplace_room", "crytek_sponza_lowpoly/crytek_sponza_lowpoly"}) {
    SCOPED_TRACE(name);
    auto path = *shared / "meshes" / (std::string(name) + ".obj");
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
    auto stored = client.Post("/v1/import/obj?store=1&width=1280&height=720", read_file(path), "model/obj");
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->status, 201) << stored->body.substr(0, 300);
    json receipt = json::parse(stored->body);
    for (const rr::PipelineInfo& p : rr::pipeline_table()) {
      json body = {{"camera", receipt["camera"]},
                   {"options", {{"width", 1280}, {"height", 720}, {"pipeline", p.name}}}};
      httplib::Headers accept = {{"Accept", "application/json"}};
      auto res = client.Post(("/v1/scenes/" + receipt["id"].get<std::string>() + "/render").c_str(), accept,
                             body.dump(), "application/json");
      ASSERT_TRUE(res);
      ASSERT_EQ(res->status, 200) << p.name << ": " << res->body.substr(0, 300);
      json answer = json::parse(res->body);
      json summary = {{"scene", name}, {"pipeline", p.name}};
      for (const char* key : {"timings_ms", "counts", "bsp", "stats"}) {
        if (answer.contains(key)) summary[key] = answer[key];
      }
      std::printf("[interior] %s\n", summary.dump().c_str());
      EXPECT_FALSE(answer.value("png_base64", "").empty());
      // The import's first view is from inside the room: culling leaves hundreds of its polygons drawn
      // (700-800 measured), where a view of nothing or of one wall draws a few.
      EXPECT_GT(answer["counts"]["polygons_drawn"].get<size_t>(), 300u);
    }
  }
}

}  // namespace

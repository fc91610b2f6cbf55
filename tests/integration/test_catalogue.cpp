// The furniture catalogue over HTTP (server/catalogue*.cpp): GET /v1/catalogue lists the shipped
// entries with their real sizes, icons and the piece that places them (cacheable, 304 on its ETag);
// an entry's icon is its PNG; its parts' meshes are read-only documents of the mesh store (served,
// stored again as "existed", DELETE 403, counted in no budget); a scene placing them renders (the
// CLI's request_limits resolves them too), is stored without pinning them, and survives a restart
// with --data-dir; two servers make the same ids.
#include "cli/cli.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/mesh_json.hpp"
#include "server_fixture.hpp"

#include <filesystem>
#include <set>

namespace {

using nlohmann::json;
using namespace rr::testing;

class Catalogue : public SharedServerTest<Catalogue> {
 protected:
  static json catalogue() {
    auto res = client().Get("/v1/catalogue");
    EXPECT_TRUE(res && res->status == 200);
    return res ? json::parse(res->body) : json();
  }
  static json item(const std::string& id) {
    const json all = catalogue();  // held: a range-for over catalogue()["items"] would outlive it
    for (const json& i : all["items"]) {
      if (i["id"] == id) return i;
    }
    ADD_FAILURE() << "no catalogue entry " << id;
    return json();
  }
  // The entry's piece at `center`, in a scene with a floor, and a view of it.
  static json scene_with(const json& entry, rr::Vec2 center) {
    json piece = entry["piece"];
    piece["center"] = {center.x, center.y};
    piece["id"] = entry["id"];
    return {{"floor", {{"cells", {4, 4}}, {"origin", {-2, -2}}}},
            {"solids", {piece}},
            {"lights", {{{"type", "directional"}, {"direction", {-0.3, -1, -0.4}}}}}};
  }
  static json view() {
    return {{"camera", {{"position", {1.2, 1.4, 1.8}}, {"target", {0, 0.4, 0}}}},
            {"options", {{"width", 96}, {"height", 72}}}};
  }
};

TEST_F(Catalogue, ListsTheShippedEntriesWithTheirRealSizesAndIcons) {
  auto res = client().Get("/v1/catalogue");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  const json answer = json::parse(res->body);
  EXPECT_EQ(answer["items"].size(), 37u);
  EXPECT_NE(answer["attribution"].get<std::string>().find("Sweet Home 3D default catalogue"), std::string::npos);
  EXPECT_NE(answer["licence"].get<std::string>().find("CC BY 3.0"), std::string::npos);
  std::set<std::string> ids, categories;
  for (const json& i : answer["items"]) {
    ids.insert(i["id"].get<std::string>());
    categories.insert(i["category"].get<std::string>());
    EXPECT_EQ(i["icon"], "/v1/catalogue/" + i["id"].get<std::string>() + "/icon.png");
    EXPECT_EQ(i["piece"]["type"], "piece");
    EXPECT_FALSE(i["piece"].contains("center"));
    for (int k = 0; k < 3; ++k) EXPECT_GT(i["piece"]["size"][k].get<double>(), 0.0) << i["id"];
    for (const json& part : i["piece"]["parts"]) EXPECT_EQ(part["ref"].get<std::string>().size(), 16u);
  }
  EXPECT_EQ(ids.size(), 37u);
  EXPECT_EQ(categories,
            (std::set<std::string>{"Bathroom", "Bedroom", "Kitchen", "Lights", "Living room", "Miscellaneous"}));
  const json chair = item("chair");
  EXPECT_EQ(chair["name"], "Chair");
  EXPECT_EQ(chair["size_cm"], json({{"width", 40.0}, {"depth", 42.0}, {"height", 90.0}}));
  EXPECT_EQ(chair["piece"]["size"], json::array({0.4, 0.9, 0.42}));
  EXPECT_EQ(item("pendant_lamp")["piece"]["base"], 1.7);  // it hangs at its elevation

  // Cacheable: the same ETag answers 304.
  const std::string etag = res->get_header_value("ETag");
  ASSERT_FALSE(etag.empty());
  EXPECT_EQ(client().Get("/v1/catalogue", {{"If-None-Match", etag}})->status, 304);

  auto icon = client().Get("/v1/catalogue/chair/icon.png");
  ASSERT_TRUE(icon);
  EXPECT_EQ(icon->status, 200);
  EXPECT_EQ(icon->get_header_value("Content-Type"), "image/png");
  EXPECT_GT(png_size(icon->body).width, 0u);
  expect_problem(client().Get("/v1/catalogue/no_such_thing/icon.png"), 404);
}

TEST_F(Catalogue, ItsMeshesAreReadOnlyDocumentsOfTheMeshStore) {
  const json chair = item("chair");
  const std::string ref = chair["piece"]["parts"][0]["ref"];
  // Counted against no document budget: the mesh store's documents and bytes stay as they were.
  const double entries_before = server_->metric("roomrender_store_entries", {"store=\"meshes\""});
  const double bytes_before = server_->metric("roomrender_store_bytes", {"store=\"meshes\""});
  auto got = client().Get(("/v1/meshes/" + ref).c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_EQ(rr::mesh_from_json(json::parse(got->body), {})->content_id, ref);
  // Sending it again is "already stored", and charges nothing.
  auto again = client().Post("/v1/meshes", got->body, "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200) << again->body;
  EXPECT_EQ(json::parse(again->body)["id"], ref);
  EXPECT_EQ(server_->metric("roomrender_store_entries", {"store=\"meshes\""}), entries_before);
  EXPECT_EQ(server_->metric("roomrender_store_bytes", {"store=\"meshes\""}), bytes_before);
  const json problem = expect_problem(client().Delete(("/v1/meshes/" + ref).c_str()), 403);
  EXPECT_NE(problem["detail"].get<std::string>().find("catalogue"), std::string::npos);
  EXPECT_EQ(client().Get(("/v1/meshes/" + ref).c_str())->status, 200);
}

TEST_F(Catalogue, APlacedModelRendersStoresAndPicksWhole) {
  const json chair = item("chair");
  const json scene = scene_with(chair, {0, 0});
  json request = view();
  request["scene"] = scene;
  auto rendered = client().Post("/v1/render", request.dump(), "application/json");
  ASSERT_TRUE(rendered);
  ASSERT_EQ(rendered->status, 200) << rendered->body;
  // The CLI resolves the same refs from the source tree's catalogue: the same bytes.
  rr::RenderRequest parsed = rr::request_from_json(request, rr::cli::request_limits());
  rr::PreparedScene prepared = rr::prepare_scene(parsed.scene);
  rr::RenderContext context;
  EXPECT_EQ(rr::render(parsed, prepared, context).png, rendered->body);
  // Down the image's middle column, the first pixel that shows the chair (a model has gaps: the
  // floor shows through them) is picked as the piece, with its part as a detail.
  json hit;
  for (int y = 0; y < 72 && hit.is_null(); y += 2) {
    json picked = request;
    picked["x"] = 48;
    picked["y"] = y;
    const json answer = json::parse(client().Post("/v1/pick", picked.dump(), "application/json")->body);
    if (answer["pointer"] != "/scene/floor" && !answer["pointer"].is_null()) hit = answer;
  }
  ASSERT_FALSE(hit.is_null()) << "the chair is seen";
  EXPECT_EQ(hit["pointer"], "/scene/solids/0");
  EXPECT_EQ(hit["part"]["pointer"].get<std::string>().rfind("/scene/solids/0/parts/", 0), 0u) << hit;

  // Stored, the scene pins none of them: they stay whatever is stored.
  auto stored = client().Post("/v1/scenes", scene.dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string id = json::parse(stored->body)["id"];
  const std::string ref = chair["piece"]["parts"][0]["ref"];
  EXPECT_EQ(client().Delete(("/v1/meshes/" + ref).c_str())->status, 403);  // read-only, not "placed by"
  auto by_id = client().Post(("/v1/scenes/" + id + "/render").c_str(), view().dump(), "application/json");
  ASSERT_TRUE(by_id);
  EXPECT_EQ(by_id->body, rendered->body);
  EXPECT_EQ(client().Delete(("/v1/scenes/" + id).c_str())->status, 204);
}

// A data directory keeps a scene placing catalogue meshes across a restart (it reads before any
// stored mesh could be missing), and a second server makes the same ids from the same files.
TEST(CatalogueRestart, AStoredSceneWithCataloguePiecesLoadsAgain) {
  const std::filesystem::path dir = fresh_output_dir();
  auto config = test_server_config();
  config.data_dir = dir;
  json scene, answer;
  std::string id, png;
  {
    TestServer server(config);
    answer = json::parse(server.client().Get("/v1/catalogue")->body);
    json piece = answer["items"][0]["piece"];
    piece["center"] = {0, 0};
    scene = {{"solids", {piece}}};
    auto stored = server.client().Post("/v1/scenes", scene.dump(), "application/json");
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->status, 201) << stored->body;
    id = json::parse(stored->body)["id"];
    png = server.client().Post(("/v1/scenes/" + id + "/render").c_str(), "{}", "application/json")->body;
  }
  TestServer again(config);
  EXPECT_EQ(json::parse(again.client().Get("/v1/catalogue")->body), answer) << "the same entries and mesh ids";
  auto rendered = again.client().Post(("/v1/scenes/" + id + "/render").c_str(), "{}", "application/json");
  ASSERT_TRUE(rendered);
  EXPECT_EQ(rendered->status, 200) << rendered->body;
  EXPECT_EQ(rendered->body, png);
  // No file of a catalogue mesh was written: they are not the store's.
  EXPECT_FALSE(std::filesystem::exists(dir / "meshes") && !std::filesystem::is_empty(dir / "meshes"));
}

TEST(CatalogueRestart, AServerWithoutACatalogueOffersAnEmptyOne) {
  auto config = test_server_config();
  config.catalogue_dir = fresh_output_dir();
  TestServer server(config);
  const json answer = json::parse(server.client().Get("/v1/catalogue")->body);
  EXPECT_EQ(answer["items"], json::array());
}

}  // namespace

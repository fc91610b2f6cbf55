// Stored scenes over real HTTP: content-addressed ids (POST names, PUT must match), canonical GET
// with conditional 304, DELETE, renders of a stored scene equal to the inline render byte for byte
// (POST with {camera, options} and GET render.png with query parameters), query parameter errors
// naming the parameter, whole render requests stored by their scene, the size bound, and persistence
// across a restart with a data directory (including the crash leftovers start-up must cope with).
// A full store (507) and retention: test_store_full.cpp.
#include "server_fixture.hpp"

#include <filesystem>
#include <fstream>

namespace {

using nlohmann::json;
using namespace rr::testing;
namespace fs = std::filesystem;

json small_scene() { return json::parse(small_request)["scene"]; }

// Stores `scene`; returns the answer's body (id, location, ...).
json store(const TestServer& server, const json& scene, int expected_status = 201) {
  auto res = server.client().Post("/v1/scenes", scene.dump(), "application/json");
  EXPECT_TRUE(res);
  if (!res) return json();
  EXPECT_EQ(res->status, expected_status) << res->body;
  json body = json::parse(res->body, nullptr, false);
  if (body.is_object() && body.contains("location")) {
    EXPECT_EQ(res->get_header_value("Location"), body["location"]);
  }
  return body;
}

class StoreTest : public SharedServerTest<StoreTest> {};

TEST_F(StoreTest, PostNamesTheSceneByItsContent) {
  json created = store(*server_, scene_with_box_at(0.1));
  std::string id = created["id"];
  EXPECT_EQ(id.size(), 16u);
  EXPECT_EQ(created["location"], "/v1/scenes/" + id);
  EXPECT_EQ(created["created"], true);
  // Same content, other formatting: the same id, and nothing new is stored.
  auto again = client().Post("/v1/scenes", scene_with_box_at(0.1).dump(4), "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
  EXPECT_EQ(json::parse(again->body)["id"], id);
  EXPECT_NE(store(*server_, scene_with_box_at(0.2))["id"], id);
}

TEST_F(StoreTest, PutMustUseTheContentHash) {
  json scene = scene_with_box_at(0.3);
  auto wrong = client().Put("/v1/scenes/0123456789abcdef", scene.dump(), "application/json");
  json problem = expect_problem(wrong, 422);
  std::string detail = problem.value("detail", "");
  std::string id = detail.substr(detail.find("id is ") + 6, 16);
  auto right = client().Put(("/v1/scenes/" + id).c_str(), scene.dump(), "application/json");
  ASSERT_TRUE(right);
  EXPECT_EQ(right->status, 201) << right->body;
  auto idempotent = client().Put(("/v1/scenes/" + id).c_str(), scene.dump(), "application/json");
  ASSERT_TRUE(idempotent);
  EXPECT_EQ(idempotent->status, 200);
  expect_problem(client().Put("/v1/scenes/not-an-id", scene.dump(), "application/json"), 404);
}

TEST_F(StoreTest, GetReturnsCanonicalJsonAndHonoursIfNoneMatch) {
  json scene = scene_with_box_at(0.4);
  std::string id = store(*server_, scene)["id"];
  auto res = client().Get(("/v1/scenes/" + id).c_str());
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(json::parse(res->body), scene);
  EXPECT_EQ(res->body, scene.dump()) << "canonical: sorted keys, no whitespace";
  EXPECT_EQ(res->get_header_value("ETag"), "\"" + id + "\"");
  EXPECT_EQ(res->get_header_value("Cache-Control"), "public, max-age=31536000, immutable");
  auto conditional = client().Get(("/v1/scenes/" + id).c_str(), {{"If-None-Match", "\"" + id + "\""}});
  ASSERT_TRUE(conditional);
  EXPECT_EQ(conditional->status, 304);
  EXPECT_TRUE(conditional->body.empty());
}

TEST_F(StoreTest, DeleteRemovesTheScene) {
  std::string id = store(*server_, scene_with_box_at(0.5))["id"];
  auto deleted = client().Delete(("/v1/scenes/" + id).c_str());
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 204);
  expect_problem(client().Get(("/v1/scenes/" + id).c_str()), 404);
  expect_problem(client().Delete(("/v1/scenes/" + id).c_str()), 404);
  expect_problem(client().Post(("/v1/scenes/" + id + "/render").c_str(), "{}", "application/json"), 404);
}

// What examples/ holds (a whole render request) stores its scene; errors point into the request.
TEST_F(StoreTest, PostTakesAWholeRequestAndStoresItsScene) {
  json request = json::parse(read_file(source_dir() / "examples" / "studio.json"));
  json created = store(*server_, request);
  ASSERT_TRUE(created.contains("id")) << created;
  auto got = client().Get(("/v1/scenes/" + created["id"].get<std::string>()).c_str());
  ASSERT_TRUE(got);
  EXPECT_EQ(json::parse(got->body), request["scene"]);
  EXPECT_EQ(store(*server_, request["scene"], 200)["id"], created["id"]) << "the bare scene is the same scene";
  auto put =
      client().Put(("/v1/scenes/" + created["id"].get<std::string>()).c_str(), request.dump(), "application/json");
  ASSERT_TRUE(put);
  EXPECT_EQ(put->status, 200) << put->body;
  ASSERT_FALSE(created["warnings"].empty()) << "studio's lamp touches its pole";
  for (const json& w : created["warnings"]) EXPECT_TRUE(w["pointer"].get<std::string>().starts_with("/scene/")) << w;

  json bad = json::parse(small_request);
  bad["scene"]["solids"][0]["size"] = {1, -1, 1};
  json problem = expect_problem(client().Post("/v1/scenes", bad.dump(), "application/json"), 422);
  EXPECT_EQ(problem["errors"][0]["pointer"], "/scene/solids/0/size/1") << problem;
  json not_object = expect_problem(client().Post("/v1/scenes", R"({"scene": [1]})", "application/json"), 422);
  EXPECT_EQ(not_object["errors"][0]["pointer"], "/scene") << not_object;
}

TEST_F(StoreTest, InvalidSceneErrorsPointIntoTheDocument) {
  json scene = small_scene();
  scene["solids"][0]["size"] = {1, -1, 1};
  json problem = expect_problem(client().Post("/v1/scenes", scene.dump(), "application/json"), 422);
  EXPECT_EQ(problem["errors"][0]["pointer"], "/solids/0/size/1") << problem;
  json not_object = expect_problem(client().Post("/v1/scenes", "[1, 2]", "application/json"), 422);
  EXPECT_EQ(not_object["errors"][0]["pointer"], "") << not_object;
  expect_problem(client().Post("/v1/scenes", "{\"walls\": [", "application/json"), 400);
}

// The acceptance check: a stored scene rendered by POST and by GET render.png gives exactly the
// bytes of the same scene sent inline, and the three share one ETag.
TEST_F(StoreTest, StoredRendersEqualTheInlineRenderByteForByte) {
  json request = json::parse(small_request);
  request["camera"] = {{"position", {2.5, 1.5, 3.5}}, {"target", {0, 0.4, 0}}, {"fov_y", 50}};
  request["options"] = {{"width", 80}, {"height", 60}, {"shading", "flat"}};
  auto inline_res = client().Post("/v1/render", request.dump(), "application/json");
  ASSERT_TRUE(inline_res);
  ASSERT_EQ(inline_res->status, 200);

  std::string id = store(*server_, request["scene"])["id"];
  json view = {{"camera", request["camera"]}, {"options", request["options"]}};
  auto posted = client().Post(("/v1/scenes/" + id + "/render").c_str(), view.dump(), "application/json");
  ASSERT_TRUE(posted);
  ASSERT_EQ(posted->status, 200) << posted->body;
  EXPECT_EQ(posted->body, inline_res->body);
  EXPECT_EQ(posted->get_header_value("X-Scene-Id"), inline_res->get_header_value("X-Scene-Id"));

  std::string query = "/v1/scenes/" + id +
                      "/render.png?position=2.5,1.5,3.5&target=0,0.4,0&fov_y=50"
                      "&width=80&height=60&shading=flat";
  auto got = client().Get(query.c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200) << got->body;
  EXPECT_EQ(got->body, inline_res->body);
  EXPECT_EQ(got->get_header_value("Cache-Control"), "public, max-age=31536000, immutable");
  EXPECT_EQ(got->get_header_value("ETag"), posted->get_header_value("ETag"));
  EXPECT_EQ(posted->get_header_value("ETag"), inline_res->get_header_value("ETag"))
      << "same scene, camera and options as sent: same tag";

  auto conditional = client().Get(query.c_str(), {{"If-None-Match", got->get_header_value("ETag")}});
  ASSERT_TRUE(conditional);
  EXPECT_EQ(conditional->status, 304);
  EXPECT_TRUE(conditional->body.empty());
}

TEST_F(StoreTest, StoredRenderTakesOnlyCameraAndOptions) {
  std::string id = store(*server_, scene_with_box_at(0.6))["id"];
  json problem = expect_problem(client().Post(("/v1/scenes/" + id + "/render").c_str(),
                                              json({{"scene", small_scene()}}).dump(), "application/json"),
                                422);
  EXPECT_EQ(problem["errors"][0]["pointer"], "/scene");
  json bad_view = expect_problem(
      client().Post(("/v1/scenes/" + id + "/render").c_str(), R"({"camera": {"near": 0}})", "application/json"), 422);
  EXPECT_EQ(bad_view["errors"][0]["pointer"], "/camera/near");
  auto json_answer = client().Post(("/v1/scenes/" + id + "/render").c_str(), {{"Accept", "application/json"}},
                                   R"({"options": {"width": 16, "height": 16}})", "application/json");
  ASSERT_TRUE(json_answer);
  EXPECT_EQ(json::parse(json_answer->body)["width"], 16);
}

TEST_F(StoreTest, QueryParameterErrorsNameTheParameter) {
  std::string id = store(*server_, scene_with_box_at(0.7))["id"];
  std::string base = "/v1/scenes/" + id + "/render.png?";
  auto check = [&](const std::string& query, int status, const std::string& parameter, const std::string& pointer) {
    auto res = client().Get((base + query).c_str());
    json problem = expect_problem(res, status);
    ASSERT_TRUE(problem.contains("errors")) << query << ": " << problem;
    EXPECT_EQ(problem["errors"][0]["parameter"], parameter) << query;
    EXPECT_EQ(problem["errors"][0]["pointer"], pointer) << query;
    ASSERT_TRUE(res);
    EXPECT_EQ(res->get_header_value("Cache-Control"), "no-store") << "errors must not be cached for a year";
    EXPECT_FALSE(res->has_header("ETag"));
  };
  check("zoom=2", 400, "zoom", "");
  check("fov_y=nan", 400, "fov_y", "/camera/fov_y");
  check("fov_y=1e999", 400, "fov_y", "/camera/fov_y");
  check("position=1,2", 400, "position", "/camera/position");
  check("position=1,2,3,4", 400, "position", "/camera/position");
  check("shadows=yes", 400, "shadows", "/options/shadows");
  check("width=1&width=2", 400, "width", "/options/width");
  check("width=100000&height=100000", 413, "width", "/options/width");
  check("width=16.5", 422, "width", "/options/width");
  check("fov_y=170", 422, "fov_y", "/camera/fov_y");
  check("pipeline=raytrace", 422, "pipeline", "/options/pipeline");
  check("up=0,0,0", 422, "up", "/camera/up");
  check("shadow_size=1000000000", 413, "shadow_size", "/options/shadow/size");
}

TEST(StoreBounds, SceneLargerThanTheWholeBudgetIs413) {
  rr::server::ServerConfig config = test_server_config();
  config.scene_store_bytes = small_scene().dump().size() - 1;  // the document's bytes, nothing prepared
  TestServer server(config);
  json problem = expect_problem(server.client().Post("/v1/scenes", small_scene().dump(), "application/json"), 413);
  EXPECT_EQ(problem["errors"][0]["pointer"], "");
}

TEST(StorePersistence, StoredScenesSurviveARestart) {
  fs::path dir = fresh_output_dir();
  rr::server::ServerConfig config = test_server_config();
  config.data_dir = dir;
  json scene = scene_with_box_at(2.0);
  std::string id, before;
  {
    TestServer server(config);
    id = store(server, scene)["id"];
    before = server.client().Get(("/v1/scenes/" + id + "/render.png?width=40&height=30").c_str())->body;
  }
  ASSERT_TRUE(fs::exists(dir / "scenes" / (id + ".json")));
  EXPECT_EQ(read_file(dir / "scenes" / (id + ".json")), scene.dump());
  TestServer restarted(config);
  auto res = restarted.client().Get(("/v1/scenes/" + id).c_str());
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(json::parse(res->body), scene);
  EXPECT_EQ(restarted.client().Get(("/v1/scenes/" + id + "/render.png?width=40&height=30").c_str())->body, before);
  auto deleted = restarted.client().Delete(("/v1/scenes/" + id).c_str());
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 204);
  EXPECT_FALSE(fs::exists(dir / "scenes" / (id + ".json")));
}

// A server whose stored scenes will not outlive it says so once at start; one with a data directory
// does not.
TEST(StorePersistence, AServerWithoutADataDirSaysItsScenesLiveOnlyAsLongAsTheProcess) {
  for (const bool with_dir : {false, true}) {
    rr::server::ServerConfig config = test_server_config();
    if (with_dir) config.data_dir = fresh_output_dir();
    LogCapture log;
    config.log_level = "warn";
    config.log_sink = log.sink();
    { TestServer server(config); }
    size_t said = 0;
    for (const json& line : log.lines()) {
      if (line.value("event", "") != "store_in_memory") continue;
      ++said;
      EXPECT_EQ(line["level"], "warn");
      EXPECT_NE(line.value("reason", "").find("only as long as this process"), std::string::npos) << line;
      EXPECT_NE(line.value("reason", "").find("--data-dir"), std::string::npos) << line;
    }
    EXPECT_EQ(said, with_dir ? 0u : 1u) << (with_dir ? "with" : "without") << " a data directory";
  }
}

// What a crash can leave: a temporary file from a write that never reached its rename (removed at
// start), and a file whose content no longer hashes to its name (kept for a person, not served).
TEST(StorePersistence, StartUpRemovesTornWritesAndSkipsMismatchedFiles) {
  fs::path dir = fresh_output_dir();
  fs::create_directories(dir / "scenes");
  write_file(dir / "scenes" / ".tmp-0123456789abcdef", "{\"walls\": [");
  write_file(dir / "scenes" / "fedcba9876543210.json", small_scene().dump());
  rr::server::ServerConfig config = test_server_config();
  config.data_dir = dir;
  LogCapture log;
  config.log_level = "warn";
  config.log_sink = log.sink();
  TestServer server(config);
  EXPECT_FALSE(fs::exists(dir / "scenes" / ".tmp-0123456789abcdef"));
  EXPECT_TRUE(fs::exists(dir / "scenes" / "fedcba9876543210.json"));
  expect_problem(server.client().Get("/v1/scenes/fedcba9876543210"), 404);
  size_t skipped = 0;
  for (const json& line : log.lines()) skipped += line.value("event", "") == "scene_file_skipped";
  EXPECT_EQ(skipped, 1u);
}

}  // namespace

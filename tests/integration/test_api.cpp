// The /v1 API over real HTTP on a loopback port: content negotiation (PNG or JSON), the render
// headers (Server-Timing, X-Scene-Id, X-Cache, ETag, X-Warning-Count) and conditional requests,
// placement warnings, the metadata endpoints (pipelines, OpenAPI, schemas, health, metrics), the
// request log line, and the hardening that lives in screening (Range ignored, REMOTE_ADDR not
// trusted, 405/406).
#include "server_fixture.hpp"

#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/http_server.hpp"
#include "support/api_routes.hpp"

#include <algorithm>
#include <chrono>
#include <set>
#include <thread>

namespace {

using nlohmann::json;
using namespace rr::testing;

class ApiTest : public SharedServerTest<ApiTest> {
 public:
  static rr::server::ServerConfig config() {
    rr::server::ServerConfig config = test_server_config();
    config.log_requests = true;
    config.log_level = "info";
    config.log_sink = log_.sink();
    return config;
  }

 protected:
  static httplib::Result post_json(const std::string& path, const std::string& body, const std::string& accept = "") {
    httplib::Headers headers;
    if (!accept.empty()) headers.emplace("Accept", accept);
    return client().Post(path.c_str(), headers, body, "application/json");
  }

  // The log line is written after the response, so a client can read the answer first: wait for it.
  static json wait_for_log_line(const std::function<bool(const json&)>& wanted) {
    for (int attempt = 0; attempt < 400; ++attempt) {
      auto lines = log_.lines();
      auto it = std::find_if(lines.rbegin(), lines.rend(), wanted);
      if (it != lines.rend()) return *it;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return json();
  }

  static inline LogCapture log_;
};

// Two boxes overlapping by 0.5 m, one box flush against the other (touching, no warning), and a
// window 2 cm from its wall's end: three kinds of placement checks in one scene.
const char* const warning_request = R"({
  "scene": {
    "floor": {"cells": [4, 4], "origin": [-2, -2]},
    "walls": [{"start": [-2, -2], "end": [2, -2], "openings": [{"type": "window", "offset": 2.68, "width": 1.3}]}],
    "solids": [{"type": "box", "center": [0, 0], "size": [1, 1, 1]},
               {"type": "box", "center": [0.5, 0], "size": [1, 1, 1], "id": "overlapping"},
               {"type": "box", "center": [-1, 0], "size": [1, 1, 1], "id": "touching"}]},
  "camera": {"position": [3, 2.5, 4], "target": [0, 0.5, 0]},
  "options": {"width": 32, "height": 24}
})";

TEST_F(ApiTest, PngByDefaultWithEveryRenderHeader) {
  auto res = post_json("/v1/render", small_request);
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(png_size(res->body).width, 64u);
  std::string timing = res->get_header_value("Server-Timing");
  for (const char* stage :
       {"parse", "tessellate", "build", "cull", "sort", "traverse", "shadow", "raster", "shade", "encode", "total"}) {
    EXPECT_NE(timing.find(std::string(stage) + ";dur="), std::string::npos) << stage << " in " << timing;
  }
  EXPECT_EQ(res->get_header_value("X-Scene-Id").size(), 16u);
  EXPECT_EQ(res->get_header_value("X-Warning-Count"), "1") << "the box at (0, 0) reaches beyond the floor";
  EXPECT_FALSE(res->has_header("X-Cache")) << "the zbuffer pipeline builds no tree";
  std::string etag = res->get_header_value("ETag");
  EXPECT_EQ(etag.size(), 18u) << etag;
  EXPECT_EQ(etag.front(), '"');
  EXPECT_EQ(res->get_header_value("Vary"), "Accept");
}

TEST_F(ApiTest, JsonAnswerCarriesTheSamePngTimingsAndStatistics) {
  auto png = post_json("/v1/render", small_request, "image/png");
  auto res = post_json("/v1/render", small_request, "application/json");
  ASSERT_TRUE(res && png);
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  json body = json::parse(res->body);
  EXPECT_EQ(base64_decode(body["png_base64"]), png->body) << "the JSON answer holds the same image";
  EXPECT_EQ(body["scene_id"], png->get_header_value("X-Scene-Id"));
  EXPECT_EQ(body["pipeline"], "zbuffer");
  EXPECT_EQ(body["cache"], "none");
  EXPECT_EQ(body["width"], 64);
  EXPECT_EQ(body["etag"], res->get_header_value("ETag"));
  EXPECT_NE(body["etag"], png->get_header_value("ETag")) << "two representations, two tags";
  EXPECT_GT(body["counts"]["polygons"].get<int>(), 0);
  EXPECT_GT(body["timings_ms"]["total"].get<double>(), 0.0);
  EXPECT_TRUE(body["warnings"].is_array());
}

TEST_F(ApiTest, AcceptIsNegotiatedWithQValues) {
  auto json_preferred = post_json("/v1/render", small_request, "image/png;q=0.5, application/json");
  ASSERT_TRUE(json_preferred);
  EXPECT_EQ(json_preferred->get_header_value("Content-Type"), "application/json");
  auto any_image = post_json("/v1/render", small_request, "image/*");
  ASSERT_TRUE(any_image);
  EXPECT_EQ(any_image->get_header_value("Content-Type"), "image/png");
  expect_problem(post_json("/v1/render", small_request, "text/html"), 406);
  expect_problem(post_json("/v1/render", small_request, "image/png;q=0, application/json;q=0"), 406);
  expect_problem(client().Get("/v1/pipelines", {{"Accept", "image/png"}}), 406);
}

TEST_F(ApiTest, ConditionalPostRenderIs304WithoutABody) {
  auto first = post_json("/v1/render", small_request);
  ASSERT_TRUE(first);
  std::string etag = first->get_header_value("ETag");
  httplib::Headers headers = {{"If-None-Match", "\"0000000000000000\", " + etag}};
  auto again = client().Post("/v1/render", headers, small_request, "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
  EXPECT_TRUE(again->body.empty());
  EXPECT_EQ(again->get_header_value("ETag"), etag);
  // The same scene with another camera is another image: a full answer.
  json moved = json::parse(small_request);
  moved["camera"]["position"] = {3, 2.6, 4};
  auto other = client().Post("/v1/render", headers, moved.dump(), "application/json");
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 200);
  EXPECT_NE(other->get_header_value("ETag"), etag);
  // Whitespace and key order do not change what is drawn, nor the tag.
  auto reformatted = client().Post("/v1/render", headers, json::parse(small_request).dump(2), "application/json");
  ASSERT_TRUE(reformatted);
  EXPECT_EQ(reformatted->status, 304);
}

TEST_F(ApiTest, PlacementProblemsAreWarningsWithPointers) {
  auto png = post_json("/v1/render", warning_request);
  ASSERT_TRUE(png);
  ASSERT_EQ(png->status, 200) << png->body;
  auto res = post_json("/v1/render", warning_request, "application/json");
  ASSERT_TRUE(res);
  json warnings = json::parse(res->body)["warnings"];
  std::set<std::string> pointers;
  for (const json& w : warnings) pointers.insert(w["pointer"].get<std::string>());
  EXPECT_EQ(pointers, (std::set<std::string>{"/scene/solids/1", "/scene/walls/0/openings/0"})) << warnings;
  EXPECT_EQ(png->get_header_value("X-Warning-Count"), std::to_string(warnings.size()));
}

// The BSP pipeline lives on another branch; once it is in the table, its tree must be built on the
// first request for a scene and reused by the next (another camera, same static geometry).
TEST_F(ApiTest, XCacheMissThenHitForTheBspPipeline) {
  if (!rr::find_pipeline("bsp")) GTEST_SKIP() << "bsp pipeline not built yet";
  json request = json::parse(small_request);
  request["options"]["pipeline"] = "bsp";
  request["scene"]["solids"][0]["center"] = {0.25, 0.5};  // a scene no other test has cached
  auto first = post_json("/v1/render", request.dump());
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  EXPECT_EQ(first->get_header_value("X-Cache"), "miss");
  request["camera"]["position"] = {-3, 2, 4};
  auto second = post_json("/v1/render", request.dump());
  ASSERT_TRUE(second);
  EXPECT_EQ(second->get_header_value("X-Cache"), "hit");
  EXPECT_EQ(first->get_header_value("X-Scene-Id"), second->get_header_value("X-Scene-Id"));
  EXPECT_GE(server_->metric("roomrender_cache_hits_total", {"cache=\"bsp\""}), 1.0);
}

// A view that leaves a level out is made once: the second render of it, from another camera, takes
// its polygons and shadow-ray tree from the views' part of the prepared cache, and draws what a
// server that never saw the first would.
TEST_F(ApiTest, AViewLeavingALevelOutIsMadeOnceForEveryCamera) {
  json request = json::parse(small_request);
  request["scene"]["levels"] = json::parse(R"([{"id": "low"}, {"id": "high", "elevation": 1.5}])");
  request["scene"]["solids"][0]["center"] = {0.3, 0.6};  // a scene no other test has drawn
  request["scene"]["solids"].push_back(
      {{"type", "box"}, {"center", {0, 0}}, {"base", 1.5}, {"size", {1, 0.2, 1}}, {"level", "high"}});
  request["options"]["levels"] = {"low"};
  request["options"]["shadows"] = true;
  request["options"]["shadow"] = {{"method", "rays"}};
  const double builds = server_->metric("roomrender_cache_builds_total", {"cache=\"views\""});
  const double hits = server_->metric("roomrender_cache_hits_total", {"cache=\"views\""});
  auto first = post_json("/v1/render", request.dump(), "image/png");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  EXPECT_EQ(server_->metric("roomrender_cache_builds_total", {"cache=\"views\""}), builds + 2.0)
      << "the selection and its tree";
  request["camera"]["position"] = {-3, 2, 4};
  auto second = post_json("/v1/render", request.dump(), "image/png");
  ASSERT_TRUE(second);
  ASSERT_EQ(second->status, 200) << second->body;
  EXPECT_EQ(server_->metric("roomrender_cache_builds_total", {"cache=\"views\""}), builds + 2.0);
  EXPECT_EQ(server_->metric("roomrender_cache_hits_total", {"cache=\"views\""}), hits + 2.0);
  EXPECT_GT(server_->metric("roomrender_cache_bytes", {"cache=\"views\""}), 0.0);
  // The same bytes as a render that makes the view for itself.
  rr::RenderRequest parsed = rr::request_from_json(request);
  const rr::PreparedScene scene = rr::prepare_scene(parsed.scene);
  rr::RenderContext alone;
  EXPECT_TRUE(second->body == rr::render(parsed, scene, alone).png) << "a cached view draws other bytes";
}

// Shadow maps fitted to the whole scene serve every camera: the second view reuses the first's maps
// (no shadow pass), and the outcome is a header, a JSON member and a /metrics series like the BSP's.
TEST_F(ApiTest, XShadowCacheMissThenHitForASceneFittedMap) {
  json request = json::parse(small_request);
  request["options"]["shadows"] = true;
  request["options"]["shadow"] = {{"fit", "scene"}, {"size", 256}};
  request["scene"]["solids"][0]["center"] = {1.5, 1.5};  // on the floor, casting onto it; no other test uses it
  auto first = post_json("/v1/render", request.dump());
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 200) << first->body;
  EXPECT_EQ(first->get_header_value("X-Shadow-Cache"), "miss");
  request["camera"]["position"] = {-3, 2, 4};
  auto second = post_json("/v1/render", request.dump(), "application/json");
  ASSERT_TRUE(second);
  ASSERT_EQ(second->status, 200) << second->body;
  EXPECT_EQ(second->get_header_value("X-Shadow-Cache"), "hit");
  json body = json::parse(second->body);
  EXPECT_EQ(body["shadow_cache"], "hit");
  EXPECT_EQ(body["counts"]["shadow_passes"], 0);
  EXPECT_EQ(body["shadow"], "rendered") << "the reused maps are looked up";
  EXPECT_GE(server_->metric("roomrender_cache_hits_total", {"cache=\"shadow\""}), 1.0);
  request["options"]["shadows"] = false;
  auto none = post_json("/v1/render", request.dump());
  ASSERT_TRUE(none);
  EXPECT_EQ(none->get_header_value("X-Shadow-Cache"), "none");
}

// One cache, one budget: each part's budget is the whole cache's, but shadow maps' (their own cap);
// the document stores' budgets are their own.
TEST_F(ApiTest, CachesAndStoresAreExportedWithTheirBudgets) {
  rr::server::ServerConfig config = server_->service().config();
  for (const char* part : {"bsp", "views", "scenes", "meshes", "textures", "all"}) {
    EXPECT_EQ(server_->metric("roomrender_cache_budget_bytes", {"cache=\"" + std::string(part) + "\""}),
              double(config.cache_bytes))
        << part;
  }
  EXPECT_EQ(server_->metric("roomrender_cache_budget_bytes", {"cache=\"shadow\""}), double(config.shadow_cache_bytes));
  EXPECT_GE(server_->metric("roomrender_cache_bytes", {"cache=\"bsp\""}), 0.0);
  EXPECT_EQ(server_->metric("roomrender_store_budget_bytes", {"store=\"scenes\""}), double(config.scene_store_bytes));
  EXPECT_EQ(server_->metric("roomrender_store_budget_bytes", {"store=\"meshes\""}), double(config.mesh_store_bytes));
  EXPECT_EQ(server_->metric("roomrender_store_max_entries", {"store=\"scenes\""}), double(config.scene_store_entries));
}

TEST_F(ApiTest, MetricsCountRequestsByRouteTemplateAndStatus) {
  // A request is counted after its answer is written (httplib's logger hook), so a client asking
  // /metrics on another connection may come first: wait (up to 1 s) for a count to reach `want`.
  auto eventually = [&](const std::string& name, const std::vector<std::string>& labels, double want) {
    double value = server_->metric(name, labels);
    for (int attempt = 0; attempt < 100 && value < want; ++attempt) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      value = server_->metric(name, labels);
    }
    return value;
  };
  double before =
      server_->metric("roomrender_http_requests_total", {"route=\"/v1/render\"", "method=\"POST\"", "status=\"422\""});
  auto bad = post_json("/v1/render", R"({"camera": {"fov_y": 500}})");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 422);
  ASSERT_TRUE(post_json("/v1/render", small_request));
  EXPECT_EQ(eventually("roomrender_http_requests_total", {"route=\"/v1/render\"", "method=\"POST\"", "status=\"422\""},
                       before + 1.0),
            before + 1.0);
  client().Get("/no/such/page");
  EXPECT_GE(eventually("roomrender_http_requests_total", {"route=\"unmatched\"", "status=\"404\""}, 1.0), 1.0);
  EXPECT_GE(eventually("roomrender_http_request_duration_seconds_count", {"route=\"/v1/render\""}, 2.0), 2.0);
  EXPECT_GE(
      server_->metric("roomrender_render_stage_duration_seconds_count", {"pipeline=\"zbuffer\"", "stage=\"raster\""}),
      1.0);
  EXPECT_GE(
      server_->metric("roomrender_render_culling_total", {"pipeline=\"zbuffer\"", "count=\"polygons_projected\""}),
      1.0);
  EXPECT_EQ(server_->metric("roomrender_renders_in_flight"), 0.0);
  EXPECT_EQ(server_->metric("roomrender_renders_queued"), 0.0);
  EXPECT_EQ(server_->metric("roomrender_build_info"), 1.0);
  EXPECT_GT(server_->metric("process_resident_memory_bytes"), 0.0);
  auto text = client().Get("/metrics");
  ASSERT_TRUE(text);
  EXPECT_EQ(text->get_header_value("Content-Type").rfind("text/plain; version=0.0.4", 0), 0u);
  EXPECT_NE(text->body.find("# TYPE roomrender_http_request_duration_seconds histogram"), std::string::npos);
  EXPECT_NE(text->body.find("le=\"+Inf\""), std::string::npos);
}

TEST_F(ApiTest, OneLogLinePerRequestWithRouteSceneAndPipeline) {
  auto res = post_json("/v1/render", small_request);
  ASSERT_TRUE(res);
  std::string scene = res->get_header_value("X-Scene-Id");
  json line = wait_for_log_line(
      [&](const json& l) { return l.value("event", "") == "request" && l.value("scene_id", "") == scene; });
  ASSERT_TRUE(line.is_object());
  EXPECT_EQ(line["method"], "POST");
  EXPECT_EQ(line["route"], "/v1/render");
  EXPECT_EQ(line["status"], 200);
  EXPECT_EQ(line["pipeline"], "zbuffer");
  EXPECT_EQ(line["bytes"].get<size_t>(), res->body.size());
  EXPECT_GT(line["duration_ms"].get<double>(), 0.0);
  EXPECT_EQ(line["level"], "info");
}

// httplib adds the peer's address as a REMOTE_ADDR header after the client's own headers; the log
// must report the socket's peer, whatever the client claims.
TEST_F(ApiTest, ClientSuppliedRemoteAddrIsNotTrusted) {
  auto res = client().Get("/examples/", {{"REMOTE_ADDR", "203.0.113.9"}});
  ASSERT_TRUE(res);
  json line = wait_for_log_line([](const json& l) { return l.value("route", "") == "/examples/"; });
  ASSERT_TRUE(line.is_object());
  EXPECT_EQ(line["remote"], "127.0.0.1");
}

TEST_F(ApiTest, RangeIsIgnoredOnRenders) {
  auto full = post_json("/v1/render", small_request);
  auto ranged = client().Post("/v1/render", {{"Range", "bytes=0-9"}}, small_request, "application/json");
  ASSERT_TRUE(full && ranged);
  EXPECT_EQ(ranged->status, 200);
  EXPECT_EQ(ranged->body, full->body);
  EXPECT_FALSE(ranged->has_header("Content-Range"));
}

TEST_F(ApiTest, PipelinesComeFromTheTable) {
  auto res = client().Get("/v1/pipelines");
  ASSERT_TRUE(res);
  json body = json::parse(res->body);
  json names = json::array();
  for (const json& p : body["pipelines"]) names.push_back(p["name"]);
  json expected = json::array();
  for (const rr::PipelineInfo& p : rr::pipeline_table()) expected.push_back(p.name);
  EXPECT_EQ(names, expected);
}

TEST_F(ApiTest, OpenApiDocumentDescribesEveryRoute) {
  auto res = client().Get("/openapi.json");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  json doc = json::parse(res->body);
  EXPECT_EQ(doc["openapi"].get<std::string>().rfind("3.1", 0), 0u);
  EXPECT_EQ(doc["jsonSchemaDialect"], "https://json-schema.org/draft/2020-12/schema");
  const std::set<std::string> described = openapi_operations(doc);
  for (const std::string& operation : api_operations(test_server_config())) {
    EXPECT_TRUE(described.contains(operation)) << operation;
  }
}

TEST_F(ApiTest, SchemasAreServedByName) {
  auto list = client().Get("/v1/schemas");
  ASSERT_TRUE(list);
  json names = json::parse(list->body)["schemas"];
  EXPECT_NE(std::find(names.begin(), names.end(), "request.schema"), names.end()) << names;
  for (const json& name : names) {
    auto res = client().Get(("/v1/schemas/" + name.get<std::string>() + ".json").c_str());
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200) << name;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/schema+json");
    json schema = json::parse(res->body);
    EXPECT_EQ(schema["$schema"], "https://json-schema.org/draft/2020-12/schema") << name;
  }
  expect_problem(client().Get("/v1/schemas/nothing.schema.json"), 404);
  expect_problem(client().Get("/v1/schemas/..%2Fopenapi.schema.json"), 404);
}

TEST_F(ApiTest, LivenessReadinessAndHealth) {
  for (const char* path : {"/livez", "/readyz", "/healthz"}) {
    auto res = client().Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_EQ(json::parse(res->body)["status"], "ok") << path;
    EXPECT_EQ(res->get_header_value("Cache-Control"), "no-store");
  }
  auto head = client().Head("/livez");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_TRUE(head->body.empty());
}

TEST_F(ApiTest, EveryMethodOutsideTheTableIs405WithAllow) {
  expect_problem_with(client().Put("/v1/render", small_request, "application/json"), 405, "Allow", "POST");
  expect_problem_with(client().Delete("/v1/scenes"), 405, "Allow", "POST, GET, HEAD");
  expect_problem_with(client().Post("/v1/scenes/0123456789abcdef", "{}", "application/json"), 405, "Allow",
                      "PUT, GET, HEAD, DELETE");
}

}  // namespace

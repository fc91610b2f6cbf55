// Write access with --api-token-file: every write (store, PUT, DELETE, import with store=1) needs
// "Authorization: Bearer <token>", else 401 with WWW-Authenticate and a problem body; reads stay
// open; tokens never reach the log. Scenes stored by two owners are referenced by each: a delete
// drops the caller's reference only (also across a restart with a data directory). GET /v1/scenes
// lists the caller's own scenes, newest first, a page at a time; on a server without tokens it is off
// unless --allow-listing.
#include "server_fixture.hpp"

#include <filesystem>
#include <set>

namespace {

using nlohmann::json;
using namespace rr::testing;
namespace fs = std::filesystem;

const std::string alice = "alice-0123456789abcdef";
const std::string bob = "bob-fedcba9876543210XYZ";
const std::string bare = "bare_token.0123456789+/==";

httplib::Headers bearer(const std::string& token) { return {{"Authorization", "Bearer " + token}}; }

fs::path token_file(const std::string& name) {
  fs::path file = output_dir("integration") / name;
  write_file(file, "# owners of this test server\nalice:" + alice + "\n\n  bob : " + bob + "  \n" + bare + "\n");
  return file;
}

rr::server::ServerConfig token_config(const std::string& name) {
  rr::server::ServerConfig config = test_server_config();
  config.api_token_file = token_file(name + ".tokens");
  return config;
}

std::string store_as(const TestServer& server, const std::string& token, const json& scene, int status = 201) {
  auto res = post_scene(server, scene, bearer(token));
  EXPECT_TRUE(res);
  if (!res) return "";
  EXPECT_EQ(res->status, status) << res->body;
  return json::parse(res->body).value("id", "");
}

void expect_unauthorized(const httplib::Result& res, bool token_sent) {
  json problem = expect_problem(res, 401);
  ASSERT_TRUE(res);
  std::string challenge = res->get_header_value("WWW-Authenticate");
  EXPECT_TRUE(challenge.starts_with("Bearer realm=")) << challenge;
  EXPECT_EQ(challenge.find("invalid_token") != std::string::npos, token_sent) << challenge;
  EXPECT_EQ(problem["title"], "Unauthorized");
}

std::vector<std::string> listed_ids(const httplib::Result& res) {
  std::vector<std::string> ids;
  EXPECT_TRUE(res);
  if (!res) return ids;
  EXPECT_EQ(res->status, 200) << res->body;
  const json body = json::parse(res->body);
  for (const json& s : body.at("scenes")) ids.push_back(s.at("id"));
  return ids;
}

TEST(Tokens, WritesNeedTheRightToken) {
  TestServer server(token_config("writes"));
  json scene = scene_with_box_at(1.0);
  expect_unauthorized(post_scene(server, scene), false);
  expect_unauthorized(post_scene(server, scene, bearer("not-a-token-of-this-server")), true);
  expect_unauthorized(post_scene(server, scene, bearer(alice + "x")), true);
  expect_unauthorized(post_scene(server, scene, {{"Authorization", "Basic " + alice}}), true);
  std::string id = store_as(server, alice, scene);
  ASSERT_EQ(id.size(), 16u);
  const std::string path = "/v1/scenes/" + id;
  expect_unauthorized(server.client().Put(path.c_str(), scene.dump(), "application/json"), false);
  expect_unauthorized(server.client().Delete(path.c_str()), false);
  expect_unauthorized(
      server.client().Post("/v1/import/obj?store=1", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "model/obj"), false);
  // A bearer token with the scheme in another case, and a bare token, both count.
  auto lower = post_scene(server, scene_with_box_at(1.1), {{"Authorization", "bearer " + bob}});
  ASSERT_TRUE(lower);
  EXPECT_EQ(lower->status, 201) << lower->body;
  store_as(server, bare, scene_with_box_at(1.2));
}

TEST(Tokens, ReadsNeedNoToken) {
  TestServer server(token_config("reads"));
  std::string id = store_as(server, alice, scene_with_box_at(2.0));
  EXPECT_EQ(server.client().Get(("/v1/scenes/" + id).c_str())->status, 200);
  EXPECT_EQ(server.client().Get(("/v1/scenes/" + id + "/render.png?width=32&height=24").c_str())->status, 200);
  EXPECT_EQ(server.client().Post(("/v1/scenes/" + id + "/render").c_str(), "{}", "application/json")->status, 200);
  EXPECT_EQ(server.client().Post("/v1/render", small_request, "application/json")->status, 200);
  auto imported = server.client().Post("/v1/import/obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "model/obj");
  ASSERT_TRUE(imported);
  EXPECT_EQ(imported->status, 200) << imported->body;
  EXPECT_EQ(server.client().Get("/healthz")->status, 200);
}

TEST(Tokens, ADeleteDropsOnlyTheCallersReference) {
  TestServer server(token_config("owners"));
  json scene = scene_with_box_at(3.0);
  std::string id = store_as(server, alice, scene);
  EXPECT_EQ(store_as(server, bob, scene, 200), id);
  const std::string path = "/v1/scenes/" + id;
  EXPECT_EQ(server.client().Delete(path.c_str(), bearer(alice))->status, 204);
  EXPECT_EQ(server.client().Get(path.c_str())->status, 200) << "bob still holds it";
  expect_problem(server.client().Delete(path.c_str(), bearer(alice)), 403);
  expect_problem(server.client().Delete(path.c_str(), bearer(bare)), 403);
  EXPECT_EQ(server.client().Delete(path.c_str(), bearer(bob))->status, 204);
  expect_problem(server.client().Get(path.c_str()), 404);
}

TEST(Tokens, OwnersSurviveARestart) {
  fs::path dir = output_dir("integration") / "tokens_restart";
  fs::remove_all(dir);
  rr::server::ServerConfig config = token_config("restart");
  config.data_dir = dir;
  json scene = scene_with_box_at(4.0);
  std::string id;
  {
    TestServer server(config);
    id = store_as(server, alice, scene);
    store_as(server, bob, scene, 200);
  }
  const std::string path = "/v1/scenes/" + id;
  {
    TestServer server(config);
    EXPECT_EQ(server.client().Delete(path.c_str(), bearer(alice))->status, 204);
    expect_problem(server.client().Delete(path.c_str(), bearer(bare)), 403);
  }
  TestServer server(config);
  EXPECT_EQ(server.client().Get(path.c_str())->status, 200);
  expect_problem(server.client().Delete(path.c_str(), bearer(alice)), 403);  // her reference stayed dropped
  EXPECT_EQ(server.client().Delete(path.c_str(), bearer(bob))->status, 204);
  EXPECT_FALSE(fs::exists(dir / "scenes" / (id + ".json")));
  EXPECT_FALSE(fs::exists(dir / "scene-meta" / (id + ".json")));
}

TEST(Tokens, TokensNeverReachTheLog) {
  rr::server::ServerConfig config = token_config("log");
  config.log_requests = true;
  config.log_level = "info";
  LogCapture log;
  config.log_sink = log.sink();
  {
    TestServer server(config);
    std::string id = store_as(server, alice, scene_with_box_at(5.0));
    post_scene(server, scene_with_box_at(5.1), bearer(bob + "-wrong"));
    server.client().Delete(("/v1/scenes/" + id).c_str(), bearer(bare));
  }
  bool said_token = false, named_alice = false;
  for (const json& line : log.lines()) {
    const std::string text = line.dump();
    for (const std::string& secret : {alice, bob, bare}) EXPECT_EQ(text.find(secret), std::string::npos) << text;
    said_token = said_token || (line.value("event", "") == "write_access" && line.value("writes", "") == "token");
    named_alice = named_alice || line.value("owner", "") == "alice";
  }
  EXPECT_TRUE(said_token) << "the start-up log says writes need a token";
  EXPECT_TRUE(named_alice) << "request lines name the owner";
}

TEST(Tokens, AnOpenServerSaysSoAtStart) {
  rr::server::ServerConfig config = test_server_config();
  config.log_level = "info";
  LogCapture log;
  config.log_sink = log.sink();
  { TestServer server(config); }
  size_t open = 0;
  for (const json& line : log.lines()) open += line.value("writes", "") == "open";
  EXPECT_EQ(open, 1u);
}

TEST(Tokens, ABadTokenFileStopsTheStartWithoutShowingTheToken) {
  rr::server::ServerConfig config = test_server_config();
  config.api_token_file = output_dir("integration") / "short.tokens";
  write_file(config.api_token_file, "carol:short-secret\n");
  rr::server::Service service(config);
  try {
    service.start();
    FAIL() << "a 12-character token was accepted";
  } catch (const std::runtime_error& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("short.tokens:1"), std::string::npos) << what;
    EXPECT_EQ(what.find("short-secret"), std::string::npos) << what;
  }
}

TEST(Listing, OwnScenesNewestFirstAPageAtATime) {
  TestServer server(token_config("listing"));
  std::vector<std::string> mine;
  for (double x : {6.0, 6.1, 6.2, 6.3, 6.4}) mine.push_back(store_as(server, alice, scene_with_box_at(x)));
  std::string bobs = store_as(server, bob, scene_with_box_at(6.5));
  store_as(server, bob, scene_with_box_at(6.0), 200);  // shared with alice: stays in her list once
  std::vector<std::string> newest_first(mine.rbegin(), mine.rend());

  EXPECT_EQ(listed_ids(server.client().Get("/v1/scenes", bearer(alice))), newest_first);
  std::vector<std::string> paged;
  std::string next = "/v1/scenes?limit=2";
  size_t pages = 0;
  while (!next.empty() && pages < 10) {
    auto res = server.client().Get(next.c_str(), bearer(alice));
    std::vector<std::string> page = listed_ids(res);
    EXPECT_LE(page.size(), 2u);
    paged.insert(paged.end(), page.begin(), page.end());
    json body = json::parse(res->body);
    next = body["next"].is_null() ? "" : body["next"].get<std::string>();
    ++pages;
  }
  EXPECT_EQ(pages, 3u);
  EXPECT_EQ(paged, newest_first);

  EXPECT_EQ(listed_ids(server.client().Get("/v1/scenes", bearer(bob))), (std::vector<std::string>{bobs, mine.front()}))
      << "bob's own, newest reference first by creation";
  expect_unauthorized(server.client().Get("/v1/scenes"), false);
  json problem = expect_problem(server.client().Get("/v1/scenes?limit=0", bearer(alice)), 400);
  EXPECT_EQ(problem["errors"][0]["parameter"], "limit");
  problem = expect_problem(server.client().Get("/v1/scenes?cursor=nonsense", bearer(alice)), 400);
  EXPECT_EQ(problem["errors"][0]["parameter"], "cursor");
}

TEST(Listing, OffOnAnOpenServerUnlessAllowed) {
  {
    TestServer server;
    post_scene(server, scene_with_box_at(7.0));
    json problem = expect_problem(server.client().Get("/v1/scenes"), 403);
    EXPECT_NE(problem["detail"].get<std::string>().find("--allow-listing"), std::string::npos);
  }
  rr::server::ServerConfig config = test_server_config();
  config.allow_listing = true;
  TestServer server(config);
  auto first = post_scene(server, scene_with_box_at(7.0));
  auto second = post_scene(server, scene_with_box_at(7.1));
  ASSERT_TRUE(first && second);
  auto res = server.client().Get("/v1/scenes");
  EXPECT_EQ(listed_ids(res),
            (std::vector<std::string>{json::parse(second->body)["id"], json::parse(first->body)["id"]}));
  json listed = json::parse(res->body)["scenes"][0];
  EXPECT_EQ(listed["location"], "/v1/scenes/" + listed["id"].get<std::string>());
  EXPECT_TRUE(listed["expires"].is_null());
  EXPECT_GT(listed["bytes"].get<double>(), 0.0);
  EXPECT_TRUE(json::parse(res->body)["next"].is_null());
}

}  // namespace

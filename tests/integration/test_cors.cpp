// CORS: reads (GET, POST /v1/render, imports without store=1) answer "Access-Control-Allow-Origin: *"
// to every origin, also on errors; writes echo an origin listed in --cors-origins (with Vary: Origin)
// and refuse other_origin origins with 403, except the server's own pages (Origin naming the Host). A
// preflight answers 204 with the allowed methods, headers and max-age, or 403 without allow headers.
#include "server_fixture.hpp"

namespace {

using nlohmann::json;
using namespace rr::testing;

const std::string listed = "https://app.example.com";
const std::string other_origin = "https://elsewhere.example.org";

rr::server::ServerConfig cors_config() {
  rr::server::ServerConfig config = test_server_config();
  config.cors_origins = {"http://localhost:5173", listed};
  return config;
}

httplib::Result preflight(const TestServer& server, const std::string& path, const std::string& origin,
                          const std::string& method) {
  return server.client().Options(path.c_str(), {{"Origin", origin},
                                                {"Access-Control-Request-Method", method},
                                                {"Access-Control-Request-Headers", "content-type, authorization"}});
}

bool lists(const std::string& list, const std::string& item) {
  return (", " + list + ",").find(", " + item + ",") != std::string::npos;
}

class Cors : public SharedServerTest<Cors> {
 public:
  static rr::server::ServerConfig config() { return cors_config(); }
};

TEST_F(Cors, PreflightForAReadFromAnyOrigin) {
  auto res = preflight(*server_, "/v1/render", other_origin, "POST");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 204) << res->body;
  EXPECT_EQ(res->get_header_value("Access-Control-Allow-Origin"), "*");
  EXPECT_TRUE(lists(res->get_header_value("Access-Control-Allow-Methods"), "POST"));
  std::string headers = res->get_header_value("Access-Control-Allow-Headers");
  EXPECT_TRUE(lists(headers, "Content-Type")) << headers;
  EXPECT_TRUE(lists(headers, "Authorization")) << headers;
  EXPECT_GT(std::stoi(res->get_header_value("Access-Control-Max-Age")), 0);
  EXPECT_TRUE(res->body.empty());
}

TEST_F(Cors, PreflightForAWriteFromAListedOrigin) {
  auto res = preflight(*server_, "/v1/scenes", listed, "POST");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 204) << res->body;
  EXPECT_EQ(res->get_header_value("Access-Control-Allow-Origin"), listed);
  EXPECT_TRUE(lists(res->get_header_value("Vary"), "Origin"));
  std::string methods = res->get_header_value("Access-Control-Allow-Methods");
  EXPECT_TRUE(lists(methods, "POST")) << methods;
  EXPECT_TRUE(lists(methods, "GET")) << methods;
  auto del = preflight(*server_, "/v1/scenes/0123456789abcdef", listed, "DELETE");
  ASSERT_TRUE(del);
  EXPECT_EQ(del->status, 204);
  EXPECT_TRUE(lists(del->get_header_value("Access-Control-Allow-Methods"), "DELETE"));
}

TEST_F(Cors, PreflightForAWriteFromAnotherOriginIsRefused) {
  for (const auto& [path, method] :
       std::vector<std::pair<std::string, std::string>>{{"/v1/scenes", "POST"},
                                                        {"/v1/scenes/0123456789abcdef", "PUT"},
                                                        {"/v1/scenes/0123456789abcdef", "DELETE"},
                                                        {"/v1/import/obj?store=1", "POST"}}) {
    SCOPED_TRACE(method + " " + path);
    auto res = preflight(*server_, path, other_origin, method);
    json problem = expect_problem(res, 403);
    EXPECT_NE(problem["detail"].get<std::string>().find("--cors-origins"), std::string::npos);
    EXPECT_FALSE(res->has_header("Access-Control-Allow-Origin"));
    EXPECT_FALSE(res->has_header("Access-Control-Allow-Methods"));
  }
  // The same paths' reads stay open to that origin.
  auto read = preflight(*server_, "/v1/scenes/0123456789abcdef", other_origin, "GET");
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 204);
  EXPECT_FALSE(lists(read->get_header_value("Access-Control-Allow-Methods"), "DELETE"));
  auto import = preflight(*server_, "/v1/import/obj", other_origin, "POST");
  ASSERT_TRUE(import);
  EXPECT_EQ(import->status, 204);
}

TEST_F(Cors, NotAPreflight) {
  auto plain = server_->client().Options("/v1/scenes");
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->status, 204);
  EXPECT_TRUE(lists(plain->get_header_value("Allow"), "POST")) << plain->get_header_value("Allow");
  expect_problem(preflight(*server_, "/v1/nothing-here", other_origin, "GET"), 404);
  expect_problem(preflight(*server_, "/v1/render", other_origin, "DELETE"), 405);
}

TEST_F(Cors, SimpleReadsAnswerEveryOriginAlsoOnErrors) {
  auto health = server_->client().Get("/healthz", {{"Origin", other_origin}});
  ASSERT_TRUE(health);
  EXPECT_EQ(health->get_header_value("Access-Control-Allow-Origin"), "*");
  std::string exposed = health->get_header_value("Access-Control-Expose-Headers");
  for (const char* name : {"Server-Timing", "X-Scene-Id", "ETag", "Location", "Retry-After", "WWW-Authenticate"}) {
    EXPECT_TRUE(lists(exposed, name)) << name << " in " << exposed;
  }
  auto render = server_->client().Post("/v1/render", {{"Origin", other_origin}}, small_request, "application/json");
  ASSERT_TRUE(render);
  EXPECT_EQ(render->status, 200);
  EXPECT_EQ(render->get_header_value("Access-Control-Allow-Origin"), "*");
  auto missing = server_->client().Get("/v1/scenes/0123456789abcdef", {{"Origin", other_origin}});
  expect_problem(missing, 404);
  EXPECT_EQ(missing->get_header_value("Access-Control-Allow-Origin"), "*");
  auto invalid = server_->client().Post("/v1/render", {{"Origin", other_origin}}, R"({"options": {"width": -1}})",
                                        "application/json");
  expect_problem(invalid, 422);
  EXPECT_EQ(invalid->get_header_value("Access-Control-Allow-Origin"), "*");
}

// Answers the connection front gives on its own (here 414) carry the header too.
TEST_F(Cors, RefusalsOfTheConnectionFrontAnswerEveryOrigin) {
  std::string answer =
      raw_exchange(server_->port(),
                   "GET /" + std::string(10000, 'a') + " HTTP/1.1\r\nHost: x\r\nOrigin: " + other_origin + "\r\n\r\n");
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 414")) << answer.substr(0, 200);
  EXPECT_NE(answer.find("\r\nAccess-Control-Allow-Origin: *\r\n"), std::string::npos) << answer.substr(0, 400);
}

TEST_F(Cors, WritesFromAnotherOriginAreRefused) {
  json scene = scene_with_box_at(1.0);
  auto refused = server_->client().Post("/v1/scenes", {{"Origin", other_origin}}, scene.dump(), "application/json");
  expect_problem(refused, 403);
  EXPECT_FALSE(refused->has_header("Access-Control-Allow-Origin"));
  EXPECT_TRUE(lists(refused->get_header_value("Vary"), "Origin"));
  auto import = server_->client().Post("/v1/import/obj?store=1", {{"Origin", other_origin}},
                                       "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "model/obj");
  expect_problem(import, 403);
  // Nothing was stored: the first store from a client without Origin creates it.
  auto stored = server_->client().Post("/v1/scenes", scene.dump(), "application/json");
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->status, 201) << stored->body;
  std::string path = "/v1/scenes/" + json::parse(stored->body)["id"].get<std::string>();
  expect_problem(server_->client().Delete(path.c_str(), {{"Origin", other_origin}}), 403);
  EXPECT_EQ(server_->client().Get(path.c_str())->status, 200);
}

TEST_F(Cors, WritesFromAListedOriginOrTheServersOwnPages) {
  auto res =
      server_->client().Post("/v1/scenes", {{"Origin", listed}}, scene_with_box_at(2.0).dump(), "application/json");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 201) << res->body;
  EXPECT_EQ(res->get_header_value("Access-Control-Allow-Origin"), listed);
  EXPECT_TRUE(lists(res->get_header_value("Vary"), "Origin"));
  EXPECT_TRUE(lists(res->get_header_value("Access-Control-Expose-Headers"), "Location"));
  const std::string own = "http://127.0.0.1:" + std::to_string(server_->port());
  auto same_origin =
      server_->client().Post("/v1/scenes", {{"Origin", own}}, scene_with_box_at(2.1).dump(), "application/json");
  ASSERT_TRUE(same_origin);
  EXPECT_EQ(same_origin->status, 201) << same_origin->body;
}

TEST(CorsDefaults, NoOriginMayWriteUnlessListed) {
  TestServer server;
  auto res = preflight(server, "/v1/scenes", "http://localhost:5173", "POST");
  expect_problem(res, 403);
  auto read = preflight(server, "/v1/render", "http://localhost:5173", "POST");
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 204);
  EXPECT_EQ(read->get_header_value("Access-Control-Allow-Origin"), "*");
}

}  // namespace

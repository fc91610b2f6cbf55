// The real HTTP service on a free loopback port (port 0), in-process, spoken to over real HTTP with
// httplib::Client (and a raw socket where a well-behaved client cannot send the request). Checks
// statuses, problem+json bodies with their JSON Pointers, headers, and that rejected requests leave
// the server healthy.
#include "server/problem.hpp"
#include "server_fixture.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

namespace {

using nlohmann::json;
using namespace rr::testing;

class ServerTest : public SharedServerTest<ServerTest> {
 protected:
  static void expect_healthy() { rr::testing::expect_healthy(*server_); }
};

// Also the health endpoint's exact body, which deployments match on.
TEST_F(ServerTest, HealthzSaysOk) {
  auto res = client().Get("/healthz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(json::parse(res->body)["status"], "ok");
}

void expect_render_ok(const httplib::Result& res, int width, int height) {
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "image/png");
  PngSize size = png_size(res->body);
  EXPECT_EQ(size.width, uint32_t(width));
  EXPECT_EQ(size.height, uint32_t(height));
  std::string timing = res->get_header_value("Server-Timing");
  for (const char* stage : {"parse", "tessellate", "raster", "shade", "encode", "total"}) {
    EXPECT_NE(timing.find(std::string(stage) + ";dur="), std::string::npos) << stage << " in " << timing;
  }
  EXPECT_EQ(res->get_header_value("X-Scene-Id").size(), 16u);
}

TEST_F(ServerTest, RendersInlineRequest) {
  expect_render_ok(client().Post("/v1/render", small_request, "application/json"), 64, 48);
}

TEST_F(ServerTest, AcceptsJsonWithParametersOrNoContentType) {
  expect_render_ok(client().Post("/v1/render", small_request, "application/json; charset=utf-8"), 64, 48);
  // httplib::Client always sends a Content-Type, so the request without one goes over a raw socket.
  std::string response = raw_exchange(server_->port(),
                                      "POST /v1/render HTTP/1.1\r\nHost: test\r\n"
                                      "Connection: close\r\nContent-Length: " +
                                          std::to_string(std::strlen(small_request)) + "\r\n\r\n" + small_request);
  EXPECT_EQ(response.rfind("HTTP/1.1 200", 0), 0u) << response.substr(0, 300);
  EXPECT_NE(response.find("Content-Type: image/png"), std::string::npos) << response.substr(0, 300);
}

TEST_F(ServerTest, RendersStudioExample) {
  std::string text = rr::testing::read_file(rr::testing::examples_dir() / "studio.json");
  json options = json::parse(text).value("options", json::object());
  expect_render_ok(client().Post("/v1/render", text, "application/json"), options.value("width", 640),
                   options.value("height", 480));
}

TEST_F(ServerTest, MalformedJsonIs400WithPointer) {
  json problem = expect_problem(client().Post("/v1/render", R"({"scene": )", "application/json"), 400);
  ASSERT_TRUE(problem.contains("errors")) << problem;
  EXPECT_TRUE(problem["errors"][0]["pointer"].is_string()) << problem;
  EXPECT_TRUE(problem["errors"][0]["detail"].is_string()) << problem;
}

TEST_F(ServerTest, InvalidSceneIs422AtTheField) {
  const char* body = R"({"scene": {"walls": [{"start": [0, 0], "end": [2, 0], "thickness": -1}]}})";
  json problem = expect_problem(client().Post("/v1/render", body, "application/json"), 422);
  ASSERT_TRUE(problem.contains("errors")) << problem;
  EXPECT_EQ(problem["errors"][0]["pointer"], "/scene/walls/0/thickness") << problem;
}

TEST_F(ServerTest, OversizedImageIs413AtTheField) {
  json problem =
      expect_problem(client().Post("/v1/render", R"({"options": {"width": 100000}})", "application/json"), 413);
  ASSERT_TRUE(problem.contains("errors")) << problem;
  EXPECT_EQ(problem["errors"][0]["pointer"], "/options/width") << problem;
}

TEST_F(ServerTest, UnknownRouteIs404) {
  expect_problem(client().Get("/no/such/thing"), 404);
  expect_problem(client().Post("/no/such/thing", "{}", "application/json"), 404);
  expect_healthy();
}

TEST_F(ServerTest, WrongMethodIs405WithAllow) {
  expect_problem_with(client().Get("/v1/render"), 405, "Allow", "POST");
  expect_problem_with(client().Post("/healthz", "{}", "application/json"), 405, "Allow", "GET, HEAD");
}

// Requests refused from their headers are answered before the body is read, and the connection is
// closed because the unread body is still on it. They go over a raw socket in one send: a client
// still writing when the server closes may see a reset instead of the answer (see
// close_after_response), which would make an httplib::Client test flaky.
std::string refused_exchange(int port, const std::string& headers, const std::string& body) {
  return raw_exchange(
      port, "POST /v1/render HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\n" + headers + "\r\n" + body);
}

void expect_refused(const std::string& response, int status) {
  EXPECT_EQ(response.rfind("HTTP/1.1 " + std::to_string(status), 0), 0u) << response;
  EXPECT_NE(response.find("Content-Type: application/problem+json"), std::string::npos) << response;
  EXPECT_NE(response.find("Connection: close"), std::string::npos) << response;
  EXPECT_NE(response.find("\"status\":" + std::to_string(status)), std::string::npos) << response;
}

TEST_F(ServerTest, ChunkedBodyIs411) {
  expect_refused(refused_exchange(server_->port(), "Transfer-Encoding: chunked\r\n", "2\r\n{}\r\n0\r\n\r\n"), 411);
  expect_healthy();
}

TEST_F(ServerTest, ContentEncodingIs415) {
  expect_refused(refused_exchange(server_->port(), "Content-Encoding: gzip\r\nContent-Length: 2\r\n", "{}"), 415);
  expect_healthy();
}

TEST_F(ServerTest, NonJsonContentTypeIs415) {
  expect_problem(client().Post("/v1/render", small_request, "text/plain"), 415);
}

// A declared body over 8 MiB is refused from its headers: the answer comes although the body is
// never sent.
TEST_F(ServerTest, DeclaredBodyOverLimitIs413BeforeReading) {
  expect_refused(refused_exchange(server_->port(), "Content-Length: 9437184\r\n", "{\"scene\":"), 413);
  expect_healthy();
}

TEST_F(ServerTest, PostWithoutLengthIs411) {
  expect_refused(refused_exchange(server_->port(), "", "{}"), 411);
  expect_healthy();
}

TEST_F(ServerTest, ConflictingLengthsAre400) {
  expect_refused(refused_exchange(server_->port(), "Content-Length: 2\r\nContent-Length: 3\r\n", "{}"), 400);
  expect_refused(refused_exchange(server_->port(), "Content-Length: 2x\r\n", "{}"), 400);
  expect_healthy();
}

TEST_F(ServerTest, HealthAndLiveness) {
  expect_healthy();
  auto res = client().Get("/livez");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
}

TEST_F(ServerTest, ListsPipelinesFromTheTable) {
  auto res = client().Get("/v1/pipelines");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  json body = json::parse(res->body);
  ASSERT_TRUE(body["pipelines"].is_array()) << body;
  ASSERT_FALSE(body["pipelines"].empty());
  bool has_zbuffer = false;
  for (const json& p : body["pipelines"]) {
    EXPECT_TRUE(p["summary"].is_string());
    has_zbuffer = has_zbuffer || p["name"] == "zbuffer";
  }
  EXPECT_TRUE(has_zbuffer) << body;
}

TEST_F(ServerTest, ServesExamplesByValidatedName) {
  auto list = client().Get("/examples/");
  ASSERT_TRUE(list);
  ASSERT_EQ(list->status, 200);
  json names = json::parse(list->body)["examples"];
  EXPECT_NE(std::find(names.begin(), names.end(), "studio"), names.end()) << names;
  auto studio = client().Get("/examples/studio.json");
  ASSERT_TRUE(studio);
  EXPECT_EQ(studio->status, 200);
  EXPECT_EQ(studio->body, rr::testing::read_file(rr::testing::examples_dir() / "studio.json"));
  expect_problem(client().Get("/examples/no_such_example.json"), 404);
  expect_problem(client().Get("/examples/Studio.json"), 404);
  expect_problem(client().Get("/examples/..%2F..%2FCMakeLists.json"), 404);
  expect_problem(client().Get("/examples/%2e%2e.json"), 404);
}

TEST_F(ServerTest, ServesTheWebPage) {
  auto res = client().Get("/");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type").rfind("text/html", 0), 0u);
  EXPECT_NE(res->body.find("/v1/render"), std::string::npos);
}

TEST_F(ServerTest, SecondServiceCannotTakeTheSamePort) {
  rr::server::ServerConfig config = server_->service().config();
  config.port = server_->port();
  rr::server::Service second(config);
  EXPECT_THROW(second.start(), std::runtime_error);
  expect_healthy();
}

// The one mapping from errors to problems, checked directly: an internal error's text (which can
// hold paths and internals) must never reach the client.
TEST(Problem, MapsErrorsToStatusesAndHidesInternalText) {
  using rr::InputError;
  EXPECT_EQ(rr::server::status_for(InputError::Kind::malformed), 400);
  EXPECT_EQ(rr::server::status_for(InputError::Kind::invalid), 422);
  EXPECT_EQ(rr::server::status_for(InputError::Kind::too_large), 413);
  std::string log_detail;
  auto input = rr::server::problem_from_exception(
      std::make_exception_ptr(InputError(InputError::Kind::invalid, "/camera/fov_y", "must be in (1, 170)")),
      log_detail);
  EXPECT_EQ(input.status, 422);
  EXPECT_TRUE(log_detail.empty());
  EXPECT_EQ(json::parse(input.body)["errors"][0]["pointer"], "/camera/fov_y");
  auto internal =
      rr::server::problem_from_exception(std::make_exception_ptr(std::runtime_error("secret /etc/path")), log_detail);
  EXPECT_EQ(internal.status, 500);
  EXPECT_EQ(log_detail, "secret /etc/path");
  EXPECT_EQ(internal.body.find("secret"), std::string::npos) << internal.body;
  EXPECT_EQ(json::parse(internal.body)["type"], "about:blank");
}

}  // namespace

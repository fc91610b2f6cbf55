// A render whose BSP build runs past the server's deadline is answered 504 soon after the deadline
// (the build checks it every few thousand classifications, not every few thousand nodes), and the
// server renders normally right after. The bound is the deadline plus 3 s, for sanitizer builds and a
// loaded machine (the whole build takes far longer); bench/deadline_overshoot.py measures the
// overshoot itself.
#include "server_fixture.hpp"

#include <chrono>
#include <random>

namespace {

using namespace rr::testing;
using json = nlohmann::json;

// `count` seeded random triangles through a 20 m cube, drawn with the bsp pipeline: nearly every
// splitter cuts many of them, so the build takes seconds.
json intersecting_soup_request(size_t count) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> coord(-10.0, 10.0), edge(-2.0, 2.0);
  json vertices = json::array(), faces = json::array();
  while (faces.size() < count) {
    double a[3], b[3], c[3];
    for (int k = 0; k < 3; ++k) a[k] = coord(rng), b[k] = a[k] + edge(rng), c[k] = a[k] + edge(rng);
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    if (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] < 0.04) continue;  // no slivers
    const size_t first = vertices.size();
    for (const double* p : {a, b, c}) vertices.push_back({p[0], p[1], p[2]});
    faces.push_back({first, first + 1, first + 2});
  }
  return {{"scene",
           {{"background", "#202020"},
            {"solids", json::array({{{"type", "mesh"},
                                     {"id", "soup"},
                                     {"color", "#b0b0b0"},
                                     {"vertices", std::move(vertices)},
                                     {"faces", std::move(faces)}}})}}},
          {"camera", {{"position", {0, 2, 30}}, {"target", {0, 0, 0}}, {"far", 100}}},
          {"options", {{"width", 320}, {"height", 240}, {"pipeline", "bsp"}, {"shading", "flat"}}}};
}

TEST(DeadlineBsp, LongBuildIs504SoonAfterTheDeadlineThenTheServerRenders) {
  rr::server::ServerConfig config = test_server_config();
  config.render_timeout_ms = 500;
  config.max_body_bytes = 64u << 20;
  TestServer server(config);
  const std::string body = intersecting_soup_request(50000).dump();
  auto client = server.client(60);
  const auto sent = std::chrono::steady_clock::now();
  auto res = client.Post("/v1/render", body, "application/json");
  const double answered_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count();
  json problem = expect_problem(res, 504);
  EXPECT_NE(problem.value("detail", "").find("deadline of 500 ms"), std::string::npos) << problem;
  EXPECT_LT(answered_ms, 500.0 + 3000.0);
  std::printf("[deadline] 504 after %.0f ms with a deadline of 500 ms\n", answered_ms);

  auto normal = client.Post("/v1/render", small_request, "application/json");
  ASSERT_TRUE(normal);
  EXPECT_EQ(normal->status, 200) << normal->body.substr(0, 300);
}

}  // namespace

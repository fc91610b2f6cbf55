// Admission, deadlines and shutdown over real HTTP. Render slots are held deterministically through
// the config's on_render_admitted seam (a latch the test opens), so saturation does not depend on
// how fast this machine renders: with 1 slot and a queue of 1, the third render is refused at once
// with 503 + Retry-After while /livez still answers. Deadlines (queued: 503, drawing: 504), the drain
// bound, and SIGTERM on the real `roomrender serve` binary (in-flight render finishes, exit 0).
#include "server_fixture.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <future>
#include <thread>

namespace {

using nlohmann::json;
using namespace rr::testing;
using namespace std::chrono_literals;

// A latch renders wait on once admitted, until the test opens it (or `max_hold` passes).
struct Latch {
  std::shared_ptr<std::atomic<bool>> open = std::make_shared<std::atomic<bool>>(false);
  std::function<void()> hook(std::chrono::milliseconds max_hold = 20s) const {
    return [open = open, max_hold] {
      auto until = std::chrono::steady_clock::now() + max_hold;
      while (!*open && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(1ms);
    };
  }
  void release() const { *open = true; }
};

// Polls /metrics until `name` reaches `value` (or 10 s pass).
bool wait_for_metric(const TestServer& server, const std::string& name, double value) {
  auto until = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < until) {
    if (server.metric(name) == value) return true;
    std::this_thread::sleep_for(5ms);
  }
  return false;
}

std::future<httplib::Result> post_async(const TestServer& server, const std::string& body) {
  return std::async(std::launch::async,
                    [&server, body] { return server.client().Post("/v1/render", body, "application/json"); });
}

rr::server::ServerConfig one_slot_config(const Latch& latch) {
  rr::server::ServerConfig config = test_server_config();
  config.render_workers = 1;
  config.render_queue = 1;
  config.on_render_admitted = latch.hook();
  return config;
}

TEST(Lifecycle, SaturationIs503WithRetryAfterWhileLivezAnswers) {
  Latch latch;
  TestServer server(one_slot_config(latch));
  auto running = post_async(server, small_request);
  ASSERT_TRUE(wait_for_metric(server, "roomrender_renders_in_flight", 1.0));
  auto queued = post_async(server, small_request);
  ASSERT_TRUE(wait_for_metric(server, "roomrender_renders_queued", 1.0));

  expect_problem_with(server.client().Post("/v1/render", small_request, "application/json"), 503, "Retry-After", "1");
  auto stored = server.client().Post("/v1/scenes", json::parse(small_request)["scene"].dump(), "application/json");
  expect_problem(stored, 503);  // storing parses and tessellates: it needs a slot too

  auto live = server.client().Get("/livez");
  ASSERT_TRUE(live);
  EXPECT_EQ(live->status, 200);
  auto ready = server.client().Get("/readyz");
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->status, 503);
  EXPECT_EQ(json::parse(ready->body)["status"], "saturated");
  EXPECT_EQ(ready->get_header_value("Retry-After"), "1");
  EXPECT_EQ(server.metric("roomrender_renders_rejected_total", {"reason=\"saturated\""}), 2.0);

  latch.release();
  httplib::Result first = running.get(), second = queued.get();
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first->status, 200);
  EXPECT_EQ(second->status, 200);
  auto ready_again = server.client().Get("/readyz");
  ASSERT_TRUE(ready_again);
  EXPECT_EQ(ready_again->status, 200);
}

// The deadline counts from arrival: the queued render gives up at it (503, it never started), and
// the render that held the slot past it is stopped at its next check (504).
TEST(Lifecycle, DeadlineIs503InTheQueueAnd504WhileDrawing) {
  Latch latch;
  rr::server::ServerConfig config = one_slot_config(latch);
  config.render_timeout_ms = 300;
  TestServer server(config);
  auto running = post_async(server, small_request);
  ASSERT_TRUE(wait_for_metric(server, "roomrender_renders_in_flight", 1.0));
  expect_problem_with(server.client().Post("/v1/render", small_request, "application/json"), 503, "Retry-After", "1");
  latch.release();
  expect_problem(running.get(), 504);
  EXPECT_EQ(server.metric("roomrender_renders_rejected_total", {"reason=\"expired\""}), 1.0);
  EXPECT_EQ(server.metric("roomrender_renders_rejected_total", {"reason=\"deadline\""}), 1.0);
}

// Without any test seam: a 1 ms deadline cannot cover tessellating and drawing a 2048x2048 frame.
TEST(Lifecycle, RealRenderPastItsDeadlineIs504) {
  rr::server::ServerConfig config = test_server_config();
  config.render_timeout_ms = 1;
  TestServer server(config);
  json request = json::parse(read_file(examples_dir() / "apartment.json"));
  request["options"]["width"] = 2048;
  request["options"]["height"] = 2048;
  json problem = expect_problem(server.client().Post("/v1/render", request.dump(), "application/json"), 504);
  EXPECT_NE(problem.value("detail", "").find("deadline of 1 ms"), std::string::npos) << problem;
}

// stop() gives in-flight renders drain_timeout_ms; one still held after that is cancelled and
// answers 503, and stop() reports that the drain did not complete.
TEST(Lifecycle, DrainBoundCancelsRendersThatDoNotFinish) {
  Latch latch;
  rr::server::ServerConfig config = one_slot_config(latch);
  config.drain_timeout_ms = 100;
  config.on_render_admitted = latch.hook(600ms);  // ignores cancellation while it holds the slot
  TestServer server(config);
  auto running = post_async(server, small_request);
  ASSERT_TRUE(wait_for_metric(server, "roomrender_renders_in_flight", 1.0));
  rr::server::DrainReport report = server.service().stop();
  EXPECT_FALSE(report.drained);
  expect_problem(running.get(), 503);
}

TEST(Lifecycle, DrainWaitsForRendersThatFinishInTime) {
  Latch latch;
  rr::server::ServerConfig config = one_slot_config(latch);
  config.on_render_admitted = latch.hook(200ms);
  TestServer server(config);
  auto running = post_async(server, small_request);
  ASSERT_TRUE(wait_for_metric(server, "roomrender_renders_in_flight", 1.0));
  rr::server::DrainReport report = server.service().stop();
  EXPECT_TRUE(report.drained);
  httplib::Result res = running.get();
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
}

double child_metric(int port, const std::string& name) {
  httplib::Client client("127.0.0.1", port);
  auto res = client.Get("/metrics");
  if (!res) return -1.0;
  size_t at = res->body.find("\n" + name + " ");
  return at == std::string::npos ? -1.0 : std::stod(res->body.substr(at + name.size() + 2));
}

// The real binary: a 4096x4096 render (over a second here) is in flight when SIGTERM arrives; the
// server stops accepting at once, the render completes with its full image, and the process exits 0
// reporting a complete drain.
TEST(Lifecycle, SigtermDrainsInFlightRendersAndExitsZero) {
  // A generous drain bound: on a loaded machine the render may take several seconds.
  ServerProcess child = start_server_process(
      {"serve", "--port", "0", "--log-requests", "0", "--render-workers", "1", "--drain-timeout-ms", "60000"});
  ASSERT_GT(child.pid, 0);
  ASSERT_GT(child.port, 0);
  json request = json::parse(read_file(examples_dir() / "apartment.json"));
  request["options"]["width"] = 4096;
  request["options"]["height"] = 4096;
  auto render = std::async(std::launch::async, [port = child.port, body = request.dump()] {
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(60);
    return client.Post("/v1/render", body, "application/json");
  });
  auto until = std::chrono::steady_clock::now() + 10s;
  while (child_metric(child.port, "roomrender_renders_in_flight") != 1.0 && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(2ms);
  }
  ASSERT_EQ(::kill(child.pid, SIGTERM), 0);
  bool refused = false;  // the listening socket closes at once
  for (auto stop = std::chrono::steady_clock::now() + 3s; !refused && std::chrono::steady_clock::now() < stop;) {
    int fd = connect_loopback(child.port);
    refused = fd < 0;
    if (fd >= 0) ::close(fd);
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_TRUE(refused) << "still accepting connections after SIGTERM";
  httplib::Result res = render.get();
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200);
  PngSize size = png_size(res->body);
  EXPECT_EQ(size.width, 4096u);
  EXPECT_EQ(size.height, 4096u);
  int status = 0;
  ::waitpid(child.pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  char line[4096] = {};
  json stopped = std::fgets(line, sizeof line, child.out) ? json::parse(line, nullptr, false) : json();
  EXPECT_EQ(stopped.value("event", ""), "stopped") << line;
  EXPECT_EQ(stopped.value("drained", false), true) << line;
  std::fclose(child.out);
}

}  // namespace

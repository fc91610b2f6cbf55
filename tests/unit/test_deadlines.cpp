// Deadlines inside long loops: a BSP build, and a frame through each pipeline, of a large random
// triangle soup stop with RenderCancelled soon after their deadline. "Soon" is counted in the CPU
// time the process spends past the deadline, not in wall time: on a shared machine the process can
// wait for a core for longer than any work it does, and that wait says nothing of where the loops
// check their token. The bound is a second of CPU, loose enough for sanitizer builds; the wall-clock
// overshoot is printed, and bench/ times it through the server.
#include "render/pipelines/bsp.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/soup_builder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <random>
#include <thread>

namespace rr {
namespace {

using Clock = std::chrono::steady_clock;
using testing::process_cpu_ms;

// 10^5 triangles scattered through a 20 m cube: nearly every splitter cuts many of them, so the
// build runs for seconds without a deadline.
const PolygonSoup& large_soup() {
  static const PolygonSoup soup = [] {
    std::mt19937 rng(19);
    return testing::random_triangle_soup(rng, 100000, 10.0);
  }();
  return soup;
}

// Reads the process's CPU time when a deadline passes, from a thread that sleeps until then; so the
// CPU time spent between the deadline and a later moment is known. A watcher woken late reads a
// later figure, which can only make the measured overshoot smaller than the true one by the work
// done while it waited for a core, never larger.
class DeadlineWatch {
 public:
  explicit DeadlineWatch(Clock::time_point deadline)
      : thread_([this, deadline] {
          std::unique_lock lock(mutex_);
          if (!wake_.wait_until(lock, deadline, [this] { return stop_; })) cpu_at_deadline_ = process_cpu_ms();
        }) {}
  ~DeadlineWatch() { finish(); }

  // CPU milliseconds of the whole process from the deadline until now (0 when it has not passed).
  double cpu_ms_since_deadline() {
    const double now = process_cpu_ms();
    finish();
    return cpu_at_deadline_ < 0 ? 0.0 : now - cpu_at_deadline_;
  }

 private:
  void finish() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  double cpu_at_deadline_ = -1;
  std::thread thread_;
};

// Runs `work` under a deadline `budget` from now; returns the CPU time the process spent past the
// deadline before `work` threw RenderCancelled (fails when it did not throw).
template <class Fn>
double overshoot_cpu_ms(std::chrono::milliseconds budget, Fn&& work) {
  CancelToken token;
  token.deadline = Clock::now() + budget;
  DeadlineWatch watch(token.deadline);
  bool cancelled = false;
  try {
    work(token);
  } catch (const RenderCancelled&) {
    cancelled = true;
  }
  const double cpu_ms = watch.cpu_ms_since_deadline();
  const double late_ms = std::chrono::duration<double, std::milli>(Clock::now() - token.deadline).count();
  EXPECT_TRUE(cancelled) << "finished " << -late_ms << " ms before its deadline";
  std::printf("[deadline] RenderCancelled %.1f ms (%.1f ms of CPU) after a deadline of %lld ms\n", late_ms, cpu_ms,
              (long long)budget.count());
  return cpu_ms;
}

TEST(Deadlines, BspBuildStopsSoonAfterItsDeadline) {
  const PolygonSoup& soup = large_soup();
  const double cpu_ms = overshoot_cpu_ms(std::chrono::milliseconds(200),
                                         [&](const CancelToken& token) { build_bsp(soup, BspOptions{}, &token); });
  EXPECT_LT(cpu_ms, 1000.0);
}

TEST(Deadlines, BspBuildWithAnExpiredDeadlineStopsAtOnce) {
  const PolygonSoup& soup = large_soup();
  const double cpu_ms = overshoot_cpu_ms(std::chrono::milliseconds(0),
                                         [&](const CancelToken& token) { build_bsp(soup, BspOptions{}, &token); });
  EXPECT_LT(cpu_ms, 1000.0);
}

// Every pipeline either finishes a 640x480 frame of the soup or stops within a second of CPU past a
// short deadline: none runs on unchecked past it.
TEST(Deadlines, EveryPipelineEndsSoonAfterAShortDeadline) {
  const RenderRequest request = request_from_json(testing::example_request("studio", 640, 480));
  const PolygonSoup& soup = large_soup();
  for (const PipelineInfo& pipeline : pipeline_table()) {
    SCOPED_TRACE(pipeline.name);
    RenderOptions options = request.options;
    options.pipeline = pipeline_id(pipeline);
    CancelToken token;
    token.deadline = Clock::now() + std::chrono::milliseconds(50);
    DeadlineWatch watch(token.deadline);
    RenderContext context;
    context.cancel = &token;
    try {
      render_frame(request.scene, soup, request.camera, options, context);
    } catch (const RenderCancelled&) {
    }
    EXPECT_LT(watch.cpu_ms_since_deadline(), 1000.0);
  }
}

TEST(Deadlines, BspFrameStopsSoonAfterAShortDeadline) {
  const RenderRequest request = request_from_json(testing::example_request("studio", 320, 240));
  RenderOptions options = request.options;
  options.pipeline = pipeline_id("bsp");
  const double cpu_ms = overshoot_cpu_ms(std::chrono::milliseconds(300), [&](const CancelToken& token) {
    RenderContext context;
    context.cancel = &token;
    render_frame(request.scene, large_soup(), request.camera, options, context);
  });
  EXPECT_LT(cpu_ms, 1000.0);
}

}  // namespace
}  // namespace rr

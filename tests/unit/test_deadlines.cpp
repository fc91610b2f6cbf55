// Deadlines inside long loops: a BSP build, and a frame through each pipeline, of a large random
// triangle soup stop with RenderCancelled soon after their deadline (the bound is the deadline plus
// a second, loose enough for sanitizer builds; bench numbers are in the commit that added it).
#include "render/pipelines/bsp.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/soup_builder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <random>

namespace rr {
namespace {

using Clock = std::chrono::steady_clock;

// 10^5 triangles scattered through a 20 m cube: nearly every splitter cuts many of them, so the
// build runs for seconds without a deadline.
const PolygonSoup& large_soup() {
  static const PolygonSoup soup = [] {
    std::mt19937 rng(19);
    return testing::random_triangle_soup(rng, 100000, 10.0);
  }();
  return soup;
}

// Runs `work` under a deadline `budget` from now; returns how long after the deadline it threw
// RenderCancelled (fails when it did not throw).
template <class Fn>
double overshoot_ms(std::chrono::milliseconds budget, Fn&& work) {
  CancelToken token;
  token.deadline = Clock::now() + budget;
  bool cancelled = false;
  try {
    work(token);
  } catch (const RenderCancelled&) {
    cancelled = true;
  }
  const double late_ms = std::chrono::duration<double, std::milli>(Clock::now() - token.deadline).count();
  EXPECT_TRUE(cancelled) << "finished " << -late_ms << " ms before its deadline";
  std::printf("[deadline] RenderCancelled %.1f ms after a deadline of %lld ms\n", late_ms, (long long)budget.count());
  return late_ms;
}

TEST(Deadlines, BspBuildStopsSoonAfterItsDeadline) {
  const PolygonSoup& soup = large_soup();
  const double late_ms = overshoot_ms(std::chrono::milliseconds(200),
                                      [&](const CancelToken& token) { build_bsp(soup, BspOptions{}, &token); });
  EXPECT_LT(late_ms, 1000.0);
}

TEST(Deadlines, BspBuildWithAnExpiredDeadlineStopsAtOnce) {
  const PolygonSoup& soup = large_soup();
  const double late_ms = overshoot_ms(std::chrono::milliseconds(0),
                                      [&](const CancelToken& token) { build_bsp(soup, BspOptions{}, &token); });
  EXPECT_LT(late_ms, 1000.0);
}

// Every pipeline either finishes a 640x480 frame of the soup or stops within a second of a short
// deadline: none runs on unchecked past it.
TEST(Deadlines, EveryPipelineEndsSoonAfterAShortDeadline) {
  const RenderRequest request = request_from_json(testing::example_request("studio", 640, 480));
  const PolygonSoup& soup = large_soup();
  for (const PipelineInfo& pipeline : pipeline_table()) {
    SCOPED_TRACE(pipeline.name);
    RenderOptions options = request.options;
    options.pipeline = pipeline_id(pipeline);
    CancelToken token;
    token.deadline = Clock::now() + std::chrono::milliseconds(50);
    RenderContext context;
    context.cancel = &token;
    try {
      render_frame(request.scene, soup, request.camera, options, context);
    } catch (const RenderCancelled&) {
    }
    const double late_ms = std::chrono::duration<double, std::milli>(Clock::now() - token.deadline).count();
    EXPECT_LT(late_ms, 1000.0);
  }
}

TEST(Deadlines, BspFrameStopsSoonAfterAShortDeadline) {
  const RenderRequest request = request_from_json(testing::example_request("studio", 320, 240));
  RenderOptions options = request.options;
  options.pipeline = pipeline_id("bsp");
  const double late_ms = overshoot_ms(std::chrono::milliseconds(300), [&](const CancelToken& token) {
    RenderContext context;
    context.cancel = &token;
    render_frame(request.scene, large_soup(), request.camera, options, context);
  });
  EXPECT_LT(late_ms, 1000.0);
}

}  // namespace
}  // namespace rr

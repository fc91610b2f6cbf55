// The table of pipelines and render_frame, which draws one frame (render.hpp wraps it into the one
// request path). Every pipeline shares the front end
// (request -> polygons in world space -> camera) and is one function in its own file plus one row in
// pipeline_table.cpp's table; validation, GET /v1/pipelines, the tests and the benchmarks iterate that
// table. A render is a pure function of (scene, polygons, camera, options): no mutable globals.
#pragma once

#include "render/core/frame.hpp"
#include "render/pipelines/pipeline_table.hpp"

#include <span>
#include <string>
#include <string_view>

namespace rr {

struct RenderResult {
  Frame frame;
  StageTimings timings;
  RenderStats stats;
};

// Draws one frame of an already tessellated scene (timings: shadow, build/sort/traverse, raster,
// shade, total). Throws RenderCancelled when context.cancel expires.
RenderResult render_frame(const Scene& scene, const PolygonSoup& soup, const Camera& camera,
                          const RenderOptions& options, const RenderContext& context = {});

}  // namespace rr

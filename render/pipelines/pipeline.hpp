// The table of pipelines and the single render entry point. Every pipeline shares the front end
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

// The whole path from request text to PNG bytes, timing every stage; throws InputError on bad input.
struct EncodedRender {
  RenderRequest request;
  RenderResult result;  // result.timings covers parse .. encode and total
  std::string png;
  std::string scene_id;
};
EncodedRender render_request_text(std::string_view request_json, const RenderContext& context = {});

// One JSON object of timings and counts, as printed by the CLI and returned by the service.
std::string timings_json(const StageTimings& timings, const RenderStats& stats);

}  // namespace rr

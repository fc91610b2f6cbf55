// The pipeline table and render_frame. Adding a pipeline is one row here plus its own
// file; everything that lists pipelines (validation, GET /v1/pipelines, tests, benchmarks) reads
// this table.
#include "render/pipelines/pipeline.hpp"

#include "render/pipelines/bsp.hpp"
#include "render/core/frustum.hpp"
#include "render/pipelines/painter.hpp"
#include "render/pipelines/reference.hpp"
#include "render/core/shadow.hpp"
#include "render/pipelines/shadow_cache.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/zbuffer.hpp"

#include <array>
#include <cassert>

namespace rr {

namespace {
constexpr std::array<PipelineInfo, 4> pipelines = {{
    {PipelineKind::zbuffer, "zbuffer",
     "Rasterization with a depth buffer (1/w, float); translucent polygons blended back to front.",
     draw_zbuffer},
    {PipelineKind::painter, "painter",
     "Painter's algorithm: polygons sorted back to front by view depth (painter.key mean, min or max), "
     "or ordered exactly by the Newell-Newell-Sancha tests with splitting (newell); no depth buffer.",
     draw_painter},
    {PipelineKind::bsp, "bsp",
     "A BSP tree of the static scene (built once, cached by scene id), walked back to front for the "
     "camera with frustum and back-face culling; no depth buffer.",
     draw_bsp},
    {PipelineKind::reference, "reference",
     "Exact reference: one double-precision ray per pixel centre through a BVH, per-pixel lighting "
     "with exact shadow rays; the ground truth the others are measured against (slow).",
     draw_reference, false},
}};
}  // namespace

std::span<const PipelineInfo> pipeline_table() { return pipelines; }

const PipelineInfo* find_pipeline(std::string_view name) {
  for (const PipelineInfo& p : pipelines) {
    if (name == p.name) return &p;
  }
  return nullptr;
}

const PipelineInfo& pipeline_info(PipelineKind kind) {
  for (const PipelineInfo& p : pipelines) {
    if (p.kind == kind) return p;
  }
  assert(false && "every PipelineKind has a row in the table");
  return pipelines[0];
}

RenderResult render_frame(const Scene& scene, const PolygonSoup& soup, const Camera& camera,
                          const RenderOptions& options, const RenderContext& context) {
  Stopwatch clock;
  RenderResult result;
  result.frame.image = Image(options.width, options.height, scene.background);
  result.frame.ids = IdBuffer(options.width, options.height);
  if (context.shadow_mask) result.frame.shadow_mask.assign(result.frame.ids.ids.size(), 0);
  result.stats.polygons = soup.polygons.size();
  ViewTransform view = make_view(camera, options.width, options.height);
  FrameInput input{scene, soup, view, options, context};
  if (context.shadow_mask) input.shadow_mask = result.frame.shadow_mask.data();
  const PipelineInfo& pipeline = pipeline_info(options.pipeline);
  check_cancel(context.cancel);
  // The shadow pass runs at most once, before any pipeline draws, and not at all when the shadow
  // cache holds this frame's maps; with no light or shadows off it does not run (shadow_ms stays 0).
  std::shared_ptr<const ShadowMaps> shadow_maps;
  if (options.shadows && !scene.lights.empty() && pipeline.shadow_maps) {
    Stopwatch shadow_clock;
    shadow_maps = obtain_shadow_maps(scene, soup, view, options, context, result.stats);
    result.timings.shadow_ms = shadow_clock.elapsed_ms();
    if (!shadow_maps->empty()) input.shadows = shadow_maps.get();
  }
  result.stats.shadow_skipped = input.shadows == nullptr;
  // Whole objects outside the frustum are skipped before any per-polygon work (timed as traverse).
  ObjectsInView objects;
  if (options.pipeline == PipelineKind::zbuffer || options.pipeline == PipelineKind::painter) {
    Stopwatch cull_clock;
    objects = objects_in_view(soup, view);
    input.objects_in_view = &objects.visible;
    result.stats.objects_culled = objects.culled;
    result.timings.traverse_ms += cull_clock.elapsed_ms();
  }
  input.lights_evaluated = &result.stats.lights_evaluated;
  pipeline.draw(input, result.frame, result.stats, result.timings);
  result.timings.total_ms = clock.elapsed_ms();
  return result;
}

}  // namespace rr

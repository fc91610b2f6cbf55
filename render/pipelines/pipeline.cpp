// The render entry point below render(): one frame of a tessellated scene through the pipeline its
// table row (pipeline_table.cpp) names.
#include "render/pipelines/pipeline.hpp"

#include "render/core/frustum.hpp"
#include "render/core/shadow.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/shadow_cache.hpp"

namespace rr {

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
  if (pipeline.culls_objects) {
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

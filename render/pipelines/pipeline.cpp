// The render entry points: one frame of a tessellated scene through the pipeline its table row
// (pipeline_table.cpp) names, and the whole path from request text to PNG bytes.
#include "render/pipelines/pipeline.hpp"

#include "render/core/frustum.hpp"
#include "render/scene_io/scene_json.hpp"
#include "render/core/png.hpp"
#include "render/core/shadow.hpp"
#include "render/pipelines/shadow_cache.hpp"
#include "render/core/timer.hpp"

#include <nlohmann/json.hpp>

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

EncodedRender render_request_text(std::string_view request_json, const RenderContext& context) {
  Stopwatch total, clock;
  EncodedRender out;
  out.request = parse_request(request_json);
  double parse_ms = clock.lap_ms();
  PolygonSoup soup = tessellate(out.request.scene.geometry);
  double tessellate_ms = clock.lap_ms();
  out.scene_id = scene_id(out.request.scene.geometry);
  RenderContext frame_context = context;
  if (frame_context.scene_id.empty()) frame_context.scene_id = out.scene_id;
  clock.lap_ms();  // the id is the cache key; hashing is not a render stage
  out.result = render_frame(out.request.scene, soup, out.request.camera, out.request.options, frame_context);
  clock.lap_ms();
  out.png = encode_png(out.result.frame.image, out.request.options.png_compression);
  StageTimings& t = out.result.timings;
  t.parse_ms = parse_ms;
  t.tessellate_ms = tessellate_ms;
  t.encode_ms = clock.lap_ms();
  t.total_ms = total.elapsed_ms();
  return out;
}

std::string timings_json(const StageTimings& t, const RenderStats& s) {
  auto ms = [](double v) { return std::round(v * 1000.0) / 1000.0; };  // microsecond resolution
  nlohmann::ordered_json j;
  j["timings_ms"] = {{"parse", ms(t.parse_ms)},   {"tessellate", ms(t.tessellate_ms)},
                     {"build", ms(t.build_ms)},   {"sort", ms(t.sort_ms)},
                     {"traverse", ms(t.traverse_ms)}, {"shadow", ms(t.shadow_ms)},
                     {"raster", ms(t.raster_ms)}, {"shade", ms(t.shade_ms)},
                     {"encode", ms(t.encode_ms)}, {"total", ms(t.total_ms)}};
  j["counts"] = {{"polygons", s.polygons},     {"polygons_culled", s.polygons_culled},
                 {"polygons_drawn", s.polygons_drawn}, {"triangles", s.triangles},
                 {"fragments", s.fragments}, {"lights_evaluated", s.lights_evaluated},
                 {"shadow_passes", s.shadow_passes}, {"objects_culled", s.objects_culled}};
  j["shadow"] = s.shadow_skipped ? "skipped" : "rendered";
  j["shadow_cache"] = s.shadow_cache;
  if (s.painter_pairs_tested || s.painter_splits || s.painter_budget_exhausted) {
    j["painter"] = {{"pairs_tested", s.painter_pairs_tested}, {"splits", s.painter_splits},
                    {"budget_exhausted", s.painter_budget_exhausted}};
  }
  if (!s.bsp_cache.empty()) {
    j["bsp"] = {{"cache", s.bsp_cache},        {"nodes", s.bsp_nodes},
                {"depth", s.bsp_depth},        {"input_polygons", s.bsp_input_polygons},
                {"fragments", s.bsp_fragments}, {"splits", s.bsp_splits},
                {"subtrees_occluded", s.bsp_subtrees_occluded}, {"polygons_occluded", s.bsp_polygons_occluded},
                {"screen_full", s.bsp_screen_full}};
  }
  return j.dump();
}

}  // namespace rr

// render() and prepare_scene() (see render.hpp): the frame from render_frame, the PNG from
// encode_png in the request's mode, and the request's stage timings gathered into one report.
#include "render/pipelines/render.hpp"

#include "render/core/png.hpp"
#include "render/core/scene_id.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/view_selection.hpp"

#include <algorithm>
#include <limits>

namespace rr {

PreparedScene prepare_scene(Scene scene) {
  PreparedScene out;
  out.scene = std::move(scene);
  Stopwatch clock;
  out.soup = tessellate(out.scene.geometry);
  bound_objects(out.soup);
  out.hierarchy = std::make_shared<const SceneHierarchy>(build_hierarchy(out.soup));
  out.cells = std::make_shared<const SceneCells>(build_cells(out.scene.geometry, out.soup, *out.hierarchy));
  out.shadow_bvh = std::make_shared<const ShadowBvh>(build_shadow_bvh(out.soup, *out.hierarchy));
  out.tessellate_ms = clock.elapsed_ms();
  out.static_id = scene_id(out.scene.geometry);
  out.warnings = placement_warnings(out.scene, out.soup);
  return out;
}

Camera view_camera(const Camera& camera, const RenderOptions& options, const PolygonSoup& soup) {
  if (!camera.frame_all) return camera;
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Vec3& p : soup.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (soup.positions.empty()) lo = hi = Vec3(0.0);
  return frame_bounds(camera, lo, hi, options.width, options.height);
}

RenderOutcome render(const RenderRequest& view, const PreparedScene& scene, const RenderContext& context) {
  Stopwatch clock;
  RenderContext frame_context = context;
  if (frame_context.scene_id.empty()) frame_context.scene_id = scene.static_id;
  if (scene.hierarchy) {
    frame_context.hierarchy = scene.hierarchy.get(), frame_context.hierarchy_soup = &scene.soup;
    frame_context.cells = scene.cells.get();
  }
  if (scene.shadow_bvh) frame_context.shadow_bvh = scene.shadow_bvh.get(), frame_context.shadow_bvh_soup = &scene.soup;
  const std::string static_id = frame_context.scene_id;
  // A view that leaves levels or ceilings out draws a copy without them, cached under its own keys.
  const Camera camera = view_camera(view.camera, view.options, scene.soup);
  const SoupSelection selection = select_objects(scene.scene.geometry, scene.soup, camera, view.options);
  PolygonSoup selected;
  if (!selection.everything) {
    selected = selected_soup(scene.soup, selection);
    frame_context.scene_id += selection.key_suffix;
  }
  const PolygonSoup& soup = selection.everything ? scene.soup : selected;
  RenderResult result = render_frame(scene.scene, soup, camera, view.options, frame_context);
  RenderOutcome out;
  out.camera = camera;
  out.frame = std::move(result.frame);
  RenderReport& report = out.report;
  report.stats = std::move(result.stats);
  report.timings = result.timings;
  if (context.encode) {
    check_cancel(context.cancel);
    Stopwatch encode_clock;
    out.png = encode_png(out.frame.image, view.options.png_compression, std::max(1u, context.threads));
    report.timings.encode_ms = encode_clock.elapsed_ms();
    // An encode that crossed the deadline is still late: the caller answers it as cancelled, never as
    // a success that arrived after the time it promised.
    check_cancel(context.cancel);
  }
  report.timings.queue_ms = context.queue_ms;
  report.timings.parse_ms = context.parse_ms;
  report.timings.tessellate_ms = context.tessellate_ms;
  report.timings.total_ms = context.before_ms + clock.elapsed_ms();
  report.scene_id = static_id;
  report.pipeline = view.options.pipeline;
  report.width = out.frame.image.width;
  report.height = out.frame.image.height;
  return out;
}

}  // namespace rr

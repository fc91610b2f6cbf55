// render() and prepare_scene() (see render.hpp): the frame from render_frame, the PNG from
// encode_png in the request's mode, and the request's stage timings gathered into one report.
#include "render/pipelines/render.hpp"

#include "render/core/png.hpp"
#include "render/core/scene_id.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/pipelines/view_selection.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

namespace rr {

namespace {

// `scene` with every light's and the ambient's intensity multiplied by `exposure`: shading is linear,
// so every pipeline and shading mode scales alike before to_byte clamps. The background is the
// clear colour the request chose, not a lit surface, and stays. Products stay finite floats.
Scene exposed_scene(const Scene& scene, double exposure) {
  auto scaled = [&](float intensity) { return float(std::min(double(intensity) * exposure, double(FLT_MAX))); };
  Scene out = scene;
  out.ambient.intensity = scaled(out.ambient.intensity);
  for (Light& light : out.lights) light.intensity = scaled(light.intensity);
  return out;
}

// Mean Rec. 709 luminance (0.2126 R + 0.7152 G + 0.0722 B of byte / 255) of the pixels that show a
// surface; nullopt when none does.
std::optional<double> mean_surface_luminance(const Frame& frame) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < frame.ids.ids.size(); ++i) {
    if (frame.ids.ids[i] == background_id) continue;
    const uint8_t* rgb = frame.image.rgb.data() + i * 3;
    sum += (0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]) / 255.0;
    ++count;
  }
  if (count == 0) return std::nullopt;
  return sum / double(count);
}

// The auto exposure rule (docs/lighting.md "Exposure"): draw the view at about 128 x 128 pixels
// (the same aspect, camera, pipeline and shading, no anti-aliasing, shadows by rays) at exposure e, starting from 1,
// and set e *= target / mean surface luminance, clamped to [min_auto_exposure, max_auto_exposure];
// repeat while the mean misses the target by more than 0.01, at most four passes. Clipped pixels
// make the mean grow less than e does, so later passes correct the first. A frame that shows no
// surface keeps 1. Deterministic: the pre-passes are renders, and renders are.
double choose_exposure(const RenderRequest& view, const Camera& camera, const PreparedScene& scene,
                       const RenderContext& context) {
  constexpr double pre_pass_pixels = 128.0 * 128.0;
  constexpr double tolerance = 0.01;
  RenderRequest small = view;
  small.camera = camera;
  small.camera.frame_all = false;
  const double s = std::min(1.0, std::sqrt(pre_pass_pixels / (double(view.options.width) * view.options.height)));
  small.options.width = std::max(1, int(std::lround(view.options.width * s)));
  small.options.height = std::max(1, int(std::lround(view.options.height * s)));
  small.options.antialias = 1;
  small.options.auto_exposure = false;
  // Shadows by rays, which the maps approximate: a map pass costs the same at any image size (seconds
  // for a furnished home), rays cost per pixel.
  small.options.shadow.method = ShadowMethod::rays;
  RenderContext pre = context;
  pre.encode = false;
  double exposure = 1.0;
  for (int pass = 0; pass < 4; ++pass) {
    small.options.exposure = exposure;
    const std::optional<double> mean = mean_surface_luminance(render(small, scene, pre).frame);
    if (!mean) return 1.0;
    if (std::abs(*mean - auto_exposure_target) <= tolerance) break;
    const double next = *mean > 0.0 ? exposure * auto_exposure_target / *mean : max_auto_exposure;
    const double clamped = std::clamp(next, min_auto_exposure, max_auto_exposure);
    if (clamped == exposure) break;
    exposure = clamped;
  }
  return exposure;
}

}  // namespace

PreparedScene prepare_scene(Scene scene, unsigned threads, PrepareLamps lamps) {
  PreparedScene out;
  out.scene = std::move(scene);
  Stopwatch clock;
  out.soup = tessellate(out.scene.geometry);
  bound_objects(out.soup);
  out.hierarchy = std::make_shared<const SceneHierarchy>(build_hierarchy(out.soup));
  out.cells = std::make_shared<const SceneCells>(build_cells(out.scene.geometry, out.soup, *out.hierarchy));
  out.shadow_bvh = std::make_shared<const ShadowBvh>(build_shadow_bvh(out.soup, *out.hierarchy));
  if (lamps == PrepareLamps::yes)
    out.lamps = std::make_shared<const PreparedLamps>(prepare_lamps(out.soup, *out.cells, out.scene.lights, threads));
  out.tessellate_ms = clock.elapsed_ms();
  out.static_id = scene_id(out.scene.geometry);
  out.warnings = placement_warnings(out.scene, out.soup);
  return out;
}

PrepareLamps lamps_for(const RenderOptions& options) {
  const bool rays = options.shadows && (options.shadow.method == ShadowMethod::rays || options.auto_exposure);
  return rays ? PrepareLamps::yes : PrepareLamps::no;
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
  if (scene.lamps) frame_context.lamps = scene.lamps.get(), frame_context.lamps_soup = &scene.soup;
  const std::string static_id = frame_context.scene_id;
  // A view that leaves levels or ceilings out draws a copy without them, cached under its own keys.
  const Camera camera = view_camera(view.camera, view.options, scene.soup);
  const SoupSelection selection = select_objects(scene.scene.geometry, scene.soup, camera, view.options);
  std::shared_ptr<const SelectedView> selected;
  double tree_ms = 0.0;  // the selection's shadow-ray tree, when this frame built it
  if (!selection.everything) {
    frame_context.scene_id += selection.key_suffix;
    const RenderOptions& o = view.options;
    ViewTree tree = ViewTree::none;
    if (o.shadows && !scene.scene.lights.empty() && pipeline_info(o.pipeline).shadow_maps)
      tree = o.shadow.method == ShadowMethod::rays ? ViewTree::always : ViewTree::with_panes;
    selected =
        selected_view(scene.soup, selection, frame_context.scene_id, tree, context.view_cache, context.cancel, tree_ms);
    if (selected->shadow_bvh)
      frame_context.shadow_bvh = selected->shadow_bvh.get(), frame_context.shadow_bvh_soup = selected->soup.get();
  }
  const PolygonSoup& soup = selected ? *selected->soup : scene.soup;
  // Exposure scales the lights once here; at exactly 1 the scene is drawn as it is, byte for byte.
  const double exposure =
      view.options.auto_exposure ? choose_exposure(view, camera, scene, context) : view.options.exposure;
  Scene exposed;
  if (exposure != 1.0) exposed = exposed_scene(scene.scene, exposure);
  RenderResult result =
      render_frame(exposure != 1.0 ? exposed : scene.scene, soup, camera, view.options, frame_context);
  result.timings.shadow_ms += tree_ms;
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
  report.exposure = exposure;
  return out;
}

}  // namespace rr

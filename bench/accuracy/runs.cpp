// The accuracy benchmark's configurations and timed renders (runs.hpp).
#include "bench/accuracy/runs.hpp"

#include "cli/bench_render.hpp"  // median_of
#include "render/core/timer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace rr::bench {

namespace {

using nlohmann::ordered_json;

std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

BenchConfig bsp_config(double w1, double w2, double w3, double epsilon) {
  BenchConfig c{"", "visibility", {}, {}};
  c.options.pipeline = pipeline_id("bsp");
  c.options.bsp.w1 = w1, c.options.bsp.w2 = w2, c.options.bsp.w3 = w3, c.options.bsp.epsilon = epsilon;
  c.label =
      "bsp w=" + short_number(w1) + "/" + short_number(w2) + "/" + short_number(w3) + " eps=" + short_number(epsilon);
  c.options_json = {{"pipeline", "bsp"}, {"bsp", {{"w1", w1}, {"w2", w2}, {"w3", w3}, {"epsilon", epsilon}}}};
  return c;
}

BenchConfig shading_config(ShadingMode mode, const char* name, int shadow_size, int pcf) {
  BenchConfig c{name, "shading", {}, {{"pipeline", "zbuffer"}, {"shading", name}}};
  c.options.shading = mode;
  if (shadow_size > 0) {
    c.options.shadows = true;
    c.options.shadow.size = shadow_size;
    c.options.shadow.pcf = pcf;
    c.label += " shadows " + std::to_string(shadow_size) + " pcf" + std::to_string(pcf);
    c.options_json["shadows"] = true;
    c.options_json["shadow"] = {{"size", shadow_size}, {"pcf", pcf}};
  }
  return c;
}

// Phong with exact shadow rays instead of maps: away from the reference's shadow edges its lit/unlit
// decisions are the reference's own, so its shadow disagreement there must be 0.
BenchConfig rays_config() {
  BenchConfig c = shading_config(ShadingMode::phong, "phong", 0, 1);
  c.options.shadows = true;
  c.options.shadow.method = ShadowMethod::rays;
  c.label += " shadows rays";
  c.options_json["shadows"] = true;
  c.options_json["shadow"] = {{"method", "rays"}};
  return c;
}

}  // namespace

std::vector<BenchConfig> make_configs(const BenchScene& scene) {
  if (scene.scene_class == "textures") {
    std::vector<BenchConfig> configs;
    const std::pair<TextureFilter, const char*> filters[] = {{TextureFilter::nearest, "nearest"},
                                                             {TextureFilter::bilinear, "bilinear"},
                                                             {TextureFilter::trilinear, "trilinear"},
                                                             {TextureFilter::anisotropic, "anisotropic"}};
    for (const auto& [filter, name] : filters) {
      BenchConfig c = shading_config(ShadingMode::phong, "phong", 0, 1);
      c.label = std::string("texture ") + name;
      c.group = "texture";
      c.options.texture_filter = filter;
      c.options_json["texture_filter"] = name;
      configs.push_back(c);
    }
    return configs;
  }
  const bool large = is_large(scene), few_shadow_settings = has_few_shadow_settings(scene);
  std::vector<BenchConfig> configs;
  configs.push_back({"zbuffer", "visibility", {}, {{"pipeline", "zbuffer"}}});
  const std::pair<PainterKey, const char*> keys[] = {
      {PainterKey::mean, "mean"}, {PainterKey::min, "min"}, {PainterKey::max, "max"}, {PainterKey::newell, "newell"}};
  for (const auto& [key, name] : keys) {
    BenchConfig c{
        std::string("painter-") + name, "visibility", {}, {{"pipeline", "painter"}, {"painter", {{"key", name}}}}};
    c.options.pipeline = pipeline_id("painter");
    c.options.painter_key = key;
    configs.push_back(c);
  }
  // BSP: the default weights and band, a wide band, balance only, fewest splits only, a narrow band.
  configs.push_back(bsp_config(1, 4, -1, 1e-7));
  configs.push_back(bsp_config(1, 4, -1, 1e-4));
  if (!large) {
    configs.push_back(bsp_config(1, 0, 0, 1e-7));
    configs.push_back(bsp_config(0, 1, 0, 1e-7));
    configs.push_back(bsp_config(1, 4, -1, 1e-10));
  }
  // Shading on the zbuffer pipeline ("zbuffer" above is flat without shadows), then shadow maps.
  configs.push_back(shading_config(ShadingMode::gouraud, "gouraud", 0, 1));
  configs.push_back(shading_config(ShadingMode::phong, "phong", 0, 1));
  if (!few_shadow_settings) {
    configs.push_back(shading_config(ShadingMode::flat, "flat", 2048, 1));
    configs.push_back(shading_config(ShadingMode::gouraud, "gouraud", 2048, 1));
  }
  configs.push_back(shading_config(ShadingMode::phong, "phong", 2048, 1));
  configs.push_back(shading_config(ShadingMode::phong, "phong", 512, 1));
  if (!few_shadow_settings) {
    configs.push_back(shading_config(ShadingMode::phong, "phong", 1024, 1));
    configs.push_back(shading_config(ShadingMode::phong, "phong", 4096, 1));
    configs.push_back(shading_config(ShadingMode::phong, "phong", 2048, 5));
  }
  configs.push_back(shading_config(ShadingMode::phong, "phong", 2048, 3));
  configs.push_back(rays_config());
  return configs;
}

TimedRender time_render(const BenchScene& scene, const std::string& scene_id, const RenderOptions& options,
                        int max_frames, double timeout_s) {
  TimedRender out;
  CancelToken cancel;
  cancel.deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                           std::chrono::duration<double>(timeout_s));
  BspCache bsp_cache(size_t{2} << 30);
  RenderContext context{&bsp_cache, &cancel, scene_id};
  RenderRequest view = scene.request;
  view.options = options;
  context.encode = false;  // frames are measured up to the image, as bench-render's
  auto frame_of = [&] {
    RenderOutcome outcome = render(view, scene.prepared, context);
    return RenderResult{std::move(outcome.frame), outcome.report.timings, std::move(outcome.report.stats)};
  };
  std::vector<double> frame_ms;
  std::vector<StageTimings> stages;
  try {
    // The warm-up frame builds (and caches) the BSP tree, pages in the buffers and is the frame the
    // error measures use: only it fills the per-pixel shadow mask, which the timed frames skip.
    context.shadow_mask = true;
    out.last = frame_of();
    out.build_ms = out.last.timings.build_ms;
    context.shadow_mask = false;
    for (int i = 0; i < max_frames; ++i) {
      Stopwatch clock;
      const RenderResult frame = frame_of();
      frame_ms.push_back(clock.elapsed_ms());
      stages.push_back(frame.timings);
      const double first = frame_ms.front();
      if (first > 1000.0 || (first > 250.0 && frame_ms.size() >= 3)) break;
    }
  } catch (const RenderCancelled&) {
    out.status = "timeout";
    return out;
  }
  auto median_stage = [&](double StageTimings::*field) {
    std::vector<double> v;
    for (const StageTimings& t : stages) v.push_back(t.*field);
    return std::round(cli::median_of(v) * 1000.0) / 1000.0;
  };
  out.frames = int(frame_ms.size());
  out.frame_ms_median = std::round(cli::median_of(frame_ms) * 1000.0) / 1000.0;
  out.stage_ms_median = {
      {"sort", median_stage(&StageTimings::sort_ms)},     {"traverse", median_stage(&StageTimings::traverse_ms)},
      {"shadow", median_stage(&StageTimings::shadow_ms)}, {"raster", median_stage(&StageTimings::raster_ms)},
      {"shade", median_stage(&StageTimings::shade_ms)},   {"total", median_stage(&StageTimings::total_ms)}};
  return out;
}

}  // namespace rr::bench

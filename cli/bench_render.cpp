// bench-render's frame loop and report (see bench_render.hpp).
#include "cli/bench_render.hpp"

#include "render/core/timer.hpp"
#include "render/scene_io/report_json.hpp"

#include <algorithm>
#include <cmath>

namespace rr::cli {

BenchReport bench_frames(const RenderRequest& request, const PreparedScene& scene, const BenchRun& run) {
  BenchReport report;
  // The cache lives for this run only; with run.bsp_cache the warm-up frames fill it as the first
  // request for a scene fills the service's.
  BspCache bsp_cache(size_t{1} << 30);
  ShadowCache shadow_cache(size_t{1} << 30);
  RenderContext context;
  context.threads = run.threads;
  context.encode = false;  // frames are measured up to the image; encoding is bench/png.cpp's
  if (run.bsp_cache) context.bsp_cache = &bsp_cache;
  if (run.shadow_cache && request.options.shadows) context.shadow_cache = &shadow_cache;
  for (int i = 0; i < run.warmup; ++i) render(request, scene, context);
  for (int i = 0; i < run.frames; ++i) {
    Stopwatch clock;
    RenderOutcome result = render(request, scene, context);
    report.frame_ms.push_back(clock.elapsed_ms());
    report.stages.push_back(result.report.timings);
    if (i + 1 == run.frames) report.last = std::move(result);
  }
  return report;
}

double median_of(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

nlohmann::ordered_json bench_report_json(const BenchReport& report, const BenchRun& run) {
  auto ms = [](double v) { return std::round(v * 1000.0) / 1000.0; };  // microsecond resolution
  auto stage_median = [&](auto&& stage_of_frame) {
    std::vector<double> values;
    for (const StageTimings& t : report.stages) values.push_back(stage_of_frame(t));
    return ms(median_of(values));
  };
  auto field = [](double StageTimings::*member) { return [member](const StageTimings& t) { return t.*member; }; };
  // What render_frame spends outside every stage (allocating and clearing the frame's buffers),
  // per frame: medians of different stages do not add up, so the difference is taken first.
  auto other = [](const StageTimings& t) {
    return t.total_ms - (t.shadow_ms + t.build_ms + t.sort_ms + t.traverse_ms + t.raster_ms + t.shade_ms);
  };
  nlohmann::ordered_json j;
  j["frames"] = run.frames;
  j["warmup"] = run.warmup;
  j["bsp_cache"] = run.bsp_cache;
  j["threads"] = run.threads;
  j["shadow_cache"] = run.shadow_cache;
  j["frame_ms_min"] = ms(*std::min_element(report.frame_ms.begin(), report.frame_ms.end()));
  j["frame_ms_median"] = ms(median_of(report.frame_ms));
  j["frame_ms_max"] = ms(*std::max_element(report.frame_ms.begin(), report.frame_ms.end()));
  j["stage_ms_median"] = {{"shadow", stage_median(field(&StageTimings::shadow_ms))},
                          {"build", stage_median(field(&StageTimings::build_ms))},
                          {"sort", stage_median(field(&StageTimings::sort_ms))},
                          {"traverse", stage_median(field(&StageTimings::traverse_ms))},
                          {"raster", stage_median(field(&StageTimings::raster_ms))},
                          {"shade", stage_median(field(&StageTimings::shade_ms))},
                          {"other", stage_median(other)},
                          {"total", stage_median(field(&StageTimings::total_ms))}};
  // The last frame's counts, in the service's own format (report_json is the one writer of it).
  const nlohmann::ordered_json last = report_json(report.last.report);
  for (const char* key : {"counts", "shadow", "painter", "bsp"}) {
    if (last.contains(key)) j[key] = last[key];
  }
  return j;
}

size_t fan_triangle_count(const PolygonSoup& soup) {
  size_t triangles = 0;
  for (const Polygon& p : soup.polygons) triangles += p.vertex_count - 2;
  return triangles;
}

}  // namespace rr::cli

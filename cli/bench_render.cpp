// bench-render: the command (its own flags; the request flags are request_flags.hpp's, as render's
// are), the frame loop and the report (see bench_render.hpp and cli.hpp).
#include "cli/bench_render.hpp"

#include "cli/args.hpp"
#include "cli/cli.hpp"
#include "cli/request_flags.hpp"
#include "render/core/kernels.hpp"
#include "render/core/png.hpp"
#include "render/core/scene_names.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/view_selection.hpp"
#include "render/scene_io/report_json.hpp"
#include "render/scene_io/scene_json.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace rr::cli {

BenchReport bench_frames(const RenderRequest& request, const PreparedScene& scene, const BenchRun& run) {
  BenchReport report;
  // The caches live for this run only; with run.bsp_cache the warm-up frames fill it as the first
  // request for a scene fills the service's, and they fill the views' cache (a view that leaves levels
  // or ceilings out) as they do the service's.
  BspCache bsp_cache(size_t{1} << 30);
  ShadowCache shadow_cache(size_t{1} << 30);
  ViewCache view_cache(size_t{1} << 30);
  RenderContext context;
  context.view_cache = &view_cache;
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
    return t.total_ms - (t.shadow_ms + t.build_ms + t.cull_ms + t.sort_ms + t.traverse_ms + t.raster_ms + t.shade_ms);
  };
  nlohmann::ordered_json j;
  j["frames"] = run.frames;
  j["warmup"] = run.warmup;
  j["bsp_cache"] = run.bsp_cache;
  j["threads"] = run.threads;
  j["simd"] = kernels().name;  // the per-pixel loops' level (ROOMRENDER_SIMD can force a lower one)
  j["shadow_cache"] = run.shadow_cache;
  j["frame_ms_min"] = ms(*std::min_element(report.frame_ms.begin(), report.frame_ms.end()));
  j["frame_ms_median"] = ms(median_of(report.frame_ms));
  j["frame_ms_max"] = ms(*std::max_element(report.frame_ms.begin(), report.frame_ms.end()));
  j["stage_ms_median"] = {{"shadow", stage_median(field(&StageTimings::shadow_ms))},
                          {"build", stage_median(field(&StageTimings::build_ms))},
                          {"cull", stage_median(field(&StageTimings::cull_ms))},
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

namespace {

// What bench-render can be asked for on this build: the benchmark script iterates these.
void print_bench_modes() {
  nlohmann::ordered_json pipelines = nlohmann::ordered_json::array(), shadings = nlohmann::ordered_json::array();
  for (const PipelineInfo& p : pipeline_table()) pipelines.push_back(p.name);
  for (const auto& s : shading_names) shadings.push_back(s.name);
  print_json_line(stdout, {{"pipelines", pipelines}, {"shadings", shadings}});
}

// bench-render's own flags (everything but the request flags) into `run`; throws UsageError.
BenchRun bench_run(const ParsedArgs& args) {
  BenchRun run;
  if (auto v = flag(args, "--frames")) run.frames = parse_int(*v, "--frames", 1, 100000);
  if (auto v = flag(args, "--warmup")) run.warmup = parse_int(*v, "--warmup", 0, 100000);
  run.threads = std::max(1u, std::thread::hardware_concurrency());
  if (auto v = flag(args, "--threads")) run.threads = unsigned(parse_int(*v, "--threads", 1, 64));
  if (auto v = flag(args, "--bsp-cache")) run.bsp_cache = parse_switch_flag(*v, "--bsp-cache", "on", "off");
  if (auto v = flag(args, "--shadow-cache")) run.shadow_cache = parse_switch_flag(*v, "--shadow-cache", "on", "off");
  return run;
}

}  // namespace

int run_bench_render(std::span<const std::string> argv) {
  if (std::find(argv.begin(), argv.end(), "--list") != argv.end()) return print_bench_modes(), 0;
  ParsedArgs args;
  BenchRun run;
  RequestPatch patch;
  try {
    args = parse_args(argv, with_request_flags({"--request", "--obj", "--scale", "--bsp-cache", "--shadow-cache",
                                                "--frames", "--warmup", "--out", "--ids", "--threads"}));
    if (args.help) return std::printf("usage: %s\n\n%s", bench_synopsis, request_flags_help().c_str()), 0;
    if (!args.positional.empty()) throw UsageError("unexpected argument " + args.positional[0]);
    if (flag(args, "--request").has_value() == flag(args, "--obj").has_value()) {
      throw UsageError("give exactly one of --request FILE and --obj FILE");
    }
    if (flag(args, "--scale") && !flag(args, "--obj")) throw UsageError("--scale goes with --obj");
    if (auto scale = flag(args, "--scale")) parse_scale(*scale);
    check_one_stdout(args, {"--out", "--ids"});
    run = bench_run(args);
    patch = request_patch(args);
  } catch (const UsageError& e) {
    return usage_failure(bench_synopsis, e.what());
  }
  return run_reporting_errors(
      [&] {
        // --obj goes through the OBJ importer (groups become mesh solids in file order), so polygon id k
        // is the k-th `f` line when groups do not interleave and no face needed repair (docs/import.md).
        const bool from_obj = flag(args, "--obj").has_value();
        std::string input = from_obj ? *flag(args, "--obj") : *flag(args, "--request");
        std::string text =
            from_obj ? imported_request_text(input, ImportFormat::obj, import_options(args, patch)) : read_input(input);
        RenderRequest request = request_from_json(apply_request_patch(parse_json_text(text), patch), request_limits());
        const PreparedScene scene = prepare_scene(std::move(request.scene));
        BenchReport report = bench_frames(request, scene, run);
        if (auto out = flag(args, "--out")) {
          write_output(*out, encode_png(report.last.frame.image, request.options.png_compression, run.threads));
        }
        if (auto ids = flag(args, "--ids")) write_output(*ids, encode_id_buffer(report.last.frame.ids));
        nlohmann::ordered_json line = {{"source", from_obj ? "obj" : "request"},
                                       {"input", input},
                                       {"pipeline", pipeline_info(request.options.pipeline).name},
                                       {"shading", shading_names.name(request.options.shading)},
                                       {"shadows", request.options.shadows},
                                       {"width", request.options.width},
                                       {"height", request.options.height},
                                       {"polygons", scene.soup.polygons.size()},
                                       {"triangles", fan_triangle_count(scene.soup)},
                                       {"setup_ms", std::round(scene.tessellate_ms * 1000.0) / 1000.0}};
        line.update(bench_report_json(report, run));
        print_json_line(line_stream(args, {"--out", "--ids"}), line);
      },
      patch.flag_by_pointer);
}

}  // namespace rr::cli

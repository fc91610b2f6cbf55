// The measuring core of `roomrender bench-render`: renders one prepared scene K times (after
// untimed warm-up frames) through render(), as the service does but without encoding, and reports the wall-clock frame
// time (min / median / max) and the median of every stage in StageTimings. Parsing and tessellation are not frame work:
// the caller times its own setup. Output is one JSON object (cli.cpp prints it).
#pragma once

#include "render/pipelines/render.hpp"

#include <nlohmann/json.hpp>

#include <vector>

namespace rr::cli {

inline constexpr const char* bench_synopsis =
    "roomrender bench-render (--request FILE | --obj FILE) [REQUEST FLAGS] [--bsp-cache on|off]\n"
    "                 [--shadow-cache on|off] [--frames K] [--warmup N] [--threads N] [--out FILE.png|-]\n"
    "                 [--ids FILE|-]   (a file of - is stdout; the JSON line then goes to stderr)\n"
    "  roomrender bench-render --list";

struct BenchRun {
  int frames = 10;  // timed frames, >= 1
  int warmup = 1;   // untimed frames first: page faults of the first framebuffers, cold caches
  // false: no BSP cache, so every frame builds its tree (frame time includes "build"); true: a
  // cache as the service keeps, filled by the warm-up frames, so timed frames measure a cache hit.
  bool bsp_cache = false;
  unsigned threads = 1;  // RenderContext::threads
  // true: a shadow cache as the service keeps, so the first frame (a warm-up one) runs the shadow
  // pass and the timed frames reuse its maps (shadow ~0 ms); false: every frame runs the pass, as a
  // renderer without a cache (the llvmpipe peer) does.
  bool shadow_cache = true;
};

struct BenchReport {
  std::vector<double> frame_ms;      // wall-clock of each timed render() call
  std::vector<StageTimings> stages;  // each timed frame's own stage timings
  RenderOutcome last;                // the last frame (no PNG), for --out and --ids
};

BenchReport bench_frames(const RenderRequest& request, const PreparedScene& scene, const BenchRun& run);

// Median of a non-empty list; the mean of the middle two for an even count (the peer harness,
// bench/peer/osmesa_bench.cpp, uses the same definition).
double median_of(std::vector<double> values);

// {"frames", "warmup", "frame_ms_min", "frame_ms_median", "frame_ms_max", "stage_ms_median": {every
//  StageTimings stage of the frame, "other" (total less the stages, per frame), "total"},
//  "counts", "shadow" (and "painter" / "bsp" when present): the last frame's counts}.
nlohmann::ordered_json bench_report_json(const BenchReport& report, const BenchRun& run);

// Triangles the rasterizer sees when every polygon is drawn as a fan: the sum of (vertices - 2).
size_t fan_triangle_count(const PolygonSoup& soup);

}  // namespace rr::cli

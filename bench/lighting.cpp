// Lighting benchmark (scripts/bench.sh lighting): examples/apartment.json at 1280x720 with the
// zbuffer pipeline, for flat / gouraud / phong x shadows off / on (default 2048^2 map, pcf 1): the
// median over --frames frames of every stage of the whole request path (parse, tessellate, shadow,
// raster, shade, encode, total). Per-pixel shading runs inside the rasterizer's loop, so Phong's
// cost shows in `raster`; `shade` is the per-polygon preparation. Writes JSON to --out.
#include "bench/bench_io.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using json = nlohmann::ordered_json;
using rr::bench::read_text;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return 0.0;
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

// One request as `roomrender render` takes it: parse, prepare_scene, render() (total: parse -> encode).
rr::RenderOutcome render_text(const std::string& text) {
  rr::Stopwatch total, parse_clock;
  rr::RenderRequest request = rr::parse_request(text);
  rr::RenderContext context;
  context.parse_ms = parse_clock.elapsed_ms();
  const rr::PreparedScene scene = rr::prepare_scene(std::move(request.scene));
  context.tessellate_ms = scene.tessellate_ms;
  context.before_ms = total.elapsed_ms();
  return rr::render(request, scene, context);
}

struct Stage {
  const char* name;
  double rr::StageTimings::*field;
};
constexpr Stage stages[] = {{"parse", &rr::StageTimings::parse_ms},   {"tessellate", &rr::StageTimings::tessellate_ms},
                            {"shadow", &rr::StageTimings::shadow_ms}, {"raster", &rr::StageTimings::raster_ms},
                            {"shade", &rr::StageTimings::shade_ms},   {"encode", &rr::StageTimings::encode_ms},
                            {"total", &rr::StageTimings::total_ms}};

}  // namespace

int main(int argc, char** argv) {
  std::string out_path;
  int frames = 21;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) {
      frames = std::max(1, std::atoi(argv[++i]));
    } else {
      std::cerr << "usage: bench_lighting [--out FILE] [--frames N]\n";
      return 2;
    }
  }
  nlohmann::json request =
      nlohmann::json::parse(read_text(std::string(ROOMRENDER_SOURCE_DIR) + "/examples/apartment.json"));
  request["options"]["width"] = 1280;
  request["options"]["height"] = 720;
  request["options"]["pipeline"] = "zbuffer";
  json results = json::array();
  std::printf("%-8s %-8s", "shading", "shadows");
  for (const Stage& s : stages) std::printf(" %10s", s.name);
  std::printf("   (median ms of %d frames)\n", frames);
  for (const char* shading : {"flat", "gouraud", "phong"}) {
    for (bool shadows : {false, true}) {
      request["options"]["shading"] = shading;
      request["options"]["shadows"] = shadows;
      const std::string text = request.dump();
      render_text(text);  // warm-up: page in the code and the allocator
      std::vector<std::vector<double>> times(std::size(stages));
      rr::RenderStats stats;
      for (int f = 0; f < frames; ++f) {
        const rr::RenderOutcome r = render_text(text);
        for (size_t s = 0; s < std::size(stages); ++s) times[s].push_back(r.report.timings.*stages[s].field);
        stats = r.report.stats;
      }
      json medians = json::object();
      std::printf("%-8s %-8s", shading, shadows ? "on" : "off");
      for (size_t s = 0; s < std::size(stages); ++s) {
        const double m = median(times[s]);
        medians[stages[s].name] = round3(m);
        std::printf(" %10.3f", m);
      }
      std::printf("\n");
      results.push_back({{"shading", shading},
                         {"shadows", shadows},
                         {"median_ms", medians},
                         {"shadow", stats.shadow_skipped ? "skipped" : "rendered"},
                         {"lights_evaluated", stats.lights_evaluated},
                         {"fragments", stats.fragments}});
    }
  }
  json doc = {{"benchmark", "lighting"}, {"scene", "examples/apartment.json"},
              {"pipeline", "zbuffer"},   {"width", 1280},
              {"height", 720},           {"shadow_map", {{"size", 2048}, {"pcf", 1}}},
              {"frames", frames},        {"results", results}};
  if (!out_path.empty()) {
    std::ofstream out(out_path);
    out << doc.dump(2) << "\n";
    if (!out) {
      std::cerr << "cannot write " << out_path << "\n";
      return 1;
    }
  }
  return 0;
}

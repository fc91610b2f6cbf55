// Painter benchmark (scripts/bench.sh painter): on examples/four_cylinders.json (4 open tubes of 60
// quads, 640x480), the median over --frames frames of the painter's sort time (culling + keys + sort,
// + the Newell tests for `newell`) and draw time (raster + shade) for every key; `newell` on the two
// classic scenes that need splits; then the sort time of generated scenes of about 10^3, 10^4 and
// 10^5 polygons (a square grid of the same tubes, seen the same way). Writes JSON to --out. The
// classic reference: 12 ms for the painter's sort of the 240 quads.
#include "render/pipelines/painter.hpp"
#include "bench/bench_io.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using json = nlohmann::ordered_json;
using rr::bench::read_text;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return 0.0;
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

constexpr rr::PainterKey keys[] = {rr::PainterKey::mean, rr::PainterKey::min, rr::PainterKey::max,
                                   rr::PainterKey::newell};
constexpr const char* key_names[] = {"mean", "min", "max", "newell"};

// A side x side grid of four_cylinders' tubes (radius 0.5, height 1.5, 60 quads, 1.6 m apart), the
// camera placed as in the example, scaled to the grid's extent.
nlohmann::json tube_grid(int side) {
  nlohmann::json solids = nlohmann::json::array();
  const char* colors[4] = {"#e05050", "#50c060", "#5080e0", "#e0c040"};
  const double half = 0.8 * (side - 1);
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      solids.push_back({{"type", "cylinder"},
                        {"color", colors[(i + 2 * j) % 4]},
                        {"center", {-half + 1.6 * i, -half + 1.6 * j}},
                        {"radius", 0.5},
                        {"height", 1.5},
                        {"segments", 60},
                        {"caps", false}});
    }
  }
  const double s = (half + 0.5) / 1.3;  // four_cylinders: tubes within +-1.3 m
  return {{"scene",
           {{"background", "#202428"},
            {"solids", solids},
            {"lights", {{{"type", "directional"}, {"direction", {-0.6, -1.0, -0.4}}, {"intensity", 0.8}}}}}},
          {"camera", {{"position", {3.1 * s, 0.6 + 2.0 * s, 3.9 * s}}, {"target", {0.0, 0.6, 0.0}}, {"far", 1000.0}}},
          {"options", {{"width", 640}, {"height", 480}, {"pipeline", "painter"}}}};
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path;
  int frames = 50;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    else if (a == "--frames" && i + 1 < argc) frames = std::max(1, std::atoi(argv[++i]));
    else {
      std::cerr << "usage: bench_painter --out FILE [--frames N]\n";
      return 2;
    }
  }
  if (out_path.empty()) {
    std::cerr << "usage: bench_painter --out FILE [--frames N]\n";
    return 2;
  }

  json result;
  result["benchmark"] = "painter";
  result["machine"] = {
    {"hardware_threads", std::thread::hardware_concurrency()},
#if defined(__clang__)
    {"compiler", __VERSION__},
#elif defined(__GNUC__)
    {"compiler", "g++ " __VERSION__},
#endif
    {"build", "Release, single thread"}
  };
  {
    std::ifstream load("/proc/loadavg");  // other work on the machine inflates the larger sizes' times
    std::string one;
    if (load >> one) result["machine"]["load_average_1min_at_start"] = std::stod(one);
  }
  result["reference"] = {{"classic_painter_sort_ms_240_quads", 12.0}};

  // The example: sort and draw per key, from the pipeline's own stage timings.
  rr::RenderRequest request =
      rr::parse_request(read_text(std::string(ROOMRENDER_SOURCE_DIR) + "/examples/four_cylinders.json"));
  const rr::PreparedScene scene = rr::prepare_scene(request.scene);
  const rr::PolygonSoup& soup = scene.soup;
  rr::RenderContext no_png;
  no_png.encode = false;  // frames up to the image, as bench-render measures them
  request.options.pipeline = rr::pipeline_id("painter");
  json example = {{"scene", "examples/four_cylinders.json"},
                  {"polygons", soup.polygons.size()},
                  {"width", request.options.width},
                  {"height", request.options.height},
                  {"frames", frames}};
  json per_key = json::object();
  std::printf("four_cylinders (%zu polygons, %dx%d), median of %d frames:\n", soup.polygons.size(),
              request.options.width, request.options.height, frames);
  for (size_t k = 0; k < std::size(keys); ++k) {
    request.options.painter_key = keys[k];
    std::vector<double> sort, raster, shade, draw, total;
    rr::RenderStats stats;
    for (int f = 0; f < frames + 2; ++f) {
      const rr::RenderReport r = rr::render(request, scene, no_png).report;
      if (f < 2) continue;  // warm-up
      sort.push_back(r.timings.sort_ms);
      raster.push_back(r.timings.raster_ms);
      shade.push_back(r.timings.shade_ms);
      draw.push_back(r.timings.raster_ms + r.timings.shade_ms);
      total.push_back(r.timings.total_ms);
      stats = r.stats;
    }
    per_key[key_names[k]] = {{"sort_ms", round3(median(sort))},        {"draw_ms", round3(median(draw))},
                             {"raster_ms", round3(median(raster))},    {"shade_ms", round3(median(shade))},
                             {"total_ms", round3(median(total))},      {"polygons_culled", stats.polygons_culled},
                             {"polygons_drawn", stats.polygons_drawn}, {"pairs_tested", stats.painter_pairs_tested},
                             {"splits", stats.painter_splits}};
    std::printf("  %-6s sort %8.3f ms  draw %8.3f ms  (drawn %zu, pairs tested %zu, splits %zu)\n", key_names[k],
                median(sort), median(draw), stats.polygons_drawn, stats.painter_pairs_tested, stats.painter_splits);
  }
  example["keys"] = per_key;
  result["four_cylinders"] = example;

  // Newell where splits are needed: the classic failure scenes.
  json classic = json::object();
  std::printf("newell on scenes that need splits (median of %d frames):\n", frames);
  for (const char* name : {"tri_intersecting", "cubes_45_pyramid_cylinder"}) {
    rr::RenderRequest c =
        rr::parse_request(read_text(std::string(ROOMRENDER_SOURCE_DIR) + "/examples/" + name + ".json"));
    const rr::PreparedScene cscene = rr::prepare_scene(c.scene);
    const rr::PolygonSoup& csoup = cscene.soup;
    c.options.pipeline = rr::pipeline_id("painter");
    c.options.painter_key = rr::PainterKey::newell;
    std::vector<double> sort, draw;
    rr::RenderStats stats;
    for (int f = 0; f < frames; ++f) {
      const rr::RenderReport r = rr::render(c, cscene, no_png).report;
      sort.push_back(r.timings.sort_ms);
      draw.push_back(r.timings.raster_ms + r.timings.shade_ms);
      stats = r.stats;
    }
    classic[name] = {{"polygons", csoup.polygons.size()},
                     {"sort_ms", round3(median(sort))},
                     {"draw_ms", round3(median(draw))},
                     {"polygons_drawn", stats.polygons_drawn},
                     {"pairs_tested", stats.painter_pairs_tested},
                     {"splits", stats.painter_splits}};
    std::printf("  %-26s sort %.3f ms  draw %.3f ms  (pairs tested %zu, splits %zu)\n", name, median(sort),
                median(draw), stats.painter_pairs_tested, stats.painter_splits);
  }
  result["newell_with_splits"] = classic;

  // Scaling: the sort stage alone (painter_order is exactly what sort_ms times).
  json scaling = json::array();
  std::printf("sort time by size (median):\n");
  for (int side : {4, 13, 41}) {  // 16, 169, 1681 tubes of 60 quads: ~10^3, 10^4, 10^5 polygons
    rr::RenderRequest g = rr::request_from_json(tube_grid(side));
    rr::PolygonSoup gsoup = rr::tessellate(g.scene.geometry);
    rr::ViewTransform view = rr::make_view(g.camera, g.options.width, g.options.height);
    rr::RenderContext context;
    rr::FrameInput input{g.scene, gsoup, view, g.options, context};
    const int runs = gsoup.polygons.size() >= 100000 ? 5 : (gsoup.polygons.size() >= 10000 ? 11 : 21);
    json row = {{"polygons", gsoup.polygons.size()}, {"tubes", side * side}, {"runs", runs}};
    json row_keys = json::object();
    std::printf("  %7zu polygons:", gsoup.polygons.size());
    for (size_t k = 0; k < std::size(keys); ++k) {
      std::vector<double> times;
      rr::PainterOrder order;
      for (int r = 0; r < runs; ++r) {
        rr::Stopwatch clock;
        order = rr::painter_order(input, keys[k]);
        times.push_back(clock.elapsed_ms());
      }
      row_keys[key_names[k]] = {{"sort_ms", round3(median(times))}, {"sorted", order.items.size()},
                                {"culled", order.culled},           {"pairs_tested", order.pairs_tested},
                                {"splits", order.splits},           {"budget_exhausted", order.budget_exhausted}};
      std::printf("  %s %.3f ms", key_names[k], median(times));
      if (keys[k] == rr::PainterKey::newell) {
        std::printf(" (pairs %zu, splits %zu%s)", order.pairs_tested, order.splits,
                    order.budget_exhausted ? ", budget exhausted" : "");
      }
    }
    std::printf("\n");
    row["keys"] = row_keys;
    scaling.push_back(row);
  }
  result["sort_scaling"] = scaling;

  std::ofstream out(out_path);
  out << result.dump(2) << "\n";
  return out ? 0 : 1;
}

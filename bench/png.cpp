// PNG encoders on rendered frames: median encode time and size of stb_image_write at its defaults
// (the reference) and of each mode (and of `fast` on one thread), with the ratios the performance
// issue targets: fast >= 5x faster than the reference and no more than 1.5x its size. Writes JSON
// to --out.
#include "render/core/png.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace rr;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path = "bench/results/png.json";
  int runs = 31;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string flag = argv[i];
    if (flag == "--out") out_path = argv[i + 1];
    if (flag == "--runs") runs = std::max(1, std::stoi(argv[i + 1]));
  }
  nlohmann::json results = nlohmann::json::array();
  for (const char* example : {"apartment", "studio", "four_cylinders"}) {
    nlohmann::json request =
        nlohmann::json::parse(read_text(std::string(ROOMRENDER_SOURCE_DIR) + "/examples/" + example + ".json"));
    request["options"]["width"] = 1280;
    request["options"]["height"] = 720;
    RenderRequest parsed = request_from_json(request);
    RenderContext no_png;
    no_png.encode = false;  // the encoders are measured below, one by one
    const Image image = render(parsed, prepare_scene(std::move(parsed.scene)), no_png).frame.image;
    struct Mode {
      std::string name;
      PngCompression mode;
      unsigned threads;
    };
    std::vector<Mode> modes = {{"stb_reference", PngCompression::small, 1},
                               {"small", PngCompression::small, 0},
                               {"fast", PngCompression::fast, 0},
                               {"fast_1_thread", PngCompression::fast, 1},
                               {"none", PngCompression::none, 1}};
    nlohmann::json row = {{"scene", example}, {"width", 1280}, {"height", 720}};
    for (const Mode& m : modes) {
      std::vector<double> ms;
      size_t bytes = 0;
      for (int r = 0; r < runs; ++r) {
        Stopwatch clock;
        bytes = (m.name == "stb_reference" ? encode_png(image) : encode_png(image, m.mode, m.threads)).size();
        ms.push_back(clock.elapsed_ms());
      }
      row[m.name] = {{"median_ms", median(ms)}, {"bytes", bytes}};
    }
    auto ratio = [&](const char* a, const char* b, const char* what) {
      return row[a][what].get<double>() / row[b][what].get<double>();
    };
    row["fast_speedup_vs_stb"] = ratio("stb_reference", "fast", "median_ms");
    row["fast_size_vs_stb"] = ratio("fast", "stb_reference", "bytes");
    row["small_speedup_vs_stb"] = ratio("stb_reference", "small", "median_ms");
    row["small_size_vs_stb"] = ratio("small", "stb_reference", "bytes");
    std::cout << row.dump() << "\n";
    results.push_back(row);
  }
  std::ofstream(out_path) << nlohmann::json{{"benchmark", "png"}, {"runs", runs}, {"results", results}}.dump(2) << "\n";
}

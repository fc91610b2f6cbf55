// scene_id() on large static geometry: median time of --runs calls (default 7) for each scene given,
// after one untimed call. Scenes come as render requests (--request FILE, e.g. the 10^6-triangle soup
// that bench_gen_scenes writes) or as OBJ files through the importer (--obj FILE, e.g. the conference
// room). Parsing and importing are not timed. Writes JSON to --out.
// usage: bench_scene_id --out OUT.json [--runs N] [--request FILE]... [--obj FILE]...
#include "render/core/scene_id.hpp"
#include "bench/bench_io.hpp"
#include "render/core/timer.hpp"
#include "render/import/import_files.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using namespace rr;
using rr::bench::read_text;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Input {
  std::string name;
  StaticGeometry geometry;
};

size_t mesh_faces(const StaticGeometry& g) {
  size_t faces = 0;
  for (const Solid& s : g.solids) faces += s.mesh ? s.mesh->faces.size() : 0;
  return faces;
}

size_t mesh_vertices(const StaticGeometry& g) {
  size_t vertices = 0;
  for (const Solid& s : g.solids) vertices += s.mesh ? s.mesh->vertices.size() : 0;
  return vertices;
}

nlohmann::json measure(const Input& input, int runs) {
  std::string id = scene_id(input.geometry);  // warms caches and the allocator
  std::vector<double> ms;
  for (int r = 0; r < runs; ++r) {
    Stopwatch clock;
    id = scene_id(input.geometry);
    ms.push_back(clock.elapsed_ms());
  }
  return {{"scene", input.name},
          {"solids", input.geometry.solids.size()},
          {"mesh_faces", mesh_faces(input.geometry)},
          {"mesh_vertices", mesh_vertices(input.geometry)},
          {"scene_id", id},
          {"median_ms", median(ms)},
          {"min_ms", *std::min_element(ms.begin(), ms.end())},
          {"runs_ms", ms}};
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path = "bench/results/scene_id.json";
  int runs = 7;
  std::vector<std::pair<std::string, std::string>> scenes;  // (flag, path)
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string flag = argv[i];
    if (flag == "--out") out_path = argv[i + 1];
    if (flag == "--runs") runs = std::max(1, std::stoi(argv[i + 1]));
    if (flag == "--request" || flag == "--obj") scenes.emplace_back(flag, argv[i + 1]);
  }
  if (scenes.empty()) {
    std::cerr << "usage: bench_scene_id --out OUT.json [--runs N] [--request FILE]... [--obj FILE]...\n";
    return 2;
  }
  nlohmann::json results = nlohmann::json::array();
  for (const auto& [flag, path] : scenes) {
    Input input{std::filesystem::path(path).stem().string(), {}};
    if (flag == "--request") {
      input.geometry = parse_request(read_text(path), ParseLimits{}).scene.geometry;
    } else {
      ImportResult imported = import_path(path, ImportFormat::obj, {});
      input.geometry = request_from_json(imported.request).scene.geometry;
    }
    nlohmann::json row = measure(input, runs);
    std::cout << row.dump() << "\n";
    results.push_back(row);
  }
  std::ofstream(out_path) << nlohmann::json{{"benchmark", "scene_id"}, {"runs", runs}, {"results", results}}.dump(2)
                          << "\n";
}

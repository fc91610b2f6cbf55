// Run time against error (issue 6; scripts: bench/accuracy.sh, report: bench/accuracy_report.py):
// renders every scene of the suite (bench/accuracy/suite.hpp) with every pipeline and option
// (bench/accuracy/runs.hpp), and measures each frame against the `reference` pipeline's frame of the
// same scene, camera and options. Writes one JSON document of all runs to --out.
//   bench_accuracy --out FILE [--size 640x360] [--frames 5] [--timeout 120] [--gen-manifest FILE]
//                  [--shared DIR] [--only NAME,NAME] [--configs LABEL,LABEL] [--r2v N] [--images DIR]
// --configs keeps the configurations whose label contains one of the given strings (e.g. "shadows"
// for every shadow setting); the reference frames they need are rendered as always.
// --images writes each scene's reference image (flat, no shadows) and its painter-mean frame as PNGs
// for a look at the cameras; they are not part of the results.
#include "bench/accuracy/errors.hpp"
#include "bench/accuracy/runs.hpp"
#include "bench/accuracy/suite.hpp"
#include "render/core/image.hpp"
#include "render/core/scene_id.hpp"
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

namespace {

using nlohmann::ordered_json;
using rr::bench::BenchScene;

struct Args {
  std::string out;
  rr::bench::SuiteOptions suite;
  int frames = 5;
  double timeout_s = 120.0;
  std::string images_dir;
  std::vector<std::string> configs;  // keep configurations whose label contains one of these; empty: all
};

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

// True when `filters` is empty or `text` contains one of them.
bool contains_any(const std::string& text, const std::vector<std::string>& filters) {
  if (filters.empty()) return true;
  return std::any_of(filters.begin(), filters.end(),
                     [&](const std::string& f) { return text.find(f) != std::string::npos; });
}

Args parse_args(int argc, char** argv) {
  Args a;
  a.suite.source_dir = ROOMRENDER_SOURCE_DIR;
  a.suite.shared_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / ".." / "shared" / "data";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--out") a.out = value;
    else if (flag == "--frames") a.frames = std::max(1, std::stoi(value));
    else if (flag == "--timeout") a.timeout_s = std::stod(value);
    else if (flag == "--gen-manifest") a.suite.gen_manifest = value;
    else if (flag == "--shared") a.suite.shared_dir = value;
    else if (flag == "--only") a.suite.only = split_list(value);
    else if (flag == "--configs") a.configs = split_list(value);
    else if (flag == "--r2v") a.suite.r2v_plans = std::stoi(value);
    else if (flag == "--images") a.images_dir = value;
    else if (flag == "--size" && std::sscanf(value.c_str(), "%dx%d", &a.suite.width, &a.suite.height) == 2) continue;
    else throw std::invalid_argument("unknown flag or value: " + flag + " " + value);
  }
  if (a.out.empty() || argc % 2 == 0) throw std::invalid_argument("--out FILE is required; flags take one value each");
  return a;
}

std::string first_line_with(const char* path, const char* prefix) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) return line.substr(line.find(':') == std::string::npos ? 0 : line.find(':') + 2);
  }
  return "";
}

ordered_json machine_json(const char* when) {
  std::ifstream load("/proc/loadavg");
  std::string load_text;
  std::getline(load, load_text);
  return {{"when", when},
          {"nproc", std::thread::hardware_concurrency()},
          {"cpu", first_line_with("/proc/cpuinfo", "model name")},
          {"loadavg", load_text}};
}

std::string utc_now() {
  std::time_t t = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return text;
}

void write_png(const std::string& path, const rr::Image& image) {
  std::ofstream out(path, std::ios::binary);
  out << rr::encode_png(image);
}

// The reference frame for `options`: the same options with pipeline `reference`, rendered once per
// scene and set of shading options (visibility options do not change the reference's frame).
struct ReferenceCache {
  const BenchScene& scene;
  const std::string& scene_id;
  double timeout_s;
  std::map<std::string, rr::bench::TimedRender> frames;

  const rr::bench::TimedRender& get(const rr::RenderOptions& options, const ordered_json& key) {
    auto it = frames.find(key.dump());
    if (it != frames.end()) return it->second;
    const rr::PipelineInfo* reference = rr::find_pipeline("reference");
    if (!reference) throw std::runtime_error("this build has no `reference` pipeline");
    rr::RenderOptions r = options;
    r.pipeline = rr::pipeline_id(*reference);
    return frames.emplace(key.dump(), rr::bench::time_render(scene, scene_id, r, 1, timeout_s)).first->second;
  }
};

ordered_json run_row(const BenchScene& scene, const rr::bench::BenchConfig& config, const rr::bench::TimedRender& timed,
                     const rr::bench::TimedRender& reference) {
  ordered_json row = {{"scene", scene.name},
                      {"class", scene.scene_class},
                      {"config", config.label},
                      {"group", config.group},
                      {"options", config.options_json},
                      {"status", timed.status},
                      {"frames", timed.frames},
                      {"frame_ms", timed.frame_ms_median},
                      {"build_ms", timed.build_ms},
                      {"stage_ms", timed.stage_ms_median},
                      {"reference_ms", reference.frame_ms_median}};
  if (timed.status == "ok" && reference.status == "ok") {
    row["errors"] = rr::bench::measure_errors(reference.last.frame, timed.last.frame, scene.prepared.soup);
  } else if (reference.status != "ok") {
    row["status"] = "reference " + reference.status;
  }
  const rr::RenderStats& s = timed.last.stats;
  row["counts"] = {{"polygons_drawn", s.polygons_drawn},
                   {"painter_splits", s.painter_splits},
                   {"bsp_fragments", s.bsp_fragments},
                   {"bsp_depth", s.bsp_depth}};
  return row;
}

// Every configuration on one scene; prints one progress line per run to stderr.
void bench_scene(const BenchScene& scene, const Args& args, ordered_json& runs) {
  const std::string id = scene.prepared.static_id;
  ReferenceCache references{scene, id, args.timeout_s, {}};
  for (rr::bench::BenchConfig config : rr::bench::make_configs(scene)) {
    if (!contains_any(config.label, args.configs)) continue;
    config.options.width = scene.request.options.width;
    config.options.height = scene.request.options.height;
    // The reference shades every pixel (Blinn-Phong, interpolated normals) whatever the shading mode,
    // and casts exact shadow rays whatever the map size: only shadows on/off changes its frame.
    const ordered_json reference_key = {{"shadows", config.options.shadows}};
    const rr::bench::TimedRender& reference = references.get(config.options, reference_key);
    const rr::bench::TimedRender timed = rr::bench::time_render(scene, id, config.options, args.frames, args.timeout_s);
    runs.push_back(run_row(scene, config, timed, reference));
    if (!args.images_dir.empty() && config.label == "painter-mean" && timed.status == "ok") {
      write_png(args.images_dir + "/" + scene.name + ".reference.png", reference.last.frame.image);
      write_png(args.images_dir + "/" + scene.name + ".painter-mean.png", timed.last.frame.image);
    }
    std::fprintf(stderr, "%-28s %-30s %9.2f ms  %s\n", scene.name.c_str(), config.label.c_str(), timed.frame_ms_median,
                 runs.back().contains("errors") ? runs.back()["errors"].dump().c_str()
                                                : runs.back()["status"].get<std::string>().c_str());
  }
  for (const auto& [key, timed] : references.frames) {  // the reference's own run time, at zero error
    const ordered_json k = ordered_json::parse(key);
    runs.push_back({{"scene", scene.name},
                    {"class", scene.scene_class},
                    {"config", "reference"},
                    {"group", "reference"},
                    {"options", {{"pipeline", "reference"}, {"shadows", k["shadows"]}}},
                    {"status", timed.status},
                    {"frames", timed.frames},
                    {"frame_ms", timed.frame_ms_median}});
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse_args(argc, argv);
    ordered_json doc = {{"benchmark", "accuracy"},
                        {"date", utc_now()},
                        {"width", args.suite.width},
                        {"height", args.suite.height},
                        {"max_frames", args.frames},
                        {"timeout_s", args.timeout_s},
                        {"machine_start", machine_json("start")}};
    ordered_json scenes = ordered_json::array(), runs = ordered_json::array();
    for (const BenchScene& scene : rr::bench::load_suite(args.suite)) {
      scenes.push_back({{"name", scene.name},
                        {"class", scene.scene_class},
                        {"source", scene.source},
                        {"polygons", scene.prepared.soup.polygons.size()},
                        {"lights", scene.prepared.scene.lights.size()},
                        {"light_added", scene.light_added},
                        {"camera", scene.camera_note},
                        {"large", rr::bench::is_large(scene)},
                        {"few_shadow_settings", rr::bench::has_few_shadow_settings(scene)}});
      bench_scene(scene, args, runs);
    }
    doc["machine_end"] = machine_json("end");
    doc["scenes"] = scenes;
    doc["runs"] = runs;
    std::ofstream out(args.out);
    out << doc.dump(1) << "\n";
    if (!out) throw std::runtime_error("cannot write " + args.out);
    return 0;
  } catch (const rr::InputError& e) {
    std::fprintf(stderr, "bench_accuracy: %s at %s\n", e.what(), e.pointer().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_accuracy: %s\n", e.what());
  }
  return 1;
}

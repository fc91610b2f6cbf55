// The benchmark scenes of issue 8, each written twice with identical triangles: a room-format request
// (what `roomrender bench-render --request` reads) and a Wavefront OBJ made from that request's own
// tessellation (what the llvmpipe peer, bench/peer/osmesa_bench.cpp, reads), plus a manifest of
// cameras (OpenGL conventions: eye, target, up, fovy, near, far) and the light (direction toward it).
// Scenes: the four open 60-quad cylinders, a 6-room apartment of ~2,700 triangles with doors and
// windows (a bird's-eye and an eye-level camera), and seeded random triangle soups of 10^3..10^6.
// usage: bench_gen_scenes --dir DIR --out MANIFEST.json [--soups 1000,10000,...] [--seed N]
#include "cli/bench_render.hpp"
#include "cli/cli.hpp"
#include "render/core/tessellate.hpp"
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct CameraSpec {
  std::string name;
  json eye, target, up = {0, 1, 0};
  double fovy = 60, near = 0.1, far = 100;
};

struct SceneSpec {
  std::string name;
  std::string kind;  // "room" or "soup"
  json request;      // camera = cameras[0], 1280x720, one directional light
  std::vector<CameraSpec> cameras;
  json light_to;  // unit-free direction toward the light
};

// Every scene gets the same frame and one directional light, given as the peer takes it.
json finish_request(json scene, const CameraSpec& camera, const json& light_to) {
  scene["lights"] = json::array(
      {{{"type", "directional"},
        {"direction", {-light_to[0].get<double>(), -light_to[1].get<double>(), -light_to[2].get<double>()}}}});
  return {{"scene", scene},
          {"camera",
           {{"position", camera.eye},
            {"target", camera.target},
            {"up", camera.up},
            {"fov_y", camera.fovy},
            {"near", camera.near},
            {"far", camera.far}}},
          {"options", {{"width", 1280}, {"height", 720}, {"pipeline", "zbuffer"}, {"shading", "flat"}}}};
}

// examples/four_cylinders.json, the classic many-thin-polygons scene, as published.
SceneSpec make_cylinders() {
  std::ifstream in(fs::path(ROOMRENDER_SOURCE_DIR) / "examples" / "four_cylinders.json");
  json example = json::parse(in);
  const json& c = example["camera"];
  CameraSpec camera{"default", c["position"], c["target"], c["up"], c["fov_y"], c["near"], c["far"]};
  json light_to = {0.6, 1.0, 0.4};
  return {"cylinders", "room", finish_request(example["scene"], camera, light_to), {camera}, light_to};
}

json box(const char* id, const char* color, double x, double z, double sx, double sy, double sz, double base = 0) {
  return {{"type", "box"}, {"id", id}, {"color", color}, {"center", {x, z}}, {"size", {sx, sy, sz}}, {"base", base}};
}

json cylinder(const char* id, const char* color, double x, double z, double r, double h, int segments,
              double base = 0) {
  return {{"type", "cylinder"}, {"id", id},    {"color", color},       {"center", {x, z}},
          {"radius", r},        {"height", h}, {"segments", segments}, {"base", base}};
}

json door(double offset, double width, bool leaf) {
  return {{"type", "door"}, {"offset", offset}, {"width", width}, {"height", 2.1}, {"leaf", leaf}};
}

json window(double offset, double width) {
  return {{"type", "window"}, {"offset", offset}, {"width", width}, {"sill", 0.9}, {"height", 1.3}};
}

json wall(const char* id, double x0, double z0, double x1, double z1, double thickness, json openings) {
  return {{"id", id},        {"start", {x0, z0}},
          {"end", {x1, z1}}, {"thickness", thickness},
          {"height", 2.7},   {"openings", std::move(openings)}};
}

// A 12 m x 8 m apartment: living room, kitchen and bathroom along the south side; two bedrooms and a
// study along the north. Exterior walls are mitred at the corners, interior walls meet them in T
// joints; doors with and without leaves, windows in every room, furniture in every room.
SceneSpec make_apartment() {
  json walls = json::array({
      wall("south", 0, 0, 12, 0, 0.25,
           {door(5.6, 1.0, true), window(1.0, 1.8), window(3.2, 1.6), window(6.9, 1.3), window(10.0, 0.9)}),
      wall("east", 12, 0, 12, 8, 0.25, {window(1.0, 1.0), window(5.2, 1.6)}),
      wall("north", 12, 8, 0, 8, 0.25, {window(1.0, 1.6), window(5.2, 1.6), window(9.3, 1.6)}),
      wall("west", 0, 8, 0, 0, 0.25, {window(1.2, 1.4), window(5.3, 1.8)}),
      wall("middle", 0, 4.5, 12, 4.5, 0.12, {door(1.5, 0.9, true), door(6.0, 0.9, false), door(9.8, 0.8, true)}),
      wall("living_kitchen", 5, 0, 5, 4.5, 0.12, {door(2.4, 1.2, false)}),
      wall("kitchen_bath", 8.5, 0, 8.5, 4.5, 0.12, {door(3.0, 0.8, true)}),
      wall("bed1_bed2", 4, 4.5, 4, 8, 0.12, json::array()),
      wall("bed2_study", 8, 4.5, 8, 8, 0.12, {door(1.6, 0.8, true)}),
  });
  json solids = json::array({
      // Living room.
      box("sofa", "#4a6fa5", 2.0, 3.7, 2.2, 0.8, 0.9),
      box("coffee_table", "#8a5a32", 2.0, 2.4, 1.1, 0.4, 0.6),
      box("tv_stand", "#333333", 2.0, 0.45, 1.6, 0.5, 0.4),
      cylinder("dining_table", "#b07840", 3.9, 1.5, 0.55, 0.75, 48),
      cylinder("dining_stool_1", "#604030", 3.1, 1.5, 0.2, 0.45, 32),
      cylinder("dining_stool_2", "#604030", 4.7, 1.5, 0.2, 0.45, 32),
      cylinder("lamp_pole", "#dddddd", 0.5, 4.0, 0.04, 1.6, 16),
      cylinder("lamp_shade", "#f0e0b0", 0.5, 4.0, 0.25, 0.3, 32, 1.5),
      // Kitchen.
      box("counter_south", "#c8c8c0", 6.75, 0.45, 3.2, 0.9, 0.6),
      box("counter_east", "#c8c8c0", 8.1, 2.0, 0.6, 0.9, 2.4),
      box("fridge", "#eeeeee", 5.5, 0.45, 0.7, 1.9, 0.65),
      cylinder("kitchen_table", "#a06a3a", 6.6, 2.9, 0.45, 0.75, 40),
      // Bathroom.
      box("bathtub", "#f4f4f4", 10.2, 0.55, 1.7, 0.55, 0.75),
      box("basin", "#f4f4f4", 11.5, 3.2, 0.5, 0.85, 0.45),
      cylinder("toilet", "#f4f4f4", 11.4, 1.9, 0.22, 0.42, 24),
      // Bedroom 1 and 2.
      box("bed1", "#a05060", 1.9, 6.9, 1.6, 0.5, 2.0),
      box("wardrobe1", "#6b4a30", 3.6, 5.6, 0.6, 2.0, 1.2),
      box("bed2", "#5060a0", 6.0, 6.9, 1.4, 0.5, 2.0),
      box("desk2", "#8a6a4a", 4.7, 5.2, 1.2, 0.75, 0.6),
      cylinder("stool2", "#505050", 4.7, 5.9, 0.2, 0.45, 24),
      // Study.
      box("desk", "#8a6a4a", 10.0, 7.5, 1.8, 0.75, 0.7),
      box("shelf", "#6b4a30", 11.7, 6.0, 0.35, 2.0, 1.6),
      cylinder("chair", "#505050", 10.0, 6.7, 0.25, 0.45, 32),
      {{"type", "pyramid"},
       {"id", "plant_leaves"},
       {"color", "#3f8f3f"},
       {"center", {8.6, 7.4}},
       {"size", {0.6, 1.2, 0.6}},
       {"base", 0.4}},
      cylinder("plant_pot", "#9a5a3a", 8.6, 7.4, 0.25, 0.4, 32),
  });
  json scene = {{"background", "#1e2a36"},
                {"floor", {{"origin", {0, 0}}, {"cells", {24, 16}}, {"cell_size", 0.5}}},
                {"walls", walls},
                {"solids", solids}};
  CameraSpec birds_eye{"birds_eye", {6.0, 9.0, -2.2}, {6.0, 0.0, 4.3}};
  CameraSpec eye_level{"eye_level", {0.5, 1.6, 1.2}, {8.5, 1.1, 3.4}};
  json light_to = {0.4, 1.0, 0.3};
  return {"apartment", "room", finish_request(scene, birds_eye, light_to), {birds_eye, eye_level}, light_to};
}

// splitmix64: a fixed, portable generator (std distributions differ between standard libraries).
struct Random {
  uint64_t state;
  double uniform() {  // [0, 1)
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
  double signed_unit() { return 2.0 * uniform() - 1.0; }
};

// n triangles with centres uniform in a 10 m cube in front of the camera. Edge lengths scale with
// n^-1/2 so the summed area, hence the overdraw, stays about the same for every n: the curve of
// time against n then measures per-triangle cost, not fill. Coordinates are millimetres, so the
// request stays compact and the OBJ and the request hold the same decimals.
SceneSpec make_soup(size_t n, uint64_t seed) {
  Random random{seed};
  const double edge = 1.6 * std::sqrt(1000.0 / double(n));
  auto mm = [](double v) { return std::round(v * 1000.0) / 1000.0; };
  json vertices = json::array(), faces = json::array();
  while (faces.size() < n) {
    double c[3] = {5 * random.signed_unit(), 5 * random.signed_unit(), 5 * random.signed_unit()};
    double p[3][3];
    for (auto& v : p) {
      for (int k = 0; k < 3; ++k) v[k] = mm(c[k] + edge * random.signed_unit());
    }
    // Refuse slivers: twice the area must be at least a tenth of edge^2.
    double a[3], b[3];
    for (int k = 0; k < 3; ++k) a[k] = p[1][k] - p[0][k], b[k] = p[2][k] - p[0][k];
    double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2], cz = a[0] * b[1] - a[1] * b[0];
    if (std::sqrt(cx * cx + cy * cy + cz * cz) < 0.1 * edge * edge) continue;
    size_t first = vertices.size();
    for (auto& v : p) vertices.push_back({v[0], v[1], v[2]});
    faces.push_back({first, first + 1, first + 2});
  }
  json scene = {{"background", "#202020"},
                {"solids", json::array({{{"type", "mesh"},
                                         {"id", "soup"},
                                         {"color", "#b0b0b0"},
                                         {"vertices", std::move(vertices)},
                                         {"faces", std::move(faces)}}})}};
  CameraSpec camera{"default", {0.0, 2.0, 14.0}, {0.0, 0.0, 0.0}};
  camera.far = 50;
  json light_to = {0.3, 1.0, 0.5};
  std::string name = "soup_" + std::to_string(n);
  return {name, "soup", finish_request(scene, camera, light_to), {camera}, light_to};
}

void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Writes the request and the OBJ of its own tessellation; returns the manifest entry.
json write_scene(const SceneSpec& spec, const fs::path& dir) {
  fs::path request_path = dir / (spec.name + ".json"), obj_path = dir / (spec.name + ".obj");
  write_file(request_path, spec.request.dump());
  rr::RenderRequest request = rr::request_from_json(spec.request);
  rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  write_file(obj_path, rr::cli::encode_obj(soup, "roomrender benchmark scene " + spec.name + ": the tessellation of " +
                                                     request_path.filename().string()));
  json cameras = json::array();
  for (const CameraSpec& c : spec.cameras) {
    cameras.push_back({{"name", c.name},
                       {"eye", c.eye},
                       {"target", c.target},
                       {"up", c.up},
                       {"fovy", c.fovy},
                       {"near", c.near},
                       {"far", c.far}});
  }
  return {{"name", spec.name},
          {"kind", spec.kind},
          {"request", request_path.string()},
          {"obj", obj_path.string()},
          {"polygons", soup.polygons.size()},
          {"triangles", rr::cli::fan_triangle_count(soup)},
          {"cameras", cameras},
          {"light_dir", spec.light_to}};
}

std::vector<size_t> parse_counts(const std::string& text) {
  std::vector<size_t> counts;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) counts.push_back(std::stoul(item));
  return counts;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::map<std::string, std::string> flags = {{"--soups", "1000,10000,100000,1000000"}, {"--seed", "8"}};
    for (int i = 1; i + 1 < argc; i += 2) flags[argv[i]] = argv[i + 1];
    if (!flags.count("--dir") || !flags.count("--out")) {
      std::fprintf(stderr, "usage: bench_gen_scenes --dir DIR --out MANIFEST.json [--soups N,N,...] [--seed N]\n");
      return 2;
    }
    fs::path dir = flags["--dir"];
    fs::create_directories(dir);
    json scenes = json::array();
    scenes.push_back(write_scene(make_cylinders(), dir));
    scenes.push_back(write_scene(make_apartment(), dir));
    const uint64_t seed = std::stoull(flags["--seed"]);
    for (size_t n : parse_counts(flags["--soups"])) scenes.push_back(write_scene(make_soup(n, seed + n), dir));
    write_file(flags["--out"], json{{"seed", seed}, {"scenes", scenes}}.dump(2) + "\n");
    for (const json& s : scenes)
      std::printf("%s: %zu triangles\n", s["name"].get<std::string>().c_str(), s["triangles"].get<size_t>());
    return 0;
  } catch (const rr::InputError& e) {  // a generator bug: the request it wrote is invalid
    std::fprintf(stderr, "bench_gen_scenes: %s at %s\n", e.what(), e.pointer().c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_gen_scenes: %s\n", e.what());
    return 1;
  }
}

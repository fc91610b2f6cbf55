// Loads the accuracy benchmark's scenes (suite.hpp). Every request goes through request_from_json, so
// the benchmark renders exactly what the service would accept; only `options` is replaced (size
// only: each benchmark configuration sets the rest) and a light is added where none is given.
#include "bench/accuracy/suite.hpp"

#include "render/core/image.hpp"
#include "render/import/import.hpp"
#include "render/import/import_files.hpp"
#include "render/import/import_obj.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace rr::bench {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  return json::parse(in);
}

bool wanted(const SuiteOptions& options, const std::string& name) {
  if (options.only.empty()) return true;
  return std::any_of(options.only.begin(), options.only.end(),
                     [&](const std::string& s) { return name.find(s) != std::string::npos; });
}

// Validates and tessellates `request` (its options replaced by the benchmark size) into a scene.
// Without `add_light`, a scene without lights keeps none (lit by its ambient alone).
BenchScene finish(std::string name, std::string scene_class, std::string source, json request,
                  const SuiteOptions& options, std::string camera_note, bool add_light = true) {
  BenchScene scene;
  json& lights = request["scene"]["lights"];
  if (add_light && (!lights.is_array() || lights.empty())) {
    // The shading and shadow measurements need a light: the importers' default sun.
    lights = json::array({{{"type", "directional"}, {"direction", {-0.35, -1.0, -0.55}}, {"intensity", 0.75}}});
    scene.light_added = true;
  }
  request["options"] = {{"width", options.width}, {"height", options.height}};
  scene.request_json = request.dump();
  scene.request = request_from_json(request);
  scene.prepared = prepare_scene(std::move(scene.request.scene));
  scene.name = std::move(name);
  scene.scene_class = std::move(scene_class);
  scene.source = std::move(source);
  scene.camera_note = std::move(camera_note);
  return scene;
}

// The classic test scenes and the hand-written rooms of examples/ (empty.json has nothing to compare).
void add_examples(const SuiteOptions& options, std::vector<BenchScene>& out) {
  const char* classic[] = {
      "tri_parallel",          "tri_intersecting",          "tetrahedron", "cylinders_8_16_32", "four_cylinders",
      "cube_pyramid_cylinder", "cubes_45_pyramid_cylinder", "rows"};
  const char* rooms[] = {"studio", "studio_lamp", "apartment"};
  auto add = [&](const char* name, const char* scene_class) {
    if (!wanted(options, name)) return;
    const fs::path path = options.source_dir / "examples" / (std::string(name) + ".json");
    out.push_back(finish(name, scene_class, "examples/" + path.filename().string(), read_json(path), options,
                         "the example's own camera"));
  };
  for (const char* name : classic) add(name, "classic");
  for (const char* name : rooms) add(name, "rooms");
}

// bench_gen_scenes' manifest: the generated apartment from each of its cameras, and the random
// triangle soups (intersecting triangles, so they join the classic class). Its cylinders scene is
// examples/four_cylinders.json again and is left out.
void add_generated(const SuiteOptions& options, std::vector<BenchScene>& out) {
  if (options.gen_manifest.empty()) return;
  const json manifest = read_json(options.gen_manifest);  // named: a range-for would not keep a temporary alive
  for (const json& entry : manifest["scenes"]) {
    const std::string kind = entry["kind"], base = entry["name"];
    if (base == "cylinders") continue;
    json request = read_json(entry["request"].get<std::string>());
    for (const json& c : entry["cameras"]) {
      // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
      std::string name = "gen_" + base;
      if (entry["cameras"].size() > 1) name.append("_").append(c["name"].get<std::string>());
      if (!wanted(options, name)) continue;
      request["camera"] = {{"position", c["eye"]}, {"target", c["target"]}, {"up", c["up"]},
                           {"fov_y", c["fovy"]},   {"near", c["near"]},     {"far", c["far"]}};
      out.push_back(finish(name, kind == "soup" ? "classic" : "rooms", "bench_gen_scenes " + base, request, options,
                           "bench_gen_scenes camera " + c["name"].get<std::string>()));
    }
  }
}

std::vector<fs::path> sorted_files(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == extension) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

json import_request(const fs::path& path, ImportFormat format, const SuiteOptions& options, double scale = 0.0) {
  ImportOptions import;
  import.width = options.width;
  import.height = options.height;
  import.scale = scale;
  return import_path(path, format, import).request;
}

// The nine Sweet Home 3D example homes (their observer camera) and the first R2V plans (the
// importer's view from 65 degrees above).
void add_floorplans(const SuiteOptions& options, std::vector<BenchScene>& out) {
  const fs::path sh3d_dir = options.shared_dir / "floorplans" / "sweethome3d";
  const fs::path r2v_dir = options.shared_dir / "floorplans" / "r2v";
  if (!fs::is_directory(sh3d_dir)) std::fprintf(stderr, "skipped: no %s\n", sh3d_dir.c_str());
  for (const fs::path& path : sorted_files(sh3d_dir, ".xml")) {
    const std::string name = "sh3d_" + path.stem().string();
    if (!wanted(options, name)) continue;
    out.push_back(finish(name, "sh3d", path.filename().string(),
                         import_request(path, ImportFormat::sweethome3d, options), options,
                         "the home's observer camera (import)"));
  }
  if (!fs::is_directory(r2v_dir)) std::fprintf(stderr, "skipped: no %s\n", r2v_dir.c_str());
  std::vector<fs::path> plans = sorted_files(r2v_dir, ".txt");
  std::erase_if(plans,
                [](const fs::path& p) { return p.filename().string().rfind("r2v_", 0) != 0; });  // LICENSE-MIT.txt
  if (plans.size() > size_t(options.r2v_plans)) plans.resize(size_t(options.r2v_plans));
  for (const fs::path& path : plans) {
    const std::string name = "r2v_" + path.stem().string().substr(4, 2);
    if (!wanted(options, name)) continue;
    out.push_back(finish(name, "r2v", path.filename().string(), import_request(path, ImportFormat::r2v, options),
                         options, "the importer's view from 65 degrees above"));
  }
}

// A camera inside the model's bounding box, at fractions of it: the importer's own camera shows
// interiors from outside, where the walls hide everything. The default is a high corner looking
// across to the opposite lower corner; fireplace_room's corner is inside a door frame, so it looks
// along x from near its +x wall instead (both checked by eye with --images).
struct InteriorView {
  Vec3 eye, target;
};
InteriorView interior_view(const std::string& mesh) {
  if (mesh == "fireplace_room") return {{0.92, 0.55, 0.5}, {0.1, 0.35, 0.5}};
  return {{0.88, 0.6, 0.88}, {0.3, 0.3, 0.3}};
}

json interior_camera(const PolygonSoup& soup, const InteriorView& view) {
  Vec3 lo(1e300), hi(-1e300);
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const Vec3 extent = hi - lo;
  const Vec3 eye = lo + extent * view.eye, target = lo + extent * view.target;
  const double diagonal = glm::length(extent);
  auto vec = [](const Vec3& v) { return json::array({v.x, v.y, v.z}); };
  return {{"position", vec(eye)},
          {"target", vec(target)},
          {"fov_y", 60.0},
          {"near", 1e-3 * diagonal},
          {"far", 2.0 * diagonal}};
}

void add_interiors(const SuiteOptions& options, std::vector<BenchScene>& out) {
  for (const std::string& mesh : options.interiors) {
    const fs::path path = options.shared_dir / "meshes" / mesh / (mesh + ".obj");
    const std::string name = "mesh_" + mesh;
    if (!wanted(options, name)) continue;
    if (!fs::exists(path)) {
      std::fprintf(stderr, "skipped: no %s\n", path.c_str());
      continue;
    }
    json request = import_request(path, ImportFormat::obj, options);
    request["options"] = {{"width", options.width}, {"height", options.height}};
    const InteriorView view = interior_view(mesh);
    request["camera"] = interior_camera(tessellate(request_from_json(request).scene.geometry), view);
    char note[160];
    std::snprintf(note, sizeof note, "inside the bounding box: eye at (%g, %g, %g) of it, target at (%g, %g, %g)",
                  view.eye.x, view.eye.y, view.eye.z, view.target.x, view.target.y, view.target.z);
    out.push_back(finish(name, "interiors", mesh + "/" + path.filename().string(), request, options, note));
  }
}

// The textured class: a 40 m floor of Sweet Home 3D's black and white tiles (0.5 m a tile; without
// ../shared, a checkerboard of the same period) seen from 0.3 m above it toward the horizon and lit
// by an ambient of 1 alone, so a pixel is its filtered texel; the papered studio of examples/; the
// fireplace room with its own UVs and images, from the camera of the untextured one.
json grazing_floor(const SuiteOptions& options) {
  const fs::path tiles = options.shared_dir / "textures" / "sweethome3d" / "blackAndWhiteTiles.jpg";
  std::string uri;
  if (fs::exists(tiles)) {
    std::ifstream in(tiles, std::ios::binary);
    uri = *import_detail::image_data_uri(std::string(std::istreambuf_iterator<char>(in), {}));
  } else {
    // Eight texels a square, so one tile of the image holds 8 x 8 squares.
    Image image(64, 64, Color(0.0f));
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 64; ++x) std::memset(image.pixel(x, y), ((x / 8 + y / 8) % 2) ? 235 : 20, 3);
    }
    uri = *import_detail::image_data_uri(encode_png(image));
  }
  return {{"scene",
           {{"ambient", {{"intensity", 1.0}}},
            {"background", "#000000"},
            {"floor",
             {{"origin", {-20, -20}},
              {"cells", {1, 1}},
              {"cell_size", 40},
              {"colors", {"#ffffff", "#ffffff"}},
              {"texture", {{"image", uri}, {"width", 0.5}, {"height", 0.5}}}}},
            {"lights", json::array()}}},
          {"camera", {{"position", {0.0, 0.3, 18.0}}, {"target", {0.4, 0.0, 4.0}}, {"fov_y", 50}, {"far", 100}}}};
}

void add_textured(const SuiteOptions& options, std::vector<BenchScene>& out) {
  if (wanted(options, "textured_grazing_floor")) {
    const bool tiles = fs::exists(options.shared_dir / "textures" / "sweethome3d" / "blackAndWhiteTiles.jpg");
    out.push_back(
        finish("textured_grazing_floor", "textures",
               tiles ? "sweethome3d/blackAndWhiteTiles.jpg on a 40 m floor" : "a checkerboard on a 40 m floor",
               grazing_floor(options), options, "0.3 m above the floor, toward the horizon", false));
  }
  if (wanted(options, "textured_papered_studio")) {
    out.push_back(finish("textured_papered_studio", "textures", "examples/studio_textured.json",
                         read_json(options.source_dir / "examples" / "studio_textured.json"), options,
                         "the example's own camera"));
  }
  const fs::path path = options.shared_dir / "meshes" / "fireplace_room" / "fireplace_room_uv.obj";
  if (!wanted(options, "textured_fireplace_room")) return;
  if (!fs::exists(path)) {
    std::fprintf(stderr, "skipped: no %s\n", path.c_str());
    return;
  }
  json request = import_request(path, ImportFormat::obj, options);
  const InteriorView view = interior_view("fireplace_room");
  request["camera"] = interior_camera(tessellate(request_from_json(request).scene.geometry), view);
  out.push_back(finish("textured_fireplace_room", "textures", "fireplace_room/" + path.filename().string(), request,
                       options, "the camera of mesh_fireplace_room"));
}

}  // namespace

std::vector<BenchScene> load_suite(const SuiteOptions& options) {
  std::vector<BenchScene> scenes;
  add_examples(options, scenes);
  add_generated(options, scenes);
  add_floorplans(options, scenes);
  add_interiors(options, scenes);
  add_textured(options, scenes);
  return scenes;
}

}  // namespace rr::bench

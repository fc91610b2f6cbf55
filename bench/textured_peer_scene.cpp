// The llvmpipe peer's copy of the accuracy suite's textured scenes (bench/textured_peer.py): for each,
// OUTDIR/NAME/request.json (the suite's request with its lights removed, ambient light 1 and every
// surface opaque, so a pixel is the material colour times the filtered texel and nothing else), scene.obj (the polygons
// this view draws, world space, f line k = the polygon of id k, with `vt` from each polygon's UvMap,
// v up as ours), scene.mtl (Kd = material colour x ambient irradiance, map_Kd) and texJ_L.png, level
// L of our own mip chain of image J, so both renderers filter the same texels. Prints one JSON line a
// scene: its name, directory and camera as osmesa_bench flags.
// usage: bench_textured_peer_scene --outdir DIR [--shared ../shared/data] [--only a,b] [--size WxH]
#include "bench/accuracy/suite.hpp"
#include "bench/bench_io.hpp"
#include "render/core/image.hpp"
#include "render/core/shading_detail.hpp"
#include "render/core/texture.hpp"
#include "render/pipelines/render.hpp"
#include "render/pipelines/view_selection.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

using namespace rr;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

std::string triple(Vec3 v) { return number(v.x) + "," + number(v.y) + "," + number(v.z); }

// Every level of the image as texJ_L.png (rows from the image's top, as MipLevel holds them).
void write_levels(const TextureImage& image, const fs::path& dir, size_t j) {
  for (size_t level = 0; level < image.levels.size(); ++level) {
    const MipLevel& m = image.levels[level];
    Image out(m.width, m.height, Color(0.0f));
    std::memcpy(out.rgb.data(), m.rgb.data(), m.rgb.size());
    write_text(dir / ("tex" + std::to_string(j) + "_" + std::to_string(level) + ".png"), encode_png(out));
  }
}

// scene.obj and scene.mtl of the soup: one `usemtl` per run of polygons of one material, faces in id
// order (ids must run 0..n-1, so the peer's f-line index is our polygon id), every corner its own
// v and, when textured, vt.
void write_obj(const PolygonSoup& soup, const glm::dvec3& irradiance, const fs::path& dir) {
  std::vector<uint32_t> order(soup.polygons.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return soup.polygons[a].id < soup.polygons[b].id; });
  std::map<const TextureImage*, size_t> images;
  std::ostringstream obj, mtl;
  obj << "# bench_textured_peer_scene\nmtllib scene.mtl\n";
  for (size_t k = 0; k < soup.materials.size(); ++k) {
    const Material& m = soup.materials[k];
    if (m.opacity < 1.0f) throw std::runtime_error("the matched setup is opaque: a material has opacity < 1");
    const glm::dvec3 kd = glm::dvec3(m.color) * irradiance;
    mtl << "newmtl m" << k << "\nKd " << number(kd.r) << " " << number(kd.g) << " " << number(kd.b) << "\n";
    if (m.texture) {
      const TextureImage* image = m.texture->decoded.get();
      auto [it, added] = images.emplace(image, images.size());
      if (added) write_levels(*image, dir, it->second);
      mtl << "map_Kd tex" << it->second << "_0.png\n";
    }
  }
  size_t v = 0, vt = 0;
  uint32_t material = ~0u;
  for (size_t k = 0; k < order.size(); ++k) {
    const Polygon& p = soup.polygons[order[k]];
    if (p.id != k) throw std::runtime_error("polygon ids are not 0..n-1 in this view");
    if (p.material != material) obj << "usemtl m" << (material = p.material) << "\n";
    const bool textured = p.uv_map > 0 && soup.materials[p.material].texture;
    std::string face = "f";  // appended piecewise: GCC 12 warns (-Wrestrict) on " " + std::string
    for (const Vec3& q : soup.points(p)) {
      obj << "v " << number(q.x) << " " << number(q.y) << " " << number(q.z) << "\n";
      face += ' ';
      face += std::to_string(++v);
      if (textured) {
        const glm::dvec2 uv = soup.uv_maps[p.uv_map - 1].at(q);
        obj << "vt " << number(uv.x) << " " << number(uv.y) << "\n";
        face += '/';
        face += std::to_string(++vt);
      }
    }
    obj << face << "\n";
  }
  write_text(dir / "scene.obj", obj.str());
  write_text(dir / "scene.mtl", mtl.str());
}

// Every `opacity` to 1, and every window's pane (0.35 when the request leaves it out): the peer draws
// no translucency, so the matched request has none.
void make_opaque(json& node) {
  if (node.is_object()) {
    if (node.contains("opacity") || (node.contains("type") && node["type"] == "window")) node["opacity"] = 1.0;
    for (auto& [key, value] : node.items()) make_opaque(value);
  } else if (node.is_array()) {
    for (json& value : node) make_opaque(value);
  }
}

json export_scene(const bench::BenchScene& suite_scene, const fs::path& outdir) {
  json request = json::parse(suite_scene.request_json);
  request["scene"]["lights"] = json::array();
  request["scene"]["ambient"] = {{"intensity", 1.0}};
  make_opaque(request["scene"]);
  const fs::path dir = outdir / suite_scene.name;
  fs::create_directories(dir);
  write_text(dir / "request.json", request.dump());
  RenderRequest parsed = request_from_json(request);
  const PreparedScene prepared = prepare_scene(std::move(parsed.scene));
  const SoupSelection selection = select_objects(prepared.scene.geometry, prepared.soup, parsed.camera, parsed.options);
  const PolygonSoup soup = selection.everything ? prepared.soup : selected_soup(prepared.soup, selection);
  write_obj(soup, shading_detail::ambient_irradiance(prepared.scene), dir);
  const Camera& c = parsed.camera;
  const Color bg = prepared.scene.background;
  return {
      {"scene", suite_scene.name},
      {"dir", dir.string()},
      {"faces", soup.polygons.size()},
      {"peer_flags",
       {"--eye", triple(c.position), "--target", triple(c.target), "--up", triple(c.up), "--fovy", number(c.fov_y_deg),
        "--near", number(c.near), "--far", number(c.far), "--size",
        std::to_string(parsed.options.width) + "x" + std::to_string(parsed.options.height), "--background",
        std::to_string(to_byte(bg.r)) + "," + std::to_string(to_byte(bg.g)) + "," + std::to_string(to_byte(bg.b))}}};
}

int run(int argc, char** argv) {
  bench::SuiteOptions options;
  options.source_dir = ROOMRENDER_SOURCE_DIR;
  options.shared_dir = fs::path(ROOMRENDER_SOURCE_DIR) / ".." / "shared" / "data";
  options.only = {"textured_"};
  fs::path outdir;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--outdir") outdir = value;
    else if (flag == "--shared") options.shared_dir = value;
    else if (flag == "--only") {
      options.only.clear();
      std::stringstream names(value);
      for (std::string name; std::getline(names, name, ',');) options.only.push_back(name);
    } else if (flag == "--size" && std::sscanf(value.c_str(), "%dx%d", &options.width, &options.height) == 2) {
      continue;
    } else {
      throw std::invalid_argument("unknown flag " + flag);
    }
  }
  if (outdir.empty() || argc % 2 == 0) throw std::invalid_argument("--outdir DIR is required; flags take one value");
  for (const bench::BenchScene& scene : bench::load_suite(options)) {
    if (scene.scene_class != "textures") continue;
    std::cout << export_scene(scene, outdir).dump() << std::endl;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bench_textured_peer_scene: " << e.what() << "\n";
    return 1;
  }
}

// The llvmpipe peer's copy of a matched render request (ambient light only, one flat colour per
// polygon) for bench/antialias.py: writes OUTDIR/scene.obj (the polygons this view draws, world
// space, f line k = k-th polygon by id, as `roomrender export`), OUTDIR/faces.txt (each face's
// colour "r g b" in 8-bit units, in the same order: material colour x ambient irradiance, rounded
// as roomrender's flat shading does) and prints the camera and background as one JSON line.
// usage: bench_antialias_peer_scene REQUEST.json OUTDIR
#include "bench/bench_io.hpp"
#include "cli/cli.hpp"
#include "render/core/image.hpp"
#include "render/core/shading_detail.hpp"
#include "render/pipelines/render.hpp"
#include "render/pipelines/view_selection.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

using namespace rr;
using rr::bench::read_text;

namespace {

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

// One byte triple per polygon in id order (encode_obj's face order). The colour is what flat
// shading gives under ambient light alone; a request with lights is not a matched setup.
std::string face_colors(const Scene& scene, const PolygonSoup& soup) {
  if (!scene.lights.empty()) throw std::runtime_error("the matched setup has no lights: remove scene.lights");
  std::vector<uint32_t> order(soup.polygons.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return soup.polygons[a].id < soup.polygons[b].id; });
  const glm::dvec3 irradiance = shading_detail::ambient_irradiance(scene);
  std::string out;
  for (uint32_t i : order) {
    const Material& m = soup.materials[soup.polygons[i].material];
    if (m.opacity < 1.0f) throw std::runtime_error("the matched setup is opaque: set every opacity to 1");
    const Color c = Color(glm::dvec3(m.color) * irradiance);
    out +=
        std::to_string(to_byte(c.r)) + " " + std::to_string(to_byte(c.g)) + " " + std::to_string(to_byte(c.b)) + "\n";
  }
  return out;
}

int run(const std::string& request_path, const std::string& outdir) {
  RenderRequest request = parse_request(read_text(request_path));
  const PreparedScene prepared = prepare_scene(std::move(request.scene));
  const SoupSelection selection =
      select_objects(prepared.scene.geometry, prepared.soup, request.camera, request.options);
  const PolygonSoup soup = selection.everything ? prepared.soup : selected_soup(prepared.soup, selection);
  write_text(outdir + "/scene.obj", cli::encode_obj(soup, "bench_antialias_peer_scene: " + request_path));
  write_text(outdir + "/faces.txt", face_colors(prepared.scene, soup));
  const Camera& c = request.camera;
  const Color bg = prepared.scene.background;
  auto triple = [](double x, double y, double z) {
    std::ostringstream s;
    s.precision(17);
    s << x << "," << y << "," << z;
    return s.str();
  };
  nlohmann::ordered_json line = {
      {"eye", triple(c.position.x, c.position.y, c.position.z)},
      {"target", triple(c.target.x, c.target.y, c.target.z)},
      {"up", triple(c.up.x, c.up.y, c.up.z)},
      {"fovy", c.fov_y_deg},
      {"near", c.near},
      {"far", c.far},
      {"size", std::to_string(request.options.width) + "x" + std::to_string(request.options.height)},
      {"background", triple(to_byte(bg.r), to_byte(bg.g), to_byte(bg.b))},
      {"faces", soup.polygons.size()}};
  std::cout << line.dump() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: bench_antialias_peer_scene REQUEST.json OUTDIR\n";
    return 2;
  }
  try {
    return run(argv[1], argv[2]);
  } catch (const std::exception& e) {
    std::cerr << "bench_antialias_peer_scene: " << e.what() << "\n";
    return 1;
  }
}

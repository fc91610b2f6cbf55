// Texture error of each filter against the reference (docs/textures.md): every scene is drawn by
// the reference pipeline (its box filter over each pixel's footprint) and by zbuffer with nearest,
// bilinear, trilinear and anisotropic filtering; the PSNR is taken over the textured pixels away from
// edges (the reference's polygon there is textured, no 4-neighbour has another id, and zbuffer drew
// the same polygon), so texture error is not mixed with edge error. Scenes: a tiled floor seen at a
// grazing angle and lit by an ambient of 1 alone (a pixel is its filtered texel), the papered studio
// (examples/studio_textured.json) and the textured fireplace room of ../shared (skipped without it).
// Results: a table on stdout and JSON at --out.
#include "bench_io.hpp"
#include "render/core/error_metrics.hpp"
#include "render/core/image.hpp"
#include "render/import/import.hpp"
#include "render/import/import_obj.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace {

using nlohmann::json;
using rr::bench::read_text;
namespace fs = std::filesystem;

const fs::path shared_data = fs::path(ROOMRENDER_SOURCE_DIR) / ".." / "shared" / "data";

// A 40 m floor tiled with Sweet Home 3D's black and white tiles (0.5 m a tile), or a checkerboard of
// the same period without ../shared, seen from 0.3 m above it toward the horizon.
json grazing_floor() {
  const fs::path tiles = shared_data / "textures" / "sweethome3d" / "blackAndWhiteTiles.jpg";
  std::string uri;
  if (fs::exists(tiles)) {
    uri = *rr::import_detail::image_data_uri(read_text(tiles.string()));
  } else {
    // Eight texels a square, so one tile of the image holds 8 x 8 squares.
    rr::Image image(64, 64, rr::Color(0.0f));
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 64; ++x) std::memset(image.pixel(x, y), ((x / 8 + y / 8) % 2) ? 235 : 20, 3);
    }
    uri = *rr::import_detail::image_data_uri(rr::encode_png(image));
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
          {"camera", {{"position", {0.0, 0.3, 18.0}}, {"target", {0.4, 0.0, 4.0}}, {"fov_y", 50}, {"far", 100}}},
          {"options", {{"width", 640}, {"height", 360}}}};
}

json papered_studio() {
  json request = json::parse(read_text(std::string(ROOMRENDER_SOURCE_DIR) + "/examples/studio_textured.json"));
  request["options"]["shadows"] = false;  // shadow error is measured elsewhere
  return request;
}

std::optional<json> fireplace_room() {
  const fs::path dir = shared_data / "meshes" / "fireplace_room";
  if (!fs::exists(dir / "fireplace_room_uv.obj")) return std::nullopt;
  rr::ImportOptions options;
  options.width = 640;
  options.height = 360;
  options.read_companion = [&](const std::string& name) -> std::optional<std::string> {
    const fs::path path = dir / name;
    if (!fs::exists(path)) return std::nullopt;
    return read_text(path.string());
  };
  json request = rr::import_obj(read_text((dir / "fireplace_room_uv.obj").string()), options).request;
  // The accuracy bench's camera for this room: inside its box, at (0.92, 0.55, 0.5) of it, looking
  // toward (0.1, 0.35, 0.5).
  request["camera"] = {{"position", {4.672, 1.582, -1.521}}, {"target", {0.050, 1.006, -1.521}}, {"near", 0.05}};
  request["options"]["shading"] = "phong";
  return request;
}

struct Scored {
  double psnr_db = 0.0;
  size_t pixels = 0;
  double ms = 0.0;
};

// PSNR over the textured pixels away from the reference's edges where both drew the same polygon.
Scored score(const rr::PolygonSoup& soup, const rr::RenderResult& ref, const rr::RenderResult& test) {
  double sum = 0.0;
  Scored s;
  const rr::IdBuffer& ids = ref.frame.ids;
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      const uint32_t id = ids.at(x, y);
      if (id == rr::background_id || soup.polygons[id].uv_map == 0 || rr::is_edge_pixel(ids, x, y)) continue;
      if (test.frame.ids.at(x, y) != id) continue;
      const uint8_t* a = ref.frame.image.pixel(x, y);
      const uint8_t* b = test.frame.image.pixel(x, y);
      for (int c = 0; c < 3; ++c) sum += double(a[c] - b[c]) * double(a[c] - b[c]);
      ++s.pixels;
    }
  }
  const double rmse = s.pixels ? std::sqrt(sum / double(3 * s.pixels)) : 0.0;
  s.psnr_db = rmse > 0.0 ? 20.0 * std::log10(255.0 / rmse) : INFINITY;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out_path = argv[++i];
    } else {
      std::cerr << "usage: bench_textures [--out FILE]\n";
      return 2;
    }
  }
  std::vector<std::pair<std::string, json>> scenes = {{"grazing_floor", grazing_floor()},
                                                      {"papered_studio", papered_studio()}};
  if (auto fireplace = fireplace_room()) scenes.emplace_back("fireplace_room", *fireplace);
  const std::pair<const char*, rr::TextureFilter> filters[] = {{"nearest", rr::TextureFilter::nearest},
                                                               {"bilinear", rr::TextureFilter::bilinear},
                                                               {"trilinear", rr::TextureFilter::trilinear},
                                                               {"anisotropic", rr::TextureFilter::anisotropic}};
  json results = json::array();
  std::printf("%-16s %-12s %10s %10s %10s\n", "scene", "filter", "PSNR dB", "pixels", "frame ms");
  for (const auto& [name, request_json] : scenes) {
    const rr::RenderRequest request = rr::request_from_json(request_json);
    const rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
    rr::RenderOptions options = request.options;
    rr::RenderContext context;
    context.threads = 2;
    options.pipeline = rr::pipeline_id("reference");
    auto start = std::chrono::steady_clock::now();
    const rr::RenderResult ref = rr::render_frame(request.scene, soup, request.camera, options, context);
    const double ref_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("%-16s %-12s %10s %10s %10.0f\n", name.c_str(), "reference", "-", "-", ref_ms);
    json row = {{"scene", name}, {"reference_ms", ref_ms}, {"filters", json::object()}};
    for (const auto& [filter_name, filter] : filters) {
      options.pipeline = rr::pipeline_id("zbuffer");
      options.texture_filter = filter;
      start = std::chrono::steady_clock::now();
      const rr::RenderResult test = rr::render_frame(request.scene, soup, request.camera, options, context);
      Scored s = score(soup, ref, test);
      s.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      std::printf("%-16s %-12s %10.2f %10zu %10.1f\n", name.c_str(), filter_name, s.psnr_db, s.pixels, s.ms);
      row["filters"][filter_name] = {{"psnr_db", s.psnr_db}, {"pixels", s.pixels}, {"frame_ms", s.ms}};
    }
    results.push_back(row);
  }
  if (!out_path.empty()) std::ofstream(out_path) << json({{"bench", "textures"}, {"scenes", results}}).dump(2) << "\n";
  return 0;
}

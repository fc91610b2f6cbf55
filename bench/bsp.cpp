// BSP benchmark (scripts/bench.sh bsp): on examples/four_cylinders.json (4 open tubes of 60 quads,
// 640x480) the median over --frames frames of the tree build, the back-to-front traversal and the
// draw (shade + raster); the bsp frame against the zbuffer frame on the apartment at 1280x720 with a
// warm cache; then build time, tree depth and fragment ratio for generated scenes of about 10^3,
// 10^4 and 10^5 polygons: grids of the tubes, and blocks of copies of the apartment; and the build
// time curve of the convex worst case, a sphere seen from inside (10^3..10^5 polygons, 1 and 2
// threads). Writes JSON to --out. The classic reference: 4.1 s to build the 240-quad tree, 2 ms to
// traverse it.
#include "render/pipelines/bsp.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using json = nlohmann::ordered_json;
using namespace rr;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

RenderRequest example(const std::string& stem, int width, int height) {
  nlohmann::json r =
      nlohmann::json::parse(read_text(std::string(ROOMRENDER_SOURCE_DIR) + "/examples/" + stem + ".json"));
  r["options"]["width"] = width;
  r["options"]["height"] = height;
  return request_from_json(r);
}

// `copies` copies of `soup` side by side on a square grid `pitch` metres apart.
PolygonSoup grid_of(const PolygonSoup& soup, int copies, double pitch) {
  PolygonSoup out;
  out.materials = soup.materials;
  out.objects = soup.objects;
  int side = int(std::ceil(std::sqrt(double(copies))));
  for (int c = 0; c < copies; ++c) {
    Vec3 shift(pitch * (c % side), 0.0, pitch * (c / side));
    for (const Polygon& p : soup.polygons) {
      Polygon q = p;
      q.first_vertex = uint32_t(out.positions.size());
      q.id = uint32_t(out.polygons.size());
      q.offset = p.offset + glm::dot(p.normal, shift);
      for (uint32_t k = 0; k < p.vertex_count; ++k) {
        out.positions.push_back(soup.positions[p.first_vertex + k] + shift);
        out.normals.push_back(soup.normals[p.first_vertex + k]);
      }
      out.polygons.push_back(q);
    }
  }
  return out;
}

// A sphere of radius 10 m seen from inside, about `faces` polygons (quads, triangles at the poles),
// normals inward: every polygon is in front of every other, the convex worst case of the build.
PolygonSoup inside_sphere(size_t faces) {
  const int rows = int(std::lround(std::sqrt(double(faces) / 2.0))), cols = int(faces) / rows;
  nlohmann::json vertices = nlohmann::json::array(), polygons = nlohmann::json::array();
  for (int i = 0; i <= rows; ++i) {
    const double theta = M_PI * i / rows;
    for (int j = 0; j < cols; ++j) {
      const double phi = 2.0 * M_PI * j / cols;
      vertices.push_back(
          {10.0 * std::sin(theta) * std::cos(phi), 10.0 * std::cos(theta), 10.0 * std::sin(theta) * std::sin(phi)});
    }
  }
  auto at = [&](int i, int j) { return i * cols + j % cols; };
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      if (i == 0) {
        polygons.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});  // the pole's vertices coincide
      } else if (i == rows - 1) {
        polygons.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
      } else {
        polygons.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  nlohmann::json request = {
      {"scene", {{"solids", nlohmann::json::array({{{"type", "mesh"}, {"vertices", vertices}, {"faces", polygons}}})}}},
      {"camera", {{"position", {0.0, 0.0, 0.0}}, {"target", {1.0, 0.0, 0.0}}}}};
  return tessellate(request_from_json(request).scene.geometry);
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path = "bench/results/bsp.json";
  int frames = 31;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string flag = argv[i];
    if (flag == "--out") out_path = argv[i + 1];
    if (flag == "--frames") frames = std::max(1, std::stoi(argv[i + 1]));
  }
  json result = {{"benchmark", "bsp"}, {"frames", frames}};

  {  // four cylinders: build, traverse, draw
    RenderRequest r = example("four_cylinders", 640, 480);
    const PreparedScene scene = prepare_scene(r.scene);
    const PolygonSoup& soup = scene.soup;
    RenderContext no_png;
    no_png.encode = false;  // frames up to the image, as bench-render measures them
    std::vector<double> build, traverse, draw, total;
    RenderStats stats;
    for (int f = 0; f < frames; ++f) {
      RenderRequest view = r;
      view.options.pipeline = pipeline_id("bsp");
      RenderReport res = render(view, scene, no_png).report;  // no cache: builds every frame
      build.push_back(res.timings.build_ms);
      traverse.push_back(res.timings.traverse_ms);
      draw.push_back(res.timings.shade_ms + res.timings.raster_ms);
      total.push_back(res.timings.total_ms);
      stats = res.stats;
    }
    result["four_cylinders"] = {
        {"polygons", soup.polygons.size()}, {"build_ms", median(build)},        {"traverse_ms", median(traverse)},
        {"draw_ms", median(draw)},          {"frame_ms", median(total)},        {"nodes", stats.bsp_nodes},
        {"depth", stats.bsp_depth},         {"fragments", stats.bsp_fragments}, {"splits", stats.bsp_splits},
        {"classic_build_ms", 4100.0},       {"classic_traverse_ms", 2.0}};
    std::cout << "four_cylinders " << result["four_cylinders"].dump() << "\n";
  }

  {  // bsp (warm cache) against zbuffer on the apartment at 1280x720
    RenderRequest r = example("apartment", 1280, 720);
    const PreparedScene scene = prepare_scene(r.scene);
    BspCache cache(256u << 20);
    RenderContext context{&cache, nullptr, scene.static_id};
    context.encode = false;
    RenderContext no_cache;
    no_cache.encode = false;
    std::vector<double> bsp_ms, z_ms;
    for (int f = 0; f < frames + 1; ++f) {
      RenderRequest view = r;
      view.options.pipeline = pipeline_id("bsp");
      double b = render(view, scene, context).report.timings.total_ms;
      view.options.pipeline = pipeline_id("zbuffer");
      double z = render(view, scene, no_cache).report.timings.total_ms;
      if (f == 0) continue;  // the first bsp frame builds the tree
      bsp_ms.push_back(b);
      z_ms.push_back(z);
    }
    result["apartment_1280x720"] = {{"bsp_frame_ms", median(bsp_ms)},
                                    {"zbuffer_frame_ms", median(z_ms)},
                                    {"bsp_over_zbuffer", median(bsp_ms) / median(z_ms)}};
    std::cout << "apartment " << result["apartment_1280x720"].dump() << "\n";
  }

  json scaling = json::array();
  struct Source {
    const char* name;
    const char* example;
    double pitch;
  };
  for (Source src : {Source{"tube grid", "four_cylinders", 4.0}, Source{"apartment block", "apartment", 14.0}}) {
    RenderRequest r = example(src.example, 640, 480);
    PolygonSoup one = tessellate(r.scene.geometry);
    for (size_t target : {size_t(1000), size_t(10000), size_t(100000)}) {
      int copies = int(std::max<size_t>(1, (target + one.polygons.size() / 2) / one.polygons.size()));
      PolygonSoup soup = grid_of(one, copies, src.pitch);
      BspTree tree = build_bsp(soup, r.options.bsp);
      json row = {{"scene", src.name},
                  {"polygons", soup.polygons.size()},
                  {"build_ms", tree.build_ms},
                  {"depth", tree.depth},
                  {"nodes", tree.nodes.size()},
                  {"fragments", tree.fragments.polygons.size()},
                  {"fragment_ratio", double(tree.fragments.polygons.size()) / double(soup.polygons.size())},
                  {"tree_mib", double(tree.bytes()) / (1 << 20)}};
      std::cout << row.dump() << "\n";
      scaling.push_back(row);
    }
  }
  result["scaling"] = scaling;

  json convex = json::array();
  for (size_t faces : {size_t(1000), size_t(3000), size_t(10000), size_t(30000), size_t(100000)}) {
    const PolygonSoup soup = inside_sphere(faces);
    for (unsigned threads : {1u, 2u}) {
      std::vector<double> ms;
      BspTree tree;
      for (int round = 0; round < 3; ++round) {
        tree = build_bsp(soup, BspOptions{}, nullptr, threads);
        ms.push_back(tree.build_ms);
      }
      json row = {{"scene", "inside sphere"}, {"polygons", soup.polygons.size()},
                  {"threads", threads},       {"build_ms", median(ms)},
                  {"depth", tree.depth},      {"nodes", tree.nodes.size()},
                  {"splits", tree.splits},    {"fragments", tree.fragments.polygons.size()}};
      std::cout << row.dump() << "\n";
      convex.push_back(row);
    }
  }
  result["convex_build"] = convex;
  std::ofstream(out_path) << result.dump(2) << "\n";
}

// Instanced mesh tessellation: one mesh of about --faces faces (a latitude-longitude sphere of planar
// quads, smooth) placed --copies times, tessellated (a) as one shared MeshData, its per-mesh plan made
// once in the run ("ref, cold") or already made by an earlier scene ("ref, warm"), and (b) as that
// many separate MeshData, as inlined meshes parse ("inline"). Median of --runs; the request's polygon
// limit is not applied. Writes JSON to --out.
// usage: bench_mesh_instancing --out OUT.json [--faces 50000] [--copies 100] [--runs 3]
#include "render/core/tessellate.hpp"
#include "render/core/timer.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace rr;

namespace {

struct RawMesh {
  std::vector<Vec3> vertices;
  std::vector<std::vector<uint32_t>> faces;
};

// rings x segments quads between the poles, and a fan of triangles at each pole.
RawMesh sphere(size_t faces) {
  const size_t segments = size_t(std::sqrt(double(faces) * 2.0));
  const size_t rings = std::max<size_t>(3, faces / segments);
  RawMesh m;
  m.vertices.push_back({0, 1, 0});
  for (size_t r = 1; r < rings; ++r) {
    const double phi = M_PI * double(r) / double(rings);
    for (size_t s = 0; s < segments; ++s) {
      const double theta = 2.0 * M_PI * double(s) / double(segments);
      m.vertices.push_back({std::sin(phi) * std::cos(theta), std::cos(phi), std::sin(phi) * std::sin(theta)});
    }
  }
  m.vertices.push_back({0, -1, 0});
  auto at = [&](size_t r, size_t s) { return uint32_t(1 + (r - 1) * segments + s % segments); };
  for (size_t s = 0; s < segments; ++s) m.faces.push_back({0, at(1, s + 1), at(1, s)});
  for (size_t r = 1; r + 1 < rings; ++r) {
    for (size_t s = 0; s < segments; ++s) m.faces.push_back({at(r, s), at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)});
  }
  const uint32_t south = uint32_t(m.vertices.size() - 1);
  for (size_t s = 0; s < segments; ++s) m.faces.push_back({south, at(rings - 1, s), at(rings - 1, s + 1)});
  return m;
}

StaticGeometry placements(const std::vector<std::shared_ptr<const MeshData>>& meshes, size_t copies) {
  StaticGeometry g;
  for (size_t i = 0; i < copies; ++i) {
    Solid s;
    s.type = SolidType::mesh;
    s.smooth = true;
    s.closed = true;
    s.mesh = meshes[i % meshes.size()];
    s.position = {double(i % 10) * 3.0, 0.0, double(i / 10) * 3.0};
    s.rotation_y_deg = double(i) * 7.0;
    g.solids.push_back(s);
  }
  return g;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string out_path = "bench/results/mesh_instancing.json";
  size_t faces = 50'000, copies = 100;
  int runs = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--out") out_path = argv[i + 1];
    if (flag == "--faces") faces = std::stoul(argv[i + 1]);
    if (flag == "--copies") copies = std::stoul(argv[i + 1]);
    if (flag == "--runs") runs = std::max(1, std::stoi(argv[i + 1]));
  }
  const RawMesh raw = sphere(faces);
  std::vector<double> cold, warm, inlined;
  size_t polygons = 0;
  for (int r = 0; r < runs; ++r) {
    // Fresh meshes each run, so no plan is left from the run before.
    std::vector<std::shared_ptr<const MeshData>> separate;
    for (size_t i = 0; i < copies; ++i) separate.push_back(make_mesh_data(raw.vertices, raw.faces, {}));
    const StaticGeometry shared = placements({separate[0]}, copies);
    Stopwatch c1;
    polygons = tessellate(shared).polygons.size();
    cold.push_back(c1.elapsed_ms());
    Stopwatch c2;
    tessellate(shared);
    warm.push_back(c2.elapsed_ms());
    const StaticGeometry copied = placements(separate, copies);
    Stopwatch c3;
    const size_t inline_polygons = tessellate(copied).polygons.size();
    inlined.push_back(c3.elapsed_ms());
    if (inline_polygons != polygons)
      std::cerr << "polygon counts differ: " << inline_polygons << " vs " << polygons << "\n";
  }
  nlohmann::json row = {{"benchmark", "mesh_instancing"},
                        {"mesh_faces", raw.faces.size()},
                        {"mesh_vertices", raw.vertices.size()},
                        {"copies", copies},
                        {"polygons", polygons},
                        {"runs", runs},
                        {"ref_cold_ms", median(cold)},
                        {"ref_warm_ms", median(warm)},
                        {"inline_ms", median(inlined)}};
  std::cout << row.dump() << "\n";
  std::ofstream(out_path) << row.dump(2) << "\n";
}

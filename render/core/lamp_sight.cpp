#include "render/core/lamp_sight.hpp"

#include "render/core/parallel.hpp"
#include "render/core/shadow.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace rr {

CellViewpoint lamp_face_view(Vec3 position, size_t face) {
  constexpr double near_m = 1e-4, far_m = 1e6, margin = 1e-6;
  const shadow_detail::CubeFace& f = shadow_detail::cube_faces[face];
  CellViewpoint viewpoint;
  viewpoint.eye = position;
  viewpoint.reach = near_m * std::sqrt(3.0);
  viewpoint.clip_from_world =
      glm::perspective(0.5 * std::numbers::pi, 1.0, near_m, far_m) * glm::lookAt(position, position + f.forward, f.up);
  viewpoint.margin_x = viewpoint.margin_y = margin;
  return viewpoint;
}

std::vector<LampFaceWalk> walk_from_lamp(const SceneCells& cells, const CellConditions& conditions, Vec3 position) {
  thread_local CellWalk walk;
  std::vector<LampFaceWalk> out;
  for (size_t face = 0; face < shadow_detail::cube_faces.size(); ++face) {
    walk_cells(cells, conditions, lamp_face_view(position, face), walk);
    LampFaceWalk& kept = out.emplace_back();
    kept.everything = walk.everything;
    if (kept.everything) break;
    kept.reached = walk.reached;
    kept.regions.resize(cells.cells.size());
    for (size_t c = 0; c < cells.cells.size(); ++c) {
      if (walk.reached[c]) kept.regions[c] = bounding_region(walk, c);
    }
  }
  return out;
}

double lamp_tolerance(Vec3 lo, Vec3 hi) { return 1e-7 * glm::length(hi - lo) + 1e-9; }

std::vector<std::vector<uint32_t>> lamp_fixtures(const PolygonSoup& soup, std::span<const Light> lights) {
  std::vector<std::vector<uint32_t>> held(soup.objects.size());  // per object: the lamps it holds
  bool any_held = false;
  for (uint32_t l = 0; l < lights.size(); ++l) {
    if (lights[l].type != LightType::point) continue;
    const Vec3 p = lights[l].position;
    for (uint32_t o = 0; o < soup.objects.size(); ++o) {
      const SceneObject& object = soup.objects[o];
      if (object.bounded && glm::all(glm::lessThan(object.lo, p)) && glm::all(glm::lessThan(p, object.hi))) {
        held[o].push_back(l), any_held = true;
      }
    }
  }
  std::vector<std::vector<uint32_t>> fixture(lights.size());
  for (uint32_t j = 0; any_held && j < soup.polygons.size(); ++j) {
    for (uint32_t l : held[soup.polygons[j].object]) fixture[l].push_back(j);
  }
  return fixture;
}

size_t PreparedLamps::bytes() const {
  size_t out = sizeof(PreparedLamps) + conditions.ceilings_drawn.capacity() + conditions.object_drawn.capacity() +
               lamps.capacity() * sizeof(Lamp);
  for (const Lamp& lamp : lamps) {
    out += lamp.faces.capacity() * sizeof(LampFaceWalk) + lamp.fixture.bits.capacity() * sizeof(uint64_t);
    for (const LampFaceWalk& face : lamp.faces)
      out += face.reached.capacity() + face.regions.capacity() * sizeof(ViewRegion);
  }
  return out;
}

PreparedLamps prepare_lamps(const PolygonSoup& soup, const SceneCells& cells, std::span<const Light> lights,
                            unsigned threads) {
  PreparedLamps out;
  if (soup.positions.empty()) return out;
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  out.tolerance = lamp_tolerance(lo, hi);
  out.conditions = cell_conditions(cells, {});
  const bool walks = cells.derived() && cells.serial != 0 && out.conditions.valid;
  if (walks) out.cells = cells.serial;
  const std::vector<std::vector<uint32_t>> fixtures = lamp_fixtures(soup, lights);
  out.lamps.resize(lights.size());
  parallel_for(threads, lights.size(), [&](size_t l, unsigned) {
    if (lights[l].type != LightType::point) return;
    PreparedLamps::Lamp& lamp = out.lamps[l];
    lamp.point = true;
    lamp.position = lights[l].position;
    if (walks) lamp.faces = walk_from_lamp(cells, out.conditions, lamp.position);
    if (!fixtures[l].empty())
      lamp.fixture = fixture_map(soup, fixtures[l], lights[l], out.tolerance, lamp_fixture_bins);
  });
  return out;
}

}  // namespace rr

// The scenes and seeded cameras of the occlusion-culling identity checks (tests/unit/test_culling.cpp,
// a CI subset) and of their full matrix (bench/culling.cpp). Scenes: the example requests, the Sweet
// Home 3D homes imported with their furniture models as the service imports them, R2V plans and the
// fireplace room OBJ from ../shared/data (absent data: those scenes are left out). Cameras: the
// request's own, then seeded ones of four kinds: inside a room at eye height, in a doorway looking
// through it, outside looking in, and aerial. A seed gives the same cameras on every run.
#pragma once

#include "render/import/import_files.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace rr::testing {

struct CullingScene {
  std::string name;
  RenderRequest request;  // as parsed from the example or the imported request
};

// `which`: "examples" (from the repository `root`), "homes", "r2v", "fireplace" (from `data`, the
// shared data folder, when there is one). `only`: scene names to keep (empty: all).
inline std::vector<CullingScene> culling_scenes(const std::string& which, const std::filesystem::path& root,
                                                const std::optional<std::filesystem::path>& data,
                                                const std::vector<std::string>& only = {}) {
  std::vector<CullingScene> out;
  auto wanted = [&](const std::string& name) {
    return only.empty() || std::find(only.begin(), only.end(), name) != only.end();
  };
  std::vector<std::filesystem::path> files;
  std::filesystem::path dir = root / "examples";
  if (which != "examples") {
    if (!data) return out;
    dir = which == "homes" ? *data / "floorplans" / "sweethome3d"
          : which == "r2v" ? *data / "floorplans" / "r2v"
                           : *data / "meshes" / "fireplace_room";
  }
  if (!std::filesystem::is_directory(dir)) return out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if ((which == "examples" && ext == ".json") || (which == "homes" && ext == ".xml") ||
        (which == "r2v" && ext == ".txt" && e.path().stem().string().starts_with("r2v_")) ||
        (which == "fireplace" && e.path().filename() == "fireplace_room.obj")) {
      files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const std::string name = f.stem().string();
    if (!wanted(name)) continue;
    if (which == "examples") {
      std::ifstream in(f, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      out.push_back({name, request_from_json(nlohmann::json::parse(text.str()))});
      continue;
    }
    ImportOptions options;
    options.furniture_models = which == "homes";  // as the service imports them
    out.push_back({name, request_from_json(import_path(f, std::nullopt, options).request)});
  }
  return out;
}

struct SeededCamera {
  std::string kind;  // "own", "inside", "doorway", "outside", "aerial"
  Camera camera;
};

// `per_kind` cameras of each seeded kind (kinds a scene cannot have, such as doorways without doors,
// fall back to inside views), after the request's own camera.
// `kinds` keeps the first `kinds` of inside, doorway, outside, aerial (1: the benchmark's eye level).
inline std::vector<SeededCamera> seeded_cameras(const RenderRequest& request, const PolygonSoup& soup, uint64_t seed,
                                                int per_kind, int kinds = 4) {
  std::vector<SeededCamera> out{{"own", request.camera}};
  Vec3 lo(1e300), hi(-1e300);
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (soup.positions.empty()) return out;
  std::mt19937_64 rng(seed);
  auto uniform = [&](double a, double b) { return a + (b - a) * double(rng() >> 11) * (1.0 / 9007199254740992.0); };
  const StaticGeometry& g = request.scene.geometry;
  const Vec3 centre = 0.5 * (lo + hi), size = hi - lo;
  const double extent = std::max({size.x, size.z, 1.0});
  auto make = [&](Vec3 eye, Vec3 target, double near) {
    Camera c = request.camera;
    c.frame_all = false;
    c.position = eye, c.target = target, c.up = Vec3(0.0, 1.0, 0.0);
    c.fov_y_deg = uniform(45.0, 75.0);
    c.near = near, c.far = std::max(50.0, 3.0 * glm::length(size));
    return c;
  };
  auto inside = [&]() {
    const double yaw = uniform(0.0, 6.283185307179586);
    Vec3 eye;
    if (!g.rooms.empty()) {
      const Room& room = g.rooms[size_t(rng() % g.rooms.size())];
      Vec2 c(0.0);
      for (const Vec2& p : room.points) c += p;
      c /= double(std::max<size_t>(1, room.points.size()));
      // A point between the centroid and a random corner: inside for rooms that are not too concave.
      const Vec2 corner = room.points.empty() ? c : room.points[size_t(rng() % room.points.size())];
      const Vec2 p = c + uniform(0.0, 0.6) * (corner - c);
      eye = Vec3(p.x, room.elevation + uniform(1.2, 1.75), p.y);
    } else {
      eye = Vec3(uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z));
      eye = centre + 0.6 * (eye - centre);
    }
    return make(eye, eye + Vec3(std::cos(yaw), uniform(-0.25, 0.1), std::sin(yaw)), 0.05);
  };
  std::vector<std::pair<const Wall*, const Opening*>> doors;
  for (const Wall& w : g.walls) {
    for (const Opening& o : w.openings) {
      if (o.type == OpeningType::door) doors.push_back({&w, &o});
    }
  }
  for (int i = 0; i < per_kind; ++i) out.push_back({"inside", inside()});
  if (kinds < 2) return out;
  for (int i = 0; i < per_kind; ++i) {
    if (doors.empty()) {
      out.push_back({"doorway", inside()});
      continue;
    }
    const auto [wall, door] = doors[size_t(rng() % doors.size())];
    const Vec2 along = glm::normalize(wall->end - wall->start), normal(-along.y, along.x);
    const Vec2 mid = wall->start + along * (door->offset + 0.5 * door->width);
    const double side = (rng() & 1) ? 1.0 : -1.0;
    const Vec2 eye2 = mid + normal * (side * uniform(0.3, 0.8)), look = mid - normal * (side * 3.0);
    double base = wall->base;
    if (wall->level >= 0 && size_t(wall->level) < g.levels.size()) base += g.levels[size_t(wall->level)].elevation;
    const double y = base + uniform(1.3, 1.7);
    out.push_back({"doorway", make(Vec3(eye2.x, y, eye2.y), Vec3(look.x, y - 0.2, look.y), 0.05)});
  }
  if (kinds < 3) return out;
  for (int i = 0; i < per_kind; ++i) {
    const double yaw = uniform(0.0, 6.283185307179586), d = uniform(0.6, 1.0) * extent;
    const Vec3 eye = centre + Vec3(d * std::cos(yaw), 0.0, d * std::sin(yaw));
    out.push_back({"outside", make(Vec3(eye.x, lo.y + uniform(1.2, 3.0), eye.z), centre, 0.1)});
  }
  if (kinds < 4) return out;
  for (int i = 0; i < per_kind; ++i) {
    const double yaw = uniform(0.0, 6.283185307179586), d = uniform(0.1, 0.5) * extent;
    const Vec3 eye = centre + Vec3(d * std::cos(yaw), 0.0, d * std::sin(yaw));
    out.push_back({"aerial", make(Vec3(eye.x, hi.y + uniform(0.5, 1.0) * extent, eye.z), centre, 0.1)});
  }
  return out;
}

}  // namespace rr::testing

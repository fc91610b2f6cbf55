// Shared by the stress tests: seeded random rooms and object soups as requests, rendering one
// tessellated scene with several pipelines (optionally moved and scaled as a whole), and the
// per-frame checks. Seeds come from testing::test_seeds (ROOMRENDER_TEST_SEED replays one).
#pragma once

#include "render/core/error_metrics.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/render_modes.hpp"
#include "support/soup_builder.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <random>
#include <string>

namespace rr::stress {

using nlohmann::json;

inline double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// A room of w x d metres: a tiled floor, four walls with opaque doors and windows (so visibility is
// one id per pixel in every pipeline), 3..8 boxes, cylinders and pyramids placed freely (they may
// intersect each other and the walls), a directional light and a camera inside looking at a
// random point.
inline json random_room(std::mt19937& rng) {
  const double w = uniform(rng, 3.0, 8.0), d = uniform(rng, 3.0, 8.0), h = uniform(rng, 2.2, 3.2);
  json walls = json::array();
  const double corners[5][2] = {{0, 0}, {w, 0}, {w, d}, {0, d}, {0, 0}};
  for (int k = 0; k < 4; ++k) {
    const double length = std::hypot(corners[k + 1][0] - corners[k][0], corners[k + 1][1] - corners[k][1]);
    json openings = json::array();
    // A door in the first half, a window in the second: openings never overlap.
    if (rng() % 2)
      openings.push_back({{"type", "door"}, {"offset", uniform(rng, 0.2, length / 2 - 1.0)}, {"width", 0.9}});
    if (rng() % 2) {
      openings.push_back(
          {{"type", "window"}, {"offset", uniform(rng, length / 2, length - 1.2)}, {"width", 1.0}, {"opacity", 1.0}});
    }
    walls.push_back({{"start", {corners[k][0], corners[k][1]}},
                     {"end", {corners[k + 1][0], corners[k + 1][1]}},
                     {"height", h},
                     {"openings", openings}});
  }
  json solids = json::array();
  const int n = 3 + int(rng() % 6);
  for (int i = 0; i < n; ++i) {
    const json center = {uniform(rng, 0.5, w - 0.5), uniform(rng, 0.5, d - 0.5)};
    const double base = rng() % 3 ? 0.0 : uniform(rng, 0.2, 1.2);
    switch (rng() % 3) {
      case 0:
        solids.push_back({{"type", "box"},
                          {"center", center},
                          {"base", base},
                          {"rotation_y", uniform(rng, 0, 90)},
                          {"size", {uniform(rng, 0.3, 1.5), uniform(rng, 0.3, 1.5), uniform(rng, 0.3, 1.5)}}});
        break;
      case 1:
        solids.push_back({{"type", "cylinder"},
                          {"center", center},
                          {"base", base},
                          {"radius", uniform(rng, 0.1, 0.6)},
                          {"height", uniform(rng, 0.3, 2.0)},
                          {"segments", 6 + int(rng() % 20)}});
        break;
      default:
        solids.push_back({{"type", "pyramid"},
                          {"center", center},
                          {"base", base},
                          {"rotation_y", uniform(rng, 0, 90)},
                          {"size", {uniform(rng, 0.3, 1.5), uniform(rng, 0.3, 1.5), uniform(rng, 0.3, 1.5)}}});
    }
  }
  const json eye = {uniform(rng, 0.3, w - 0.3), uniform(rng, 0.8, h - 0.3), uniform(rng, 0.3, d - 0.3)};
  const json target = {uniform(rng, 0.0, w), uniform(rng, 0.0, 1.5), uniform(rng, 0.0, d)};
  return {{"scene",
           {{"floor", {{"cells", {int(std::ceil(w)), int(std::ceil(d))}}}},
            {"walls", walls},
            {"solids", solids},
            {"lights", {{{"type", "directional"}, {"direction", {0.3, -1.0, 0.4}}}}}}},
          {"camera", {{"position", eye}, {"target", target}, {"fov_y", uniform(rng, 50, 90)}}},
          {"options", {{"width", 160}, {"height", 120}}}};
}

// n random triangles (an open mesh) in a 4 m cube, crossing each other freely, seen from outside.
inline json random_soup(std::mt19937& rng, int n) {
  json vertices = json::array(), faces = json::array();
  while (int(faces.size()) < n) {
    const Vec3 c(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2));
    Vec3 p[3];
    for (Vec3& v : p) v = c + Vec3(uniform(rng, -1.2, 1.2), uniform(rng, -1.2, 1.2), uniform(rng, -1.2, 1.2));
    if (glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) < 0.1) continue;  // no slivers here
    const size_t first = vertices.size();
    for (const Vec3& v : p) vertices.push_back({v.x, v.y, v.z});
    faces.push_back({first, first + 1, first + 2});
  }
  const double a = uniform(rng, 0, 2 * pi);
  const json mesh = {{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}};
  return {{"scene", {{"solids", json::array({mesh})}}},
          {"camera", {{"position", {9 * std::cos(a), uniform(rng, -3, 3), 9 * std::sin(a)}}, {"target", {0, 0, 0}}}},
          {"options", {{"width", 160}, {"height", 120}}}};
}

// One tessellated request, rendered by any pipeline with any painter key; `place` moves and
// scales the whole world (geometry, camera, lights, near/far) as x -> scale * x + offset.
struct StressScene {
  RenderRequest request;
  PolygonSoup soup;

  explicit StressScene(const json& r) : request(request_from_json(r)), soup(tessellate(request.scene.geometry)) {}

  void place(double scale, Vec3 offset) {
    for (Vec3& p : soup.positions) p = scale * p + offset;
    for (Polygon& poly : soup.polygons) poly.offset = glm::dot(poly.normal, soup.positions[poly.first_vertex]);
    Camera& c = request.camera;
    c.position = scale * c.position + offset;
    c.target = scale * c.target + offset;
    c.near *= scale;
    c.far *= scale;
    for (Light& l : request.scene.lights) l.position = scale * l.position + offset;
  }

  Frame render(const std::string& pipeline, PainterKey key = PainterKey::mean) const {
    RenderOptions options = request.options;
    options.pipeline = pipeline_id(pipeline);
    options.painter_key = key;
    return render_frame(request.scene, soup, request.camera, options).frame;
  }

  // Drawn by a row of testing::exact_pipelines() in its exact mode.
  Frame render_exact(const PipelineInfo& pipeline) const { return run_exact(pipeline).frame; }
  RenderResult run_exact(const PipelineInfo& pipeline) const {
    return render_frame(request.scene, soup, request.camera, testing::exact_options(pipeline, request.options));
  }
};

// Replay hint for failure messages.
inline std::string seed_note(unsigned seed) {
  return "seed " + std::to_string(seed) + " (replay with ROOMRENDER_TEST_SEED=" + std::to_string(seed) + ")";
}

}  // namespace rr::stress

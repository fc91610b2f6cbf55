// Coplanar overlaps: tessellation groups polygons that overlap in one plane (and only those), and
// every exact pipeline (PipelineInfo::exact_mode; bsp in both traversals) shows the reference's
// polygon (the lowest id of a plane group) at every pixel off the reference's id edges, for two
// differently triangulated overlapping squares and for seeded random stacks of coplanar polygons.
#include "render/core/coplanar.hpp"
#include "render/core/error_metrics.hpp"
#include "support/render_helpers.hpp"
#include "support/render_modes.hpp"
#include "support/soup_builder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rr {
namespace {

using nlohmann::json;

struct Exact {
  std::string name;
  const PipelineInfo* pipeline;
  json options;  // set before the pipeline's exact mode
};

// Every exact pipeline in its exact mode, and the bsp walk in its other settings.
std::vector<Exact> exact_modes() {
  std::vector<Exact> modes;
  for (const PipelineInfo* p : testing::exact_pipelines(false)) modes.push_back({p->name, p, json::object()});
  const PipelineInfo* bsp = find_pipeline("bsp");
  modes.push_back({"bsp back_to_front", bsp, {{"bsp", {{"traversal", "back_to_front"}}}}});
  modes.push_back({"bsp epsilon 0", bsp, {{"bsp", {{"epsilon", 0.0}}}}});
  return modes;
}

testing::SceneRender render_with(json request, const json& options) {
  for (auto& [key, value] : options.items()) request["options"][key] = value;
  return testing::render_json(request);
}

testing::SceneRender render_exact(json request, const Exact& mode) {
  for (auto& [key, value] : mode.options.items()) request["options"][key] = value;
  testing::SceneRender out;
  out.request = request_from_json(request);
  out.request.options = testing::exact_options(*mode.pipeline, out.request.options);
  out.soup = tessellate(out.request.scene.geometry);
  out.result = render_frame(out.request.scene, out.soup, out.request.camera, out.request.options);
  return out;
}

// Non-edge pixels of each exact pipeline that differ from the reference; also checks that the
// reference's frame is not empty.
void expect_exact(const json& request, const std::string& what) {
  const testing::SceneRender truth = render_with(request, {{"pipeline", "reference"}});
  size_t covered = 0;
  for (uint32_t id : truth.result.frame.ids.ids) covered += id != background_id;
  ASSERT_GT(covered, 500u) << what;
  for (const Exact& e : exact_modes()) {
    const testing::SceneRender r = render_exact(request, e);
    const VisibilityError err = visibility_error(truth.result.frame.ids, r.result.frame.ids);
    EXPECT_EQ(err.non_edge_differing, 0u) << what << ", " << e.name << ": " << err.non_edge_differing << " of "
                                          << err.non_edge_pixels << " non-edge pixels differ from the reference";
  }
}

// A point of the tilted plane through `c` spanned by the unit vectors e1, e2.
json at(Vec3 c, Vec3 e1, Vec3 e2, double u, double v) {
  const Vec3 p = c + u * e1 + v * e2;
  return {p.x, p.y, p.z};
}

const Vec3 kCentre(0.1, 0.3, -0.2);
const Vec3 kE1 = glm::normalize(Vec3(1.0, 0.3, 0.1));
const Vec3 kE2 = glm::normalize(glm::cross(glm::normalize(Vec3(0.2, 1.0, 0.45)), kE1));

// A square [u0, u0+s] x [v0, v0+s] of the tilted plane as two triangles split along one diagonal.
json square_mesh(double u0, double v0, double s, bool other_diagonal) {
  json vertices = json::array();
  for (auto [u, v] : {std::pair{u0, v0}, {u0 + s, v0}, {u0 + s, v0 + s}, {u0, v0 + s}}) {
    vertices.push_back(at(kCentre, kE1, kE2, u, v));
  }
  const json faces = other_diagonal ? json{{0, 1, 3}, {1, 2, 3}} : json{{0, 1, 2}, {0, 2, 3}};
  return {{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}};
}

json two_squares() {
  const Vec3 normal = glm::cross(kE1, kE2);
  const Vec3 eye = kCentre + 4.0 * normal + Vec3(0.7, 0.4, 0.3);
  return {
      {"scene", {{"solids", {square_mesh(-1.0, -1.0, 1.6, false), square_mesh(-0.5, -0.4, 1.6, true)}}}},
      {"camera", {{"position", {eye.x, eye.y, eye.z}}, {"target", {kCentre.x, kCentre.y, kCentre.z}}, {"fov_y", 50}}},
      {"options", {{"width", 200}, {"height", 150}}}};
}

TEST(Coplanar, OverlappingSquaresFormOneGroupAndTheirOwnHalvesDoNot) {
  const RenderRequest request = request_from_json(two_squares());
  const PolygonSoup soup = tessellate(request.scene.geometry);
  ASSERT_EQ(soup.polygons.size(), 4u);
  for (const Polygon& p : soup.polygons) EXPECT_EQ(p.plane_group, 1u) << "polygon " << p.id;

  // One square alone: its two triangles share an edge but do not overlap, so no group.
  json one = two_squares();
  one["scene"]["solids"].erase(1);
  const PolygonSoup alone = tessellate(request_from_json(one).scene.geometry);
  for (const Polygon& p : alone.polygons) EXPECT_EQ(p.plane_group, 0u) << "polygon " << p.id;

  // A parallel square 1 mm off the plane overlaps on screen but is not coplanar.
  json lifted = two_squares();
  const Vec3 n = glm::cross(kE1, kE2);
  for (json& v : lifted["scene"]["solids"][1]["vertices"]) {
    for (int k = 0; k < 3; ++k) v[k] = v[k].get<double>() + 1e-3 * n[k];
  }
  for (const Polygon& p : tessellate(request_from_json(lifted).scene.geometry).polygons) EXPECT_EQ(p.plane_group, 0u);
}

// The same squares built 10^7 m from the origin (the coordinate limit), where doubles are 1.9e-9 m
// apart and each triangle's computed plane differs from the others' in far more than the last bits.
json two_squares_moved(Vec3 offset) {
  json request = two_squares();
  for (json& solid : request["scene"]["solids"]) {
    for (json& v : solid["vertices"]) {
      for (int k = 0; k < 3; ++k) v[k] = v[k].get<double>() + offset[k];
    }
  }
  for (const char* key : {"position", "target"}) {
    for (int k = 0; k < 3; ++k) request["camera"][key][k] = request["camera"][key][k].get<double>() + offset[k];
  }
  return request;
}

TEST(Coplanar, OverlappingSquaresFarFromTheOriginStillFormOneGroup) {
  const json request = two_squares_moved(Vec3(7e6, 1e3, -9.9e6));
  const PolygonSoup soup = tessellate(request_from_json(request).scene.geometry);
  ASSERT_EQ(soup.polygons.size(), 4u);
  for (const Polygon& p : soup.polygons) EXPECT_EQ(p.plane_group, 1u) << "polygon " << p.id;
  expect_exact(request, "two squares near 1e7 m");
}

TEST(Coplanar, OverlappingSquaresOfDifferentTriangulationsShowTheLowerIdEverywhere) {
  const json request = two_squares();
  const testing::SceneRender truth = render_with(request, {{"pipeline", "reference"}});
  // The overlap (u, v in [-0.5, 0.6] x [-0.4, 0.6]) shows the first square (ids 0 and 1) in the
  // reference: its centre's pixel.
  const Vec3 middle = kCentre + 0.05 * kE1 + 0.1 * kE2;
  const Vec4 clip = truth.view.clip_from_world * Vec4(middle, 1.0);
  const int x = int((clip.x / clip.w + 1.0) * 0.5 * 200), y = int((1.0 - clip.y / clip.w) * 0.5 * 150);
  EXPECT_LE(truth.result.frame.ids.ids[size_t(y * 200 + x)], 1u);
  expect_exact(request, "two squares");
}

// A random convex polygon of `n` corners around (u, v) in a plane, as one face or as a fan.
void add_stack_polygon(std::mt19937& rng, Vec3 c, Vec3 e1, Vec3 e2, json& solids) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int n = 3 + int(unit(rng) * 4);
  std::vector<double> angles;
  for (int k = 0; k < n; ++k) angles.push_back(unit(rng) * 2.0 * M_PI);
  std::sort(angles.begin(), angles.end());
  const double u = unit(rng) - 0.5, v = unit(rng) - 0.5, radius = 0.8 + 0.8 * unit(rng);
  json vertices = json::array(), faces = json::array();
  for (double a : angles) vertices.push_back(at(c, e1, e2, u + radius * std::cos(a), v + radius * std::sin(a)));
  if (unit(rng) < 0.5) {
    json face = json::array();
    for (int k = 0; k < n; ++k) face.push_back(k);
    faces.push_back(face);
  } else {  // a fan from a random corner: another triangulation of the same plane
    const int first = int(unit(rng) * n);
    for (int k = 1; k + 1 < n; ++k) faces.push_back({first, (first + k) % n, (first + k + 1) % n});
  }
  solids.push_back({{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}});
}

json random_stacks(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  json solids = json::array();
  for (int plane = 0; plane < 3; ++plane) {
    const Vec3 normal = glm::normalize(Vec3(unit(rng), 2.5 + 0.5 * unit(rng), unit(rng)));
    const Vec3 e1 = glm::normalize(glm::cross(normal, Vec3(0.3, 0.1, 1.0)));
    const Vec3 e2 = glm::cross(normal, e1);
    const Vec3 c(unit(rng), 0.6 * unit(rng), unit(rng));
    for (int k = 0; k < 4; ++k) add_stack_polygon(rng, c, e1, e2, solids);
  }
  const double a = M_PI * unit(rng);
  return {
      {"scene", {{"solids", solids}}},
      {"camera", {{"position", {3.5 * std::cos(a), 4.5 + 0.5 * unit(rng), 3.5 * std::sin(a)}}, {"target", {0, 0, 0}}}},
      {"options", {{"width", 160}, {"height", 120}}}};
}

TEST(Coplanar, RandomCoplanarStacksMatchTheReferenceInEveryExactPipeline) {
  const auto seeds = testing::test_seeds(1700, 12);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    const json request = random_stacks(rng);
    size_t grouped = 0;
    for (const Polygon& p : tessellate(request_from_json(request).scene.geometry).polygons)
      grouped += p.plane_group != 0;
    EXPECT_GT(grouped, 0u) << "seed " << seed;
    expect_exact(request,
                 "seed " + std::to_string(seed) + " (replay with ROOMRENDER_TEST_SEED=" + std::to_string(seed) + ")");
  }
}

}  // namespace
}  // namespace rr

// Shadow maps against exact shadows: a box on a floor under a directional light and under a point
// light (its shadow crosses cube faces), ray cast per pixel; self-shadowing (acne) at a grazing
// light; the gap at a box's base (peter-panning); when the pass is skipped; the memory bound; no
// sunlight inside a closed room, with maps and rays; with a doorway open, exactly its patch lit; with a
// glazed window, its patch lit by what the pane lets through.
// The floor is one grey #808080 cell, ambient 0.2, flat shading and pcf 1, so a floor pixel is
// either lit or at the ambient value and the threshold between them classifies it.
#include "render/core/shadow.hpp"
#include "render/core/tessellate.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/scene_io/report_json.hpp"
#include "support/render_helpers.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace rr {
namespace {

// report_json of a report holding only these timings and stats, as text.
std::string report_text(const StageTimings& timings, const RenderStats& stats) {
  RenderReport report;
  report.timings = timings;
  report.stats = stats;
  return report_json(report).dump();
}

using nlohmann::json;
using testing::render_json;
using testing::SceneRender;

constexpr double kAmbientLevel = 128.0 * 0.2;  // a shadowed floor pixel

json box_on_floor(json light, double floor_size = 12.0) {
  return {{"scene",
           {{"ambient", {{"intensity", 0.2}}},
            {"floor",
             {{"origin", {-floor_size / 2, -floor_size / 2}},
              {"cells", {1, 1}},
              {"cell_size", floor_size},
              {"colors", {"#808080", "#808080"}}}},
            {"solids", {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1.5, 1}}, {"color", "#3060c0"}}}},
            {"lights", {std::move(light)}}}},
          {"camera", {{"position", {-1, 4.5, 4}}, {"target", {0.8, 0, 0.3}}}},
          {"options", {{"width", 640}, {"height", 480}, {"shadows", true}}}};
}

struct ShadowComparison {
  size_t floor_pixels = 0, exact_area = 0, rendered_area = 0, mismatched = 0;
  double worst_distance = 0.0;  // of a mismatched pixel from the exact shadow's boundary, pixels
  Vec2 exact_centroid{0.0}, rendered_centroid{0.0};
};

// Pixels classified twice, `truth` (exact) and `drawn` (rendered), 1 or 0, -1 where neither applies
// (row-major, `w` wide): how many differ and the farthest of those from the exact boundary, the
// classified pixels with a 4-neighbour of the other class or one for which edge(neighbour) holds.
struct Misplaced {
  size_t pixels = 0, drawn_outside = 0;  // drawn_outside: drawn 1 where the truth is 0
  double worst_distance = 0.0;           // pixels
};
template <class Edge>
Misplaced misplaced(const std::vector<int>& truth, const std::vector<int>& drawn, int w, Edge&& edge) {
  const int h = int(truth.size() / size_t(w));
  std::vector<Vec2> boundary;
  for (int y = 1; y + 1 < h; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      if (truth[i] < 0) continue;
      for (long n : {-1L, 1L, -long(w), long(w)}) {
        const size_t j = size_t(long(i) + n);
        if ((truth[j] >= 0 && truth[j] != truth[i]) || edge(j)) {
          boundary.push_back({x, y});
          break;
        }
      }
    }
  }
  Misplaced m;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] < 0 || truth[i] == drawn[i]) continue;
    ++m.pixels;
    m.drawn_outside += size_t(drawn[i] == 1 && truth[i] == 0);
    const Vec2 at(double(i % size_t(w)), double(i / size_t(w)));
    double nearest = 1e9;
    for (const Vec2& b : boundary) nearest = std::min(nearest, glm::length(b - at));
    m.worst_distance = std::max(m.worst_distance, nearest);
  }
  return m;
}

// Classifies every floor pixel of `r` (lit vs shadowed, threshold halfway between `lit` and the
// ambient level) and compares with `exact(p)` at the pixel's ray-cast floor point.
template <class Exact, class LitLevel>
ShadowComparison compare_shadow(const SceneRender& r, Exact&& exact, LitLevel&& lit) {
  const int w = r.view.width, h = r.view.height;
  std::vector<int> truth(size_t(w * h), -1), drawn(size_t(w * h), -1);  // -1: not the floor
  ShadowComparison c;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (r.result.frame.ids.at(x, y) != 0) continue;  // polygon 0 is the floor cell
      auto p = testing::pixel_on_plane(r.view, x, y, {0, 1, 0}, 0.0);
      if (!p) continue;
      const double level = lit(x, y, *p);
      if (level - kAmbientLevel < 16.0) continue;  // too dim to tell lit from shadowed
      const size_t i = size_t(y * w + x);
      truth[i] = exact(*p) ? 1 : 0;
      drawn[i] = testing::channel(r.result.frame.image, x, y) < 0.5 * (level + kAmbientLevel) ? 1 : 0;
      ++c.floor_pixels;
      c.exact_area += size_t(truth[i]);
      c.rendered_area += size_t(drawn[i]);
      c.exact_centroid += double(truth[i]) * Vec2(x, y);
      c.rendered_centroid += double(drawn[i]) * Vec2(x, y);
    }
  }
  c.exact_centroid /= double(std::max<size_t>(1, c.exact_area));
  c.rendered_centroid /= double(std::max<size_t>(1, c.rendered_area));
  // The exact boundary also runs along the box's outline, where the shadow starts at the base:
  // sampling the map there is as coarse as at any other shadow edge.
  const Misplaced m = misplaced(truth, drawn, w, [&](size_t n) {
    const uint32_t id = r.result.frame.ids.ids[n];
    return id != 0 && id != background_id;
  });
  c.mismatched = m.pixels;
  c.worst_distance = m.worst_distance;
  return c;
}

void expect_matches_exact(const ShadowComparison& c, double max_distance_px) {
  ASSERT_GT(c.exact_area, 5000u);
  std::cout << "shadow area " << c.exact_area << " exact, " << c.rendered_area << " rendered; " << c.mismatched
            << " pixels differ, at most " << c.worst_distance << " px from the exact boundary\n";
  // Area within 1 %, centroid within half a pixel, and every misclassified pixel on the boundary
  // (the exact shadow's edge, or the box's outline).
  EXPECT_NEAR(double(c.rendered_area), double(c.exact_area), 0.01 * double(c.exact_area));
  EXPECT_LE(glm::length(c.rendered_centroid - c.exact_centroid), 0.5);
  EXPECT_LE(c.worst_distance, max_distance_px) << c.mismatched << " mismatched pixels";
}

const Vec3 kBoxLo{-0.5, 0.0, -0.5}, kBoxHi{0.5, 1.5, 0.5};

TEST(Shadow, DirectionalShadowOfABoxMatchesTheRayCastShadow) {
  const Vec3 travel = glm::normalize(Vec3(1.0, -0.8, 0.5));
  auto r = render_json(box_on_floor({{"type", "directional"}, {"direction", {1.0, -0.8, 0.5}}}));
  ASSERT_FALSE(r.result.stats.shadow_skipped);
  const double lit = 128.0 * (0.2 + -travel.y);
  auto c = compare_shadow(
      r, [&](Vec3 p) { return testing::ray_hits_box(p, -travel, kBoxLo, kBoxHi); },
      [&](int, int, Vec3) { return lit; });
  // pcf 1 at 2048^2: a texel is ~5 mm here, a pixel ~10 mm, so only pixels the exact boundary
  // passes through (or touches) may differ.
  expect_matches_exact(c, 1.0);
}

TEST(Shadow, PointLightShadowAcrossCubeFacesMatchesTheRayCastShadow) {
  // From the light at (-1.5, 3, -1) the shadow starts in the -Y face and ends in the +X face.
  const Vec3 light{-1.5, 3.0, -1.0};
  json request = box_on_floor({{"type", "point"}, {"position", {light.x, light.y, light.z}}, {"intensity", 1.5}});
  auto r = render_json(request);
  ASSERT_FALSE(r.result.stats.shadow_skipped);
  request["options"]["shadows"] = false;
  auto unshadowed = render_json(request);
  auto c = compare_shadow(
      r, [&](Vec3 p) { return testing::ray_hits_box(p, light - p, kBoxLo, kBoxHi); },
      [&](int x, int y, Vec3) { return double(testing::channel(unshadowed.result.frame.image, x, y)); });
  expect_matches_exact(c, 1.0);
}

// A floor lit at `elevation_deg` above the horizon, with a box hidden under it: the box is a
// receiver the camera's frustum holds, so the floor becomes a caster and meets its own depth.
SceneRender grazing_floor(double elevation_deg, double azimuth_deg, int pcf, double extra_bias) {
  const double e = radians(elevation_deg), a = radians(azimuth_deg);
  json request = box_on_floor(
      {{"type", "directional"}, {"direction", {std::cos(e) * std::cos(a), -std::sin(e), std::cos(e) * std::sin(a)}}},
      30.0);
  request["scene"]["solids"][0] = {{"type", "box"}, {"center", {0, 0}}, {"base", -3}, {"size", {1, 1, 1}}};
  request["options"]["shadow"] = {{"pcf", pcf}, {"bias", extra_bias}, {"slope_bias", extra_bias}};
  return render_json(request);
}

double acne_share(const SceneRender& r, double elevation_deg) {
  const double lit = 128.0 * (0.2 + std::sin(radians(elevation_deg)));
  size_t floor = 0, dark = 0;
  for (int y = 0; y < r.view.height; ++y) {
    for (int x = 0; x < r.view.width; ++x) {
      if (r.result.frame.ids.at(x, y) != 0) continue;
      ++floor;
      dark += testing::channel(r.result.frame.image, x, y) < 0.5 * (lit + kAmbientLevel);
    }
  }
  EXPECT_GT(floor, 100000u);
  return double(dark) / double(floor);
}

TEST(Shadow, FloorAtAGrazingLightDoesNotShadowItself) {
  for (double azimuth : {0.0, 33.0}) {
    for (int pcf : {1, 3, 5}) {
      SCOPED_TRACE("azimuth " + std::to_string(azimuth) + ", pcf " + std::to_string(pcf));
      auto r = grazing_floor(10.0, azimuth, pcf, 0.0);
      ASSERT_FALSE(r.result.stats.shadow_skipped);
      EXPECT_LT(acne_share(r, 10.0), 0.001);
    }
  }
  // Control: without the constant and slope biases the same floor does show acne, so the floor
  // really is in the map and the biases are what keep it clean.
  auto r = grazing_floor(10.0, 33.0, 1, -shadow_default_bias);
  EXPECT_GT(acne_share(r, 10.0), 0.05);
}

TEST(Shadow, BoxOnTheFloorCastsFromItsBaseWithoutAGap) {
  // Light at 45 degrees along +X onto a 1 m cube: the shadow covers x in (0.5, 1.5) at z = 0. The
  // first shadowed floor point beyond the base may be at most 1.5 texels from it (sampled every
  // 0.1 mm up to 0.9 m, short of the shadow's far end).
  json request = box_on_floor({{"type", "directional"}, {"direction", {1, -1, 0}}});
  request["scene"]["solids"][0]["size"] = {1, 1, 1};
  RenderRequest req = request_from_json(request);
  PolygonSoup soup = tessellate(req.scene.geometry);
  ViewTransform view = make_view(req.camera, req.options.width, req.options.height);
  ShadowMaps maps = build_shadow_maps(req.scene, soup, view, req.options);
  ASSERT_EQ(maps.lights.size(), 1u);
  const double texel = std::max(maps.lights[0].texel_u, maps.lights[0].texel_v);
  double gap = -1.0;
  for (double s = 1e-5; s < 0.9; s += 1e-4) {
    for (double z : {-0.3, 0.0, 0.3}) {
      const float vis = shadow_visibility_at(maps, 0, {0.5 + s, 0.0, z}, {0, 1, 0}, 0.0);
      if (vis > 0.0f) gap = std::max(gap, s);
    }
  }
  EXPECT_LE(gap, 1.5 * texel) << "texel " << texel << " m";
  // The lookup itself is not trivially dark: past the shadow's end the floor is lit.
  EXPECT_EQ(shadow_visibility_at(maps, 0, {1.6, 0.0, 0.0}, {0, 1, 0}, 0.0), 1.0f);
}

bool same_image(const Image& a, const Image& b) { return a.rgb == b.rgb; }

TEST(Shadow, PassIsSkippedWhenNothingNeedsIt) {
  auto expect_skipped = [](json request, bool pass_ran) {
    auto on = render_json(request);
    request["options"]["shadows"] = false;
    auto off = render_json(request);
    EXPECT_TRUE(on.result.stats.shadow_skipped);
    if (!pass_ran) {
      EXPECT_EQ(on.result.timings.shadow_ms, 0.0);
    }
    EXPECT_NE(report_text(on.result.timings, on.result.stats).find("\"shadow\":\"skipped\""), std::string::npos);
    EXPECT_TRUE(same_image(on.result.frame.image, off.result.frame.image));
  };
  json request = box_on_floor({{"type", "directional"}, {"direction", {0.5, -1.0, 0.25}}});
  for (const char* mode : {"flat", "gouraud", "phong"}) {
    SCOPED_TRACE(mode);
    request["options"]["shading"] = mode;
    // No lights: nothing runs at all.
    json no_lights = request;
    no_lights["scene"]["lights"] = json::array();
    expect_skipped(no_lights, false);
    // A lone floor under a light: nothing can cast onto it (the analysis runs, no map is drawn).
    json floor_only = request;
    floor_only["scene"]["solids"] = json::array();
    expect_skipped(floor_only, true);
    // A light of intensity 0 adds nothing, so its shadow could not show.
    json dark = request;
    dark["scene"]["lights"][0]["intensity"] = 0;
    expect_skipped(dark, true);
    // Shadows off: nothing runs.
    json off = request;
    off["options"]["shadows"] = false;
    auto r = render_json(off);
    EXPECT_TRUE(r.result.stats.shadow_skipped);
    EXPECT_EQ(r.result.timings.shadow_ms, 0.0);
    // Control: the box does cast, and changes the image.
    auto cast = render_json(request);
    EXPECT_FALSE(cast.result.stats.shadow_skipped);
    EXPECT_FALSE(same_image(cast.result.frame.image, r.result.frame.image));
  }
}

TEST(Shadow, ManyLightsShareABoundedTexelBudget) {
  json request = box_on_floor({{"type", "point"}, {"position", {-2, 3, -2}}});
  for (double x : {2.0, -2.0, 2.0})
    request["scene"]["lights"].push_back({{"type", "point"}, {"position", {x, 3, x > 0 ? 2 : -1}}});
  RenderRequest req = request_from_json(request);
  PolygonSoup soup = tessellate(req.scene.geometry);
  ShadowMaps maps = build_shadow_maps(req.scene, soup, make_view(req.camera, 640, 480), req.options);
  ASSERT_EQ(maps.lights.size(), 4u);
  EXPECT_LT(maps.side, 2048);
  EXPECT_LE(maps.maps.size() * size_t(maps.side) * size_t(maps.side), shadow_max_texels);
}

// The sun outside a closed room lights nothing inside it, with shadow maps and with shadow rays, in
// every pipeline. The room is four walls and a room with its ceiling at the walls' height, the
// camera inside facing the wall the sun falls on (its lit side faces the sun), so every wall-ceiling
// and wall-wall joint it sees is a concave contact between a caster and a lit receiver. The frame
// with the sun on must be byte-identical to the frame with the sun at intensity 0. Also: a room's
// ceiling reaches 1 cm beyond its outline, and keeps the outline where the grown one would cross
// itself.

// A 4 x 3 m room of 10 cm walls 2.5 m high on their centre lines, the room's outline `outline`, a
// sun 57 degrees high falling on the inner face of the wall along z = 0.
json closed_room_in_sun(const json& outline) {
  json walls = json::array();
  const double corners[4][2] = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  for (int i = 0; i < 4; ++i) {
    walls.push_back({{"id", "wall" + std::to_string(i)},
                     {"start", {corners[i][0], corners[i][1]}},
                     {"end", {corners[(i + 1) % 4][0], corners[(i + 1) % 4][1]}},
                     {"thickness", 0.1},
                     {"height", 2.5}});
  }
  return {{"scene",
           {{"walls", walls},
            {"rooms", {{{"id", "room"}, {"points", outline}, {"ceiling", true}, {"ceiling_height", 2.5}}}},
            {"lights", {{{"type", "directional"}, {"direction", {-0.35, -1.0, -0.55}}, {"intensity", 0.75}}}}}},
          {"camera", {{"position", {2, 1.5, 2.8}}, {"target", {2, 2.2, 0}}, {"fov_y", 60}}},
          {"options", {{"width", 960}, {"height", 540}, {"shadows", true}}}};
}

const json room_at_inner_faces = {{0.05, 0.05}, {3.95, 0.05}, {3.95, 2.95}, {0.05, 2.95}};
const json room_at_wall_centres = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};

// Pixels that differ between the frame with the sun on and at intensity 0.
size_t sunlit_pixels(json request, const std::string& pipeline, const std::string& method, const std::string& shading) {
  request["options"]["pipeline"] = pipeline;
  request["options"]["shading"] = shading;
  request["options"]["shadow"]["method"] = method;
  const testing::SceneRender on = testing::render_json(request);
  request["scene"]["lights"][0]["intensity"] = 0;
  const testing::SceneRender off = testing::render_json(request);
  const std::vector<uint8_t>&a = on.result.frame.image.rgb, &b = off.result.frame.image.rgb;
  size_t lit = 0;
  for (size_t i = 0; i < a.size(); i += 3) lit += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2];
  return lit;
}

void expect_dark_inside(const json& request) {
  for (const PipelineInfo& p : pipeline_table()) {
    for (const char* method : {"map", "rays"}) {
      for (const char* shading : {"phong", "flat"}) {
        EXPECT_EQ(sunlit_pixels(request, p.name, method, shading), 0u)
            << p.name << ", shadow.method " << method << ", " << shading;
      }
    }
  }
}

// The ceiling overlapping the walls already: what is left is the lookup, whose bias and plane
// extrapolation lit a wall's face within a texel of the ceiling and of the other walls.
TEST(ClosedRoomSun, RoomDrawnToTheWallCentresIsDarkInside) {
  expect_dark_inside(closed_room_in_sun(room_at_wall_centres));
}

// As Sweet Home 3D draws rooms: the ceiling ends at the walls' inner faces, and only its 1 cm reach
// under the walls closes the joint for the maps.
TEST(ClosedRoomSun, RoomDrawnToTheWallsInnerFacesIsDarkInside) {
  expect_dark_inside(closed_room_in_sun(room_at_inner_faces));
}

// The plan rectangle [min, max] of the ceiling polygons of `request`'s scene.
std::pair<Vec2, Vec2> ceiling_extent(const json& request) {
  const RenderRequest parsed = request_from_json(request);
  const PolygonSoup soup = tessellate(parsed.scene.geometry);
  Vec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Polygon& p : soup.polygons) {
    if (!soup.objects[p.object].ceiling) continue;
    for (const Vec3& q : soup.points(p)) lo = glm::min(lo, Vec2(q.x, q.z)), hi = glm::max(hi, Vec2(q.x, q.z));
  }
  return {lo, hi};
}

TEST(ClosedRoomSun, CeilingReachesOneCentimetreUnderTheWalls) {
  const auto [lo, hi] = ceiling_extent(closed_room_in_sun(room_at_inner_faces));
  EXPECT_NEAR(lo.x, 0.04, 1e-12);
  EXPECT_NEAR(lo.y, 0.04, 1e-12);
  EXPECT_NEAR(hi.x, 3.96, 1e-12);
  EXPECT_NEAR(hi.y, 2.96, 1e-12);
}

TEST(ClosedRoomSun, CeilingStaysWhereNoWallReachesIt) {
  json request = closed_room_in_sun(room_at_inner_faces);
  for (json& wall : request["scene"]["walls"]) wall["height"] = 1.0;
  const auto [lo, hi] = ceiling_extent(request);
  EXPECT_EQ(lo, Vec2(0.05, 0.05));
  EXPECT_EQ(hi, Vec2(3.95, 2.95));
}

TEST(ClosedRoomSun, CeilingKeepsAnOutlineWhoseGrowthWouldCrossItself) {
  // A 1.5 cm wall reaching into the room from its far wall, the outline around it: grown by 1 cm
  // under that wall, the notch's sides would cross.
  json request = closed_room_in_sun({{0.05, 0.05},
                                     {3.95, 0.05},
                                     {3.95, 2.95},
                                     {2.0075, 2.95},
                                     {2.0075, 2.0},
                                     {1.9925, 2.0},
                                     {1.9925, 2.95},
                                     {0.05, 2.95}});
  request["scene"]["walls"].push_back(
      {{"id", "fin"}, {"start", {2, 3}}, {"end", {2, 2}}, {"thickness", 0.015}, {"height", 2.5}});
  const auto [lo, hi] = ceiling_extent(request);
  EXPECT_EQ(lo, Vec2(0.05, 0.05));
  EXPECT_EQ(hi, Vec2(3.95, 2.95));
}

// The closed room with a 1 m wide opening in the wall along z = 3, whose outer face the sun lights:
// a doorway 2.1 m high (no leaf), or a window from 0.8 to 2.0 m with a pane. The sunlight that
// passes lands on the floor as a parallelogram. A ray that reaches the floor crosses the opening's
// outer and inner rectangles (the wall is T thick); per metre of descent it moves a = 0.35 m along
// -x and b = 0.55 m along -z, so it spends T / b of height and a T / b of width inside the wall. The
// patch is {(u - a s, 2.95 - b s) : u in [x0, x1 - a T / b], s in [sill, top - T / b]}: area
// b (w - a T / b)(top - T / b - sill). The camera looks down at it from inside.
constexpr double kOpeningX0 = 1.5, kOpeningWidth = 1.0, kWallThickness = 0.1;
constexpr double kDoorHeight = 2.1, kWindowSill = 0.8, kWindowTop = 2.0;
constexpr double kSunA = 0.35, kSunB = 0.55;  // the sun's (-0.35, -1, -0.55): x and z per unit of descent

json room_with_opening(const json& opening) {
  json request = closed_room_in_sun(room_at_inner_faces);
  // wall2 runs from (4, 3) to (0, 3): the offset is measured from (4, 3).
  json o = opening;
  o["offset"] = 4.0 - (kOpeningX0 + kOpeningWidth);
  o["width"] = kOpeningWidth;
  request["scene"]["walls"][2]["openings"] = {o};
  request["camera"] = {{"position", {2.6, 2.3, 0.4}}, {"target", {1.4, 0.0, 2.4}}, {"fov_y", 60}};
  request["options"]["width"] = 1280;
  request["options"]["height"] = 720;
  return request;
}

json room_with_open_door() { return room_with_opening({{"type", "door"}, {"height", kDoorHeight}, {"leaf", false}}); }

// A pane of opacity 0.4 tinted #99ccff: it lets through 0.6 x (0.6, 0.8, 1.0).
const Color kPaneTransmittance{0.36f, 0.48f, 0.6f};
json room_with_window(const std::string& color, double opacity) {
  return room_with_opening({{"type", "window"},
                            {"sill", kWindowSill},
                            {"height", kWindowTop - kWindowSill},
                            {"color", color},
                            {"opacity", opacity}});
}

// Is the floor point (x, z) in the analytic patch of an opening from `sill` to `top`?
bool in_opening_patch(double x, double z, double sill, double top) {
  const double inner_face = 3.0 - kWallThickness / 2;
  const double s = (inner_face - z) / kSunB;  // height at which the ray crosses the inner face
  const double u = x + kSunA * s;             // where it crosses it along x
  return s >= sill && s <= top - kWallThickness / kSunB && u >= kOpeningX0 &&
         u <= kOpeningX0 + kOpeningWidth - kSunA * kWallThickness / kSunB;
}

// One frame of the room with the sun on and one with it at intensity 0, and per floor pixel (-1
// elsewhere): the floor point its centre sees, in the analytic patch or not (`truth`), and lit
// (the sun changes a channel by more than 2 levels) or not.
struct SunPatch {
  SceneRender on, off;
  std::vector<int> truth, lit;
  size_t truth_area = 0, lit_area = 0;
};
SunPatch sun_patch(json request, double sill, double top) {
  SunPatch p{render_json(request), {}, {}, {}};
  request["scene"]["lights"][0]["intensity"] = 0;
  p.off = render_json(request);
  const int w = p.on.view.width, h = p.on.view.height;
  p.truth.assign(size_t(w) * size_t(h), -1), p.lit.assign(p.truth.size(), -1);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const auto q = testing::pixel_on_plane(p.on.view, x, y, {0, 1, 0}, 0.0);
      if (!q || !(q->x > 0.06 && q->x < 3.94 && q->z > 0.06 && q->z < 2.94)) continue;
      bool sun = false;
      for (int c = 0; c < 3; ++c) {
        sun |= std::abs(int(p.on.result.frame.image.rgb[3 * i + c]) - int(p.off.result.frame.image.rgb[3 * i + c])) > 2;
      }
      p.truth[i] = in_opening_patch(q->x, q->z, sill, top) ? 1 : 0;
      p.lit[i] = sun ? 1 : 0;
      p.truth_area += size_t(p.truth[i]);
      p.lit_area += size_t(p.lit[i]);
    }
  }
  return p;
}

// With rays: area within 1 % of the analytic patch's pixels, every differing pixel within a pixel
// of its edge; with maps: within their 2-pixel edge band (docs/accuracy.md). The analytic patch is
// classified per pixel centre: the floor point the centre's ray meets, in the patch or not.
void expect_patch(const SunPatch& p, const std::string& what, const std::string& method, size_t min_area) {
  const Misplaced m = misplaced(p.truth, p.lit, p.on.view.width, [](size_t) { return false; });
  std::cout << what << " " << method << ": patch " << p.truth_area << " px, lit " << p.lit_area << " px, " << m.pixels
            << " differ (" << m.drawn_outside << " lit outside), at most " << m.worst_distance << " px from the edge\n";
  ASSERT_GT(p.truth_area, min_area) << "the camera sees the patch";
  if (method == "rays") {
    EXPECT_NEAR(double(p.lit_area), double(p.truth_area), 0.01 * double(p.truth_area)) << what;
    EXPECT_LE(m.worst_distance, 1.0) << what << ": rays decide within a pixel of the exact edge";
  } else {
    EXPECT_LE(m.worst_distance, 2.0) << what << ": the map misplaces the edge by more than its band";
  }
}

// Every pipeline, Phong, with rays and with maps.
TEST(OpenDoorSun, ExactlyThePatchTheDoorwayLetsThroughIsLit) {
  const double patch_area =
      kSunB * (kOpeningWidth - kSunA * kWallThickness / kSunB) * (kDoorHeight - kWallThickness / kSunB);
  std::cout << "analytic patch " << patch_area << " m2\n";
  for (const PipelineInfo& p : pipeline_table()) {
    for (const char* method : {"rays", "map"}) {
      json request = room_with_open_door();
      request["options"]["pipeline"] = p.name;
      request["options"]["shading"] = "phong";
      request["options"]["shadow"]["method"] = method;
      expect_patch(sun_patch(request, 0.0, kDoorHeight), p.name, method, 20000);
    }
  }
}

// The sun's share of the patch's light, per channel, summed over the patch's pixels at least 3
// pixels inside its analytic edge (on minus off).
glm::dvec3 sun_in_patch(const SunPatch& p) {
  const int w = p.on.view.width, h = p.on.view.height;
  glm::dvec3 sum(0.0);
  for (int y = 3; y + 3 < h; ++y) {
    for (int x = 3; x + 3 < w; ++x) {
      bool inside = true;
      for (int dy = -3; dy <= 3 && inside; ++dy) {
        for (int dx = -3; dx <= 3 && inside; ++dx) inside = p.truth[size_t((y + dy) * w + x + dx)] == 1;
      }
      if (!inside) continue;
      const size_t i = size_t(y * w + x);
      for (int c = 0; c < 3; ++c) {
        sum[c] += double(p.on.result.frame.image.rgb[3 * i + size_t(c)]) -
                  double(p.off.result.frame.image.rgb[3 * i + size_t(c)]);
      }
    }
  }
  return sum;
}

// A glazed window: the patch lies where the analytic projection of the opening puts it (as for the
// doorway), and its sunlight is the pane's transmittance of what the same window without a pane
// (opacity 0, white: it lets everything through) lets in, channel by channel, within 1 % (the
// bytes' rounding, averaged over the patch), in every pipeline and the reference, with rays and maps.
TEST(SunThroughGlass, AWindowCastsItsPatchTintedByThePane) {
  for (const PipelineInfo& p : pipeline_table()) {
    for (const char* method : {"rays", "map"}) {
      auto frames = [&](json request) {
        request["options"]["pipeline"] = p.name;
        request["options"]["shading"] = "phong";
        request["options"]["shadow"]["method"] = method;
        return sun_patch(request, kWindowSill, kWindowTop);
      };
      const SunPatch glazed = frames(room_with_window("#99ccff", 0.4));
      const SunPatch clear = frames(room_with_window("#ffffff", 0.0));
      expect_patch(glazed, p.name + std::string(" glazed"), method, 12000);
      expect_patch(clear, p.name + std::string(" clear"), method, 12000);
      const glm::dvec3 through = sun_in_patch(glazed), all = sun_in_patch(clear);
      ASSERT_GT(all.r, 1e4) << "the patch holds enough sunlight to measure";
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(through[c] / all[c], double(kPaneTransmittance[c]), 0.01)
            << p.name << " " << method << ", channel " << c;
      }
      std::cout << p.name << " " << method << ": transmitted " << through.r / all.r << ", " << through.g / all.g << ", "
                << through.b / all.b << "\n";
    }
  }
}

}  // namespace
}  // namespace rr

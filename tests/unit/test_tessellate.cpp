// Exact fixtures for the tessellator: face counts derived by hand, areas and volumes against
// analytic values (relative 1e-9: the only error is double rounding over a few hundred terms),
// closedness as the vanishing area-weighted normal sum, and the invariants of tessellate.hpp.
#include "render/core/tessellate.hpp"
#include "render/scene_io/element_pointer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace rr {
namespace {

constexpr double rel_tol = 1e-9;

double cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

Vec3 centroid(const PolygonSoup& soup, const Polygon& p) {
  Vec3 c{0.0};
  for (const Vec3& v : soup.points(p)) c += v;
  return c / double(p.vertex_count);
}

// Invariants every soup must satisfy: ids are indices; polygons are convex, planar, CCW seen from
// the front (Newell normal == normal); normals unit; flags follow the object and the material.
void expect_valid_soup(const PolygonSoup& soup) {
  ASSERT_EQ(soup.positions.size(), soup.normals.size());
  for (size_t i = 0; i < soup.polygons.size(); ++i) {
    const Polygon& p = soup.polygons[i];
    SCOPED_TRACE("polygon " + std::to_string(i));
    EXPECT_EQ(p.id, i);
    ASSERT_GE(p.vertex_count, 3u);
    ASSERT_LE(size_t(p.first_vertex) + p.vertex_count, soup.positions.size());
    ASSERT_LT(p.material, soup.materials.size());
    ASSERT_LT(p.object, soup.objects.size());
    EXPECT_NEAR(glm::length(p.normal), 1.0, 1e-12);
    const auto pts = soup.points(p);
    double extent = 0.0;
    for (const Vec3& v : pts) extent = std::max(extent, glm::length(v - pts[0]));
    const double scale = std::max(extent, glm::length(pts[0]));
    for (const Vec3& v : pts) EXPECT_NEAR(glm::dot(p.normal, v), p.offset, 1e-9 * scale);
    EXPECT_GT(polygon_area(pts), 0.0);
    Vec3 newell{0.0};
    for (size_t k = 1; k + 1 < pts.size(); ++k) newell += glm::cross(pts[k] - pts[0], pts[k + 1] - pts[0]);
    EXPECT_GT(glm::dot(glm::normalize(newell), p.normal), 1.0 - 1e-9);
    for (size_t k = 0; k < pts.size(); ++k) {  // convex: every turn is to the left about the normal
      const Vec3 e1 = pts[k] - pts[(k + pts.size() - 1) % pts.size()];
      const Vec3 e2 = pts[(k + 1) % pts.size()] - pts[k];
      EXPECT_GE(glm::dot(glm::cross(e1, e2), p.normal), -1e-12 * glm::length(e1) * glm::length(e2));
    }
    for (const glm::vec3& n : soup.vertex_normals(p)) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    EXPECT_EQ((p.flags & polygon_closed) != 0, soup.objects[p.object].closed);
    EXPECT_EQ((p.flags & polygon_translucent) != 0, soup.materials[p.material].opacity < 1.0f);
  }
}

void expect_estimate_bounds(const StaticGeometry& g, const PolygonSoup& soup) {
  EXPECT_GE(estimate_polygon_count(g), soup.polygons.size());
}

PolygonSoup tessellate_checked(const StaticGeometry& g) {
  PolygonSoup soup = tessellate(g);
  expect_valid_soup(soup);
  expect_estimate_bounds(g, soup);
  return soup;
}

std::vector<size_t> polygons_of(const PolygonSoup& soup, const std::string& pointer) {
  std::vector<size_t> out;
  for (size_t i = 0; i < soup.polygons.size(); ++i) {
    if (element_pointer(soup.objects[soup.polygons[i].object].element) == pointer) out.push_back(i);
  }
  return out;
}

double total_area(const PolygonSoup& soup, const std::vector<size_t>& polys) {
  double a = 0.0;
  for (size_t i : polys) a += polygon_area(soup.points(soup.polygons[i]));
  return a;
}

// Sum of area * normal: zero for a closed surface (divergence theorem applied to a constant field).
Vec3 area_vector(const PolygonSoup& soup, const std::vector<size_t>& polys) {
  Vec3 s{0.0};
  for (size_t i : polys) s += polygon_area(soup.points(soup.polygons[i])) * soup.polygons[i].normal;
  return s;
}

// Divergence theorem with the field p - ref: volume = sum of area * (offset - n.ref) / 3.
// Positive only when the normals point outward.
double volume(const PolygonSoup& soup, const std::vector<size_t>& polys, Vec3 ref = Vec3(0.0)) {
  double v = 0.0;
  for (size_t i : polys) {
    const Polygon& p = soup.polygons[i];
    v += polygon_area(soup.points(p)) * (p.offset - glm::dot(p.normal, ref)) / 3.0;
  }
  return v;
}

void expect_closed(const PolygonSoup& soup, const std::vector<size_t>& polys) {
  const double scale = total_area(soup, polys);
  const Vec3 s = area_vector(soup, polys);
  EXPECT_NEAR(s.x, 0.0, rel_tol * scale);
  EXPECT_NEAR(s.y, 0.0, rel_tol * scale);
  EXPECT_NEAR(s.z, 0.0, rel_tol * scale);
}

void expect_rel(double actual, double expected) { EXPECT_NEAR(actual, expected, rel_tol * std::abs(expected)); }

void expect_vec(Vec3 actual, Vec3 expected, double tol = 1e-12) {
  EXPECT_NEAR(actual.x, expected.x, tol);
  EXPECT_NEAR(actual.y, expected.y, tol);
  EXPECT_NEAR(actual.z, expected.z, tol);
}

// --- plan helpers for the join tests ---------------------------------------------------------

std::vector<Vec2> plan_of(const PolygonSoup& soup, size_t poly) {
  std::vector<Vec2> out;
  for (const Vec3& v : soup.points(soup.polygons[poly])) out.push_back({v.x, v.z});
  double a = 0.0;
  for (size_t i = 0; i < out.size(); ++i) a += cross2(out[i], out[(i + 1) % out.size()]);
  if (a < 0.0) std::reverse(out.begin(), out.end());  // positive orientation in (x, z)
  return out;
}

double plan_area(const std::vector<Vec2>& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) a += cross2(p[i], p[(i + 1) % p.size()]);
  return 0.5 * std::abs(a);
}

// Area of the intersection of two convex plan polygons (Sutherland-Hodgman).
double overlap_area(const std::vector<Vec2>& subject, const std::vector<Vec2>& clip) {
  std::vector<Vec2> poly = subject;
  for (size_t i = 0; i < clip.size() && !poly.empty(); ++i) {
    const Vec2 a = clip[i], b = clip[(i + 1) % clip.size()];
    const auto side = [&](Vec2 p) { return cross2(b - a, p - a); };
    std::vector<Vec2> next;
    for (size_t k = 0; k < poly.size(); ++k) {
      const Vec2 p = poly[k], q = poly[(k + 1) % poly.size()];
      if (side(p) >= 0.0) next.push_back(p);
      if ((side(p) >= 0.0) != (side(q) >= 0.0)) next.push_back(p + (q - p) * (side(p) / (side(p) - side(q))));
    }
    poly = next;
  }
  return poly.size() < 3 ? 0.0 : plan_area(poly);
}

bool plan_contains(const std::vector<Vec2>& p, Vec2 q) {
  for (size_t i = 0; i < p.size(); ++i) {
    if (cross2(p[(i + 1) % p.size()] - p[i], q - p[i]) < 0.0) return false;
  }
  return true;
}

// The single top face (+Y) of a wall without openings.
size_t top_face(const PolygonSoup& soup, const std::string& pointer) {
  size_t found = soup.polygons.size();
  for (size_t i : polygons_of(soup, pointer)) {
    if (soup.polygons[i].normal.y > 0.5) {
      EXPECT_EQ(found, soup.polygons.size()) << "more than one top face";
      found = i;
    }
  }
  return found;
}

Wall make_wall(Vec2 start, Vec2 end, double thickness = 0.2, double height = 2.5) {
  Wall w;
  w.start = start;
  w.end = end;
  w.thickness = thickness;
  w.height = height;
  return w;
}

Opening door(double offset, double width, double height) {
  Opening o;
  o.type = OpeningType::door;
  o.offset = offset;
  o.width = width;
  o.height = height;
  return o;
}

Opening window(double offset, double width, double height, double sill) {
  Opening o;
  o.type = OpeningType::window;
  o.offset = offset;
  o.width = width;
  o.height = height;
  o.sill = sill;
  o.opacity = 0.35f;
  return o;
}

// --- floor -----------------------------------------------------------------------------------

TEST(Tessellate, FloorCellsRowByRowWithCyclingColours) {
  StaticGeometry g;
  g.has_floor = true;
  g.floor.origin = {1.0, 2.0};
  g.floor.cells_x = 3;
  g.floor.cells_z = 2;
  g.floor.cell_size = 0.5;
  g.floor.elevation = 0.1;
  g.floor.colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 6u);
  ASSERT_EQ(soup.objects.size(), 1u);
  EXPECT_EQ(element_pointer(soup.objects[0].element), "/scene/floor");
  EXPECT_FALSE(soup.objects[0].closed);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 3; ++i) {
      const Polygon& p = soup.polygons[size_t(j * 3 + i)];  // j (z) outer, i (x) inner
      EXPECT_EQ(p.vertex_count, 4u);
      EXPECT_EQ(soup.materials[p.material].color, g.floor.colors[size_t(i + j) % 3]);
      expect_vec(p.normal, {0.0, 1.0, 0.0});
      EXPECT_DOUBLE_EQ(p.offset, 0.1);
      EXPECT_EQ(p.flags, 0u);
      expect_vec(centroid(soup, p), {1.0 + 0.5 * i + 0.25, 0.1, 2.0 + 0.5 * j + 0.25});
      for (const glm::vec3& n : soup.vertex_normals(p)) EXPECT_EQ(n, glm::vec3(0, 1, 0));
    }
  }
  expect_rel(total_area(soup, polygons_of(soup, "/scene/floor")), 6 * 0.25);
}

// --- a wall with a door and a window -----------------------------------------------------------

// A 4 m wall along +X (left side is -Z), 0.2 thick, 2.5 high; a door at 0.5..1.4 (2.0 high) and a
// window at 2.0..3.2 (sill 0.9, 1.0 high). Columns along the wall: full, door, full, window, full.
StaticGeometry door_and_window_wall(Vec2 start = {0.0, 0.0}, Vec2 end = {4.0, 0.0}) {
  StaticGeometry g;
  Wall w = make_wall(start, end);
  w.openings = {door(0.5, 0.9, 2.0), window(2.0, 1.2, 1.0, 0.9)};
  g.walls = {w};
  return g;
}

// Inside the wall's volume (in its own frame: x along, z across, y up).
bool inside_door_and_window_wall(Vec3 p) {
  if (!(p.x > 0.0 && p.x < 4.0 && p.z > -0.1 && p.z < 0.1 && p.y > 0.0 && p.y < 2.5)) return false;
  const bool in_door = p.x > 0.5 && p.x < 1.4 && p.y < 2.0;
  const bool in_window = p.x > 2.0 && p.x < 3.2 && p.y > 0.9 && p.y < 1.9;
  return !in_door && !in_window;
}

TEST(Tessellate, WallWithDoorAndWindowFaceCountAndOrder) {
  const PolygonSoup soup = tessellate_checked(door_and_window_wall());
  // Long faces: per side 3 full columns + 1 above the door + 2 (below and above the window) = 6,
  // so 12. Top: 1 (nothing reaches it). Bottom: 2 (split by the door). End faces: 2. -> 17.
  // Door: 2 jambs + head (no sill) = 3, leaf 6. Window: 2 jambs + head + sill = 4, pane 1.
  // 17 + 3 + 6 + 4 + 1 = 31.
  ASSERT_EQ(soup.polygons.size(), 31u);
  const Vec3 left{0, 0, -1}, right{0, 0, 1}, up{0, 1, 0}, down{0, -1, 0}, back{-1, 0, 0}, ahead{1, 0, 0};
  const std::vector<Vec3> expected = {left,  left,  left,  left,  left,  left,
                                      right, right, right, right, right, right,  // long faces
                                      up,    down,  down,  back,  ahead,         // top, bottom, ends
                                      ahead, back,  down,                        // door reveals
                                      left,  right, up,    down,  back,  ahead,  // door leaf
                                      ahead, back,  down,  up,                   // window reveals
                                      left};                                     // pane
  for (size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE("polygon " + std::to_string(i));
    expect_vec(soup.polygons[i].normal, expected[i]);
  }
  // The left face's pieces run along the wall, each column bottom to top.
  const double piece_x[6] = {0.25, 0.95, 1.7, 2.6, 2.6, 3.6};
  const double piece_y[6] = {1.25, 2.25, 1.25, 0.45, 2.2, 1.25};
  for (size_t i = 0; i < 6; ++i) expect_vec(centroid(soup, soup.polygons[i]), {piece_x[i], piece_y[i], -0.1});
  EXPECT_EQ(polygons_of(soup, "/scene/walls/0").size(), 24u);
  EXPECT_EQ(polygons_of(soup, "/scene/walls/0/openings/0").size(), 6u);
  EXPECT_EQ(polygons_of(soup, "/scene/walls/0/openings/1").size(), 1u);
}

TEST(Tessellate, WallWithDoorAndWindowIsClosedWithAnalyticAreaAndVolume) {
  const PolygonSoup soup = tessellate_checked(door_and_window_wall());
  const auto wall = polygons_of(soup, "/scene/walls/0");
  // Long faces 2 (L h - door - window), top L t, bottom (L - door width) t, ends 2 h t, door
  // reveals (2 h_door + w_door) t, window reveals 2 (w + h) t.
  const double L = 4.0, h = 2.5, t = 0.2;
  const double area = 2 * (L * h - 0.9 * 2.0 - 1.2 * 1.0) + L * t + (L - 0.9) * t + 2 * h * t + (2 * 2.0 + 0.9) * t +
                      2 * (1.2 + 1.0) * t;
  expect_rel(total_area(soup, wall), area);
  expect_closed(soup, wall);
  expect_rel(volume(soup, wall), (L * h - 0.9 * 2.0 - 1.2 * 1.0) * t);
  EXPECT_TRUE(soup.objects[soup.polygons[wall[0]].object].closed);
}

TEST(Tessellate, WallFacesPointOutOfTheWall) {
  const PolygonSoup soup = tessellate_checked(door_and_window_wall());
  // A face's centroid stepped 1 micron along its normal is outside the wall, stepped back inside.
  for (size_t i : polygons_of(soup, "/scene/walls/0")) {
    SCOPED_TRACE("polygon " + std::to_string(i));
    const Vec3 c = centroid(soup, soup.polygons[i]), n = soup.polygons[i].normal;
    EXPECT_FALSE(inside_door_and_window_wall(c + 1e-6 * n));
    EXPECT_TRUE(inside_door_and_window_wall(c - 1e-6 * n));
  }
}

TEST(Tessellate, DoorLeafAndWindowPane) {
  const PolygonSoup soup = tessellate_checked(door_and_window_wall());
  const auto leaf = polygons_of(soup, "/scene/walls/0/openings/0");
  const Polygon& leaf_face = soup.polygons[leaf[0]];
  EXPECT_TRUE(soup.objects[leaf_face.object].closed);
  EXPECT_EQ(soup.materials[leaf_face.material].color, Opening{}.color);
  expect_closed(soup, leaf);
  // 4 cm thick, 2 mm narrower than the opening on each side and at the top, on the base.
  expect_rel(volume(soup, leaf), (0.9 - 0.004) * 0.04 * (2.0 - 0.002));
  for (size_t i : leaf) {
    for (const Vec3& v : soup.points(soup.polygons[i])) {
      EXPECT_TRUE(v.x > 0.5 && v.x < 1.4 && std::abs(v.z) < 0.1 && v.y >= 0.0 && v.y < 2.0);
    }
  }
  const auto pane = polygons_of(soup, "/scene/walls/0/openings/1");
  const Polygon& p = soup.polygons[pane[0]];
  EXPECT_FALSE(soup.objects[p.object].closed);
  EXPECT_EQ(p.flags, uint32_t(polygon_translucent));
  EXPECT_FLOAT_EQ(soup.materials[p.material].opacity, 0.35f);
  expect_vec(p.normal, {0, 0, -1});   // faces the wall's left
  EXPECT_NEAR(p.offset, 0.0, 1e-15);  // middle of the thickness
  expect_rel(polygon_area(soup.points(p)), 1.2 * 1.0);
}

TEST(Tessellate, WallFarFromOriginAndTurnedKeepsAreaAndVolume) {
  // The same wall 1e5 m away along a diagonal: only rounding differs.
  const Vec2 start{1e5, -2e5}, dir = glm::normalize(Vec2(3.0, -4.0));
  const PolygonSoup soup = tessellate_checked(door_and_window_wall(start, start + 4.0 * dir));
  const auto wall = polygons_of(soup, "/scene/walls/0");
  ASSERT_EQ(soup.polygons.size(), 31u);
  expect_rel(volume(soup, wall, Vec3(start.x, 0.0, start.y)), (10.0 - 1.8 - 1.2) * 0.2);
  const Vec3 s = area_vector(soup, wall);
  EXPECT_LT(glm::length(s), 1e-8);
  // Left of start -> end. Positions near 2e5 m carry ~3e-11 m of rounding, over a 1 m face.
  expect_vec(soup.polygons[0].normal, {dir.y, 0.0, -dir.x}, 1e-10);
}

TEST(Tessellate, OpeningsFlushWithTheEndAndWithEachOther) {
  // A full-height door flush with the square start, touching a window: no jamb where two voids or
  // a void and the outside meet, no head for the door, the start face is gone.
  StaticGeometry g;
  Wall w = make_wall({0.0, 0.0}, {3.0, 0.0});
  w.openings = {door(0.0, 1.0, 2.5), window(1.0, 1.0, 1.0, 0.5)};
  g.walls = {w};
  const PolygonSoup soup = tessellate_checked(g);
  // Columns: door (no material), window (below 0.5, above 1.5), full. Long faces 2 x 3, top 1,
  // bottom 1, start face 0, end face 1 -> 9. Door: far jamb against the window column's two pieces
  // = 2, leaf 6. Window: near jamb 0, far jamb 1, head 1, sill 1 = 3, pane 1. Total 21.
  EXPECT_EQ(soup.polygons.size(), 21u);
  const auto wall = polygons_of(soup, "/scene/walls/0");
  EXPECT_EQ(wall.size(), 14u);
  expect_closed(soup, wall);
  expect_rel(volume(soup, wall), (2.0 * 2.5 - 1.0) * 0.2);
}

TEST(Tessellate, WindowFromBaseToTopSplitsTheWall) {
  StaticGeometry g;
  Wall w = make_wall({0.0, 0.0}, {3.0, 0.0});
  w.openings = {window(1.0, 0.5, 2.5, 0.0)};
  g.walls = {w};
  const PolygonSoup soup = tessellate_checked(g);
  // Two separate boxes of 6 faces, sharing the wall's object; then the pane.
  EXPECT_EQ(soup.polygons.size(), 13u);
  const auto wall = polygons_of(soup, "/scene/walls/0");
  expect_closed(soup, wall);
  expect_rel(volume(soup, wall), 2.5 * 2.5 * 0.2);
}

// --- joins -------------------------------------------------------------------------------------

struct JoinCase {
  Vec2 a0, a1, b0, b1;
  double ta, tb;
};

// Two walls sharing an end point: each is still closed, the top faces do not overlap, and the
// summed volume equals the analytic union (for equal thickness the mitred wall keeps t * L).
void expect_mitred(const JoinCase& c, double union_area) {
  StaticGeometry g;
  g.walls = {make_wall(c.a0, c.a1, c.ta), make_wall(c.b0, c.b1, c.tb)};
  const PolygonSoup soup = tessellate_checked(g);
  const auto a = polygons_of(soup, "/scene/walls/0"), b = polygons_of(soup, "/scene/walls/1");
  expect_closed(soup, a);
  expect_closed(soup, b);
  const auto top_a = plan_of(soup, top_face(soup, "/scene/walls/0"));
  const auto top_b = plan_of(soup, top_face(soup, "/scene/walls/1"));
  EXPECT_NEAR(overlap_area(top_a, top_b), 0.0, 1e-12);
  expect_rel(plan_area(top_a) + plan_area(top_b), union_area);
  expect_rel(volume(soup, a) + volume(soup, b), union_area * 2.5);
}

TEST(Tessellate, MitredLCornerHasNoOverlap) {
  // Union: [0, 4.1] x [-0.1, 0.1] and [3.9, 4.1] x [-0.1, 3], overlapping in 0.2 x 0.2.
  expect_mitred({{0, 0}, {4, 0}, {4, 0}, {4, 3}, 0.2, 0.2}, 4.1 * 0.2 + 0.2 * 3.1 - 0.04);
  StaticGeometry g;
  g.walls = {make_wall({0, 0}, {4, 0}), make_wall({4, 0}, {4, 3})};
  const PolygonSoup soup = tessellate(g);
  const auto top_a = plan_of(soup, top_face(soup, "/scene/walls/0"));
  const auto top_b = plan_of(soup, top_face(soup, "/scene/walls/1"));
  for (Vec2 corner : {Vec2(4.1, -0.1), Vec2(3.9, 0.1)}) {  // both ends of the mitre line
    for (const auto* top : {&top_a, &top_b}) {
      EXPECT_TRUE(std::any_of(top->begin(), top->end(), [&](Vec2 p) { return glm::length(p - corner) < 1e-12; }));
    }
  }
  EXPECT_TRUE(plan_contains(top_a, {4.05, -0.05}) || plan_contains(top_b, {4.05, -0.05}));  // outer corner filled
}

TEST(Tessellate, MitreHandlesUnequalThicknessAndAnyEndOrder) {
  // B is 0.1 thick: union [0, 4.05] x [-0.1, 0.1] and [3.95, 4.05] x [-0.1, 3].
  const double area = 4.05 * 0.2 + 0.1 * 3.1 - 0.1 * 0.2;
  expect_mitred({{0, 0}, {4, 0}, {4, 0}, {4, 3}, 0.2, 0.1}, area);
  expect_mitred({{4, 0}, {0, 0}, {4, 3}, {4, 0}, 0.2, 0.1}, area);  // both walls reversed
  // 135 degrees, equal thickness: each wall keeps t * L.
  const Vec2 far = Vec2(4, 0) + 2.0 * glm::normalize(Vec2(1, 1));
  expect_mitred({{0, 0}, {4, 0}, {4, 0}, far, 0.2, 0.2}, 0.2 * 4 + 0.2 * 2);
  // 30 degrees: sharp but above the 15 degree limit.
  const Vec2 back = Vec2(4, 0) + 3.0 * Vec2(-std::cos(radians(30)), std::sin(radians(30)));
  expect_mitred({{0, 0}, {4, 0}, {4, 0}, back, 0.2, 0.2}, 0.2 * 4 + 0.2 * 3);
}

double max_x_of_wall(const PolygonSoup& soup, const std::string& pointer) {
  double m = -1e300;
  for (size_t i : polygons_of(soup, pointer)) {
    for (const Vec3& v : soup.points(soup.polygons[i])) m = std::max(m, v.x);
  }
  return m;
}

TEST(Tessellate, NoMitreBelowFifteenDegreesOrWithThreeWalls) {
  StaticGeometry sharp;
  const Vec2 back = Vec2(4, 0) + 3.0 * Vec2(-std::cos(radians(10)), std::sin(radians(10)));
  sharp.walls = {make_wall({0, 0}, {4, 0}), make_wall({4, 0}, back)};
  EXPECT_DOUBLE_EQ(max_x_of_wall(tessellate_checked(sharp), "/scene/walls/0"), 4.0);
  StaticGeometry three;
  three.walls = {make_wall({0, 0}, {4, 0}), make_wall({4, 0}, {4, 3}), make_wall({4, 0}, {4, -3})};
  EXPECT_DOUBLE_EQ(max_x_of_wall(tessellate_checked(three), "/scene/walls/0"), 4.0);
}

TEST(Tessellate, TeeIsCutBackToTheFace) {
  StaticGeometry g;
  g.walls = {make_wall({0, 0}, {4, 0}), make_wall({2, 0}, {2, 3}, 0.1), make_wall({1, 0}, {1, -2}, 0.1)};
  const PolygonSoup soup = tessellate_checked(g);
  const auto host = polygons_of(soup, "/scene/walls/0");
  EXPECT_EQ(host.size(), 6u);  // the through wall is untouched
  expect_rel(volume(soup, host), 4 * 0.2 * 2.5);
  for (const std::string& p : {std::string("/scene/walls/1"), std::string("/scene/walls/2")}) {
    const auto w = polygons_of(soup, p);
    expect_closed(soup, w);
    double min_abs_z = 1e300;
    for (size_t i : w) {
      for (const Vec3& v : soup.points(soup.polygons[i])) min_abs_z = std::min(min_abs_z, std::abs(v.z));
    }
    EXPECT_NEAR(min_abs_z, 0.1, 1e-15);  // the host's face on that side
  }
  expect_rel(volume(soup, polygons_of(soup, "/scene/walls/1")), 0.1 * 2.9 * 2.5);
  expect_rel(volume(soup, polygons_of(soup, "/scene/walls/2")), 0.1 * 1.9 * 2.5);
}

TEST(Tessellate, SlantedTeeKeepsThicknessTimesRemainingLength) {
  // B leaves A's centreline at (2, 0) toward (4, 3); cut along A's face z = 0.1, a slanted end.
  // A strip cut by a slanted line keeps t * (centreline length), which crosses z = 0.1 at 1/30.
  StaticGeometry g;
  g.walls = {make_wall({0, 0}, {4, 0}), make_wall({2, 0}, {4, 3}, 0.1)};
  const PolygonSoup soup = tessellate_checked(g);
  const auto b = polygons_of(soup, "/scene/walls/1");
  expect_closed(soup, b);
  expect_rel(volume(soup, b), 0.1 * 2.5 * std::sqrt(13.0) * (1.0 - 1.0 / 30.0));
}

// Seeded random rooms: a star-shaped loop of 3..7 walls of one thickness (so every mitre keeps
// t * L), with random heights, bases and openings in the middle half of each wall (flush with each
// other, reaching the base or the top at times). Every wall must stay closed with the analytic
// volume, and at joints the mitre is sure to fit (>= 20 degrees, reach under L / 4), the top faces
// of the two walls must not overlap.
TEST(Tessellate, RandomRoomsStayClosedAndMitresDoNotOverlap) {
  for (uint32_t seed = 1; seed <= 200; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    const auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    const int k = std::uniform_int_distribution<int>(3, 7)(rng);
    const double t = uniform(0.05, 0.3);
    std::vector<Vec2> corners;
    for (int i = 0; i < k; ++i) {
      const double a = 2 * pi * (i + uniform(0.0, 0.5)) / k, r = uniform(3.0, 8.0);
      corners.push_back({r * std::cos(a), r * std::sin(a)});
    }
    StaticGeometry g;
    std::vector<double> expected_volume;
    for (int i = 0; i < k; ++i) {
      Wall w = make_wall(corners[size_t(i)], corners[size_t(i + 1) % size_t(k)], t, uniform(2.0, 3.0));
      w.base = uniform(0.0, 0.5);
      const double L = glm::length(w.end - w.start);
      std::vector<double> cuts;
      const int n = std::uniform_int_distribution<int>(0, 3)(rng);
      for (int j = 0; j < 2 * n; ++j) cuts.push_back(uniform(0.25 * L, 0.75 * L));
      std::sort(cuts.begin(), cuts.end());
      double volume_left = t * L * w.height;
      for (int j = 0; j < n; ++j) {
        if (j > 0 && uniform(0, 1) < 0.3) cuts[size_t(2 * j)] = cuts[size_t(2 * j - 1)];  // flush
        const double off = cuts[size_t(2 * j)], width = cuts[size_t(2 * j + 1)] - off;
        if (width <= 1e-3) continue;
        Opening o;
        if (uniform(0, 1) < 0.5) {
          o = door(off, width, uniform(0, 1) < 0.3 ? w.height : uniform(0.5, w.height));
          o.leaf = uniform(0, 1) < 0.5;
        } else {
          const double sill = uniform(0, 1) < 0.2 ? 0.0 : uniform(0.0, w.height - 0.2);
          o = window(off, width, uniform(0, 1) < 0.3 ? w.height - sill : uniform(0.1, w.height - sill), sill);
        }
        volume_left -= t * width * o.height;
        w.openings.push_back(o);
      }
      g.walls.push_back(w);
      expected_volume.push_back(volume_left);
    }
    const PolygonSoup soup = tessellate_checked(g);
    const size_t walls = size_t(k);
    std::vector<std::vector<std::vector<Vec2>>> tops(walls);  // top pieces of each wall
    for (int i = 0; i < k; ++i) {
      const std::string pointer = "/scene/walls/" + std::to_string(i);
      const auto polys = polygons_of(soup, pointer);
      expect_closed(soup, polys);
      expect_rel(volume(soup, polys, Vec3(corners[size_t(i)].x, 0, corners[size_t(i)].y)), expected_volume[size_t(i)]);
      for (size_t p : polys) {
        if (soup.polygons[p].normal.y > 0.5 &&
            std::abs(soup.polygons[p].offset - g.walls[size_t(i)].base - g.walls[size_t(i)].height) < 1e-9) {
          tops[size_t(i)].push_back(plan_of(soup, p));
        }
      }
    }
    for (int i = 0; i < k; ++i) {  // the joint at the end of wall i
      const Wall &a = g.walls[size_t(i)], &b = g.walls[size_t(i + 1) % size_t(k)];
      const Vec2 da = glm::normalize(a.start - a.end), db = glm::normalize(b.end - b.start);
      const double theta = std::acos(std::clamp(glm::dot(da, db), -1.0, 1.0));
      const double reach = 0.5 * t / std::tan(0.5 * theta);
      const double shortest = std::min(glm::length(a.end - a.start), glm::length(b.end - b.start));
      if (theta < radians(20.0) || reach > 0.25 * shortest) continue;
      for (const auto& pa : tops[size_t(i)]) {
        for (const auto& pb : tops[size_t(i + 1) % size_t(k)]) EXPECT_NEAR(overlap_area(pa, pb), 0.0, 1e-12);
      }
    }
    if (::testing::Test::HasFailure()) break;  // one failing seed is enough to read
  }
}

// --- solids ------------------------------------------------------------------------------------

Solid make_solid(SolidType type) {
  Solid s;
  s.type = type;
  return s;
}

TEST(Tessellate, BoxFacesVolumeAndOrder) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::box);
  s.center = {1.0, 2.0};
  s.base = 0.5;
  s.size = {2.0, 1.0, 3.0};
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 6u);
  EXPECT_EQ(element_pointer(soup.objects[0].element), "/scene/solids/0");
  EXPECT_TRUE(soup.objects[0].closed);
  const Vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const double offsets[6] = {2.0, 0.0, 1.5, -0.5, 3.5, -0.5};
  for (size_t i = 0; i < 6; ++i) {
    expect_vec(soup.polygons[i].normal, normals[i]);
    EXPECT_NEAR(soup.polygons[i].offset, offsets[i], 1e-12);
    EXPECT_EQ(soup.polygons[i].flags, uint32_t(polygon_closed));
  }
  const auto all = polygons_of(soup, "/scene/solids/0");
  expect_closed(soup, all);
  expect_rel(total_area(soup, all), 2 * (2.0 * 1.0 + 2.0 * 3.0 + 1.0 * 3.0));
  expect_rel(volume(soup, all), 6.0);
}

TEST(Tessellate, RotationYIsCounterClockwiseSeenFromAbove) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::box);
  s.rotation_y_deg = 90.0;
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  expect_vec(soup.polygons[0].normal, {0, 0, -1});  // the box's +X face now faces -Z
  expect_vec(soup.polygons[4].normal, {1, 0, 0});   // and its +Z face faces +X
}

TEST(Tessellate, PyramidFourTrianglesThenBase) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::pyramid);
  s.size = {2.0, 3.0, 4.0};
  s.base = 1.0;
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 5u);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(soup.polygons[i].vertex_count, 3u);
  EXPECT_GT(soup.polygons[0].normal.x, 0.0);
  EXPECT_LT(soup.polygons[1].normal.x, 0.0);
  EXPECT_GT(soup.polygons[2].normal.z, 0.0);
  EXPECT_LT(soup.polygons[3].normal.z, 0.0);
  expect_vec(soup.polygons[4].normal, {0, -1, 0});
  const auto all = polygons_of(soup, "/scene/solids/0");
  expect_closed(soup, all);
  expect_rel(volume(soup, all), 2.0 * 4.0 * 3.0 / 3.0);
}

TEST(Tessellate, CylinderWithCapsIsClosedAndSmooth) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::cylinder);
  s.center = {1.0, -1.0};
  s.radius = 0.5;
  s.height = 2.0;
  s.segments = 8;
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 10u);  // 8 sides, top, bottom
  EXPECT_TRUE(soup.objects[0].closed);
  EXPECT_TRUE(soup.objects[0].smooth);
  expect_vec(soup.polygons[8].normal, {0, 1, 0});
  expect_vec(soup.polygons[9].normal, {0, -1, 0});
  EXPECT_EQ(soup.polygons[8].vertex_count, 8u);
  const auto all = polygons_of(soup, "/scene/solids/0");
  expect_closed(soup, all);
  expect_rel(volume(soup, all), 0.5 * 8 * 0.25 * std::sin(2 * pi / 8) * 2.0);  // inscribed octagon
  for (size_t i = 0; i < 8; ++i) {                                             // radial shading normals on the sides
    const Polygon& p = soup.polygons[i];
    for (size_t k = 0; k < 4; ++k) {
      const Vec3 v = soup.points(p)[k];
      const Vec3 radial = glm::normalize(Vec3(v.x - 1.0, 0.0, v.z + 1.0));
      expect_vec(Vec3(soup.vertex_normals(p)[k]), radial, 1e-6);
    }
  }
}

TEST(Tessellate, OpenCylinderHasOnlySidesFacingOut) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::cylinder);
  s.segments = 5;
  s.caps = false;
  s.smooth = false;
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 5u);
  EXPECT_FALSE(soup.objects[0].closed);
  for (const Polygon& p : soup.polygons) {
    EXPECT_EQ(p.flags, 0u);
    EXPECT_GT(glm::dot(centroid(soup, p), p.normal), 0.0);  // the axis is at the origin
    for (const glm::vec3& n : soup.vertex_normals(p)) expect_vec(Vec3(n), p.normal, 1e-6);
  }
}

TEST(Tessellate, ConcavePrismEitherOrientation) {
  // An L of area 3 in the plan, 1.5 high: 6 side quads, each cap 4 triangles.
  std::vector<Vec2> l_shape = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  for (int reversed = 0; reversed < 2; ++reversed) {
    SCOPED_TRACE(reversed ? "reversed" : "as given");
    StaticGeometry g;
    Solid s = make_solid(SolidType::prism);
    s.points = l_shape;
    s.base = 0.25;
    s.height = 1.5;
    g.solids = {s};
    const PolygonSoup soup = tessellate_checked(g);
    ASSERT_EQ(soup.polygons.size(), 14u);
    for (size_t i = 0; i < 6; ++i) EXPECT_NEAR(soup.polygons[i].normal.y, 0.0, 1e-15);
    for (size_t i = 6; i < 10; ++i) expect_vec(soup.polygons[i].normal, {0, 1, 0});
    for (size_t i = 10; i < 14; ++i) expect_vec(soup.polygons[i].normal, {0, -1, 0});
    const auto all = polygons_of(soup, "/scene/solids/0");
    expect_closed(soup, all);
    expect_rel(volume(soup, all), 3.0 * 1.5);
    std::reverse(l_shape.begin(), l_shape.end());
  }
}

TEST(Tessellate, StarPrismIsEarClippedExactly) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::prism);
  for (int k = 0; k < 10; ++k) {  // a five-pointed star, radii 1 and 0.4
    const double r = k % 2 ? 0.4 : 1.0, a = 2 * pi * k / 10;
    s.points.push_back({r * std::cos(a), r * std::sin(a)});
  }
  s.height = 1.0;
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  EXPECT_EQ(soup.polygons.size(), 10u + 2 * 8u);
  const auto all = polygons_of(soup, "/scene/solids/0");
  expect_closed(soup, all);
  expect_rel(volume(soup, all), 10 * 0.5 * 1.0 * 0.4 * std::sin(2 * pi / 10));
}

const std::vector<Vec3> tetrahedron_vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
// Counter-clockwise seen from outside.
const std::vector<std::vector<uint32_t>> tetrahedron_faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

Solid tetrahedron() {
  Solid s = make_solid(SolidType::mesh);
  s.mesh = make_mesh_data(tetrahedron_vertices, tetrahedron_faces, {});
  s.smooth = false;
  s.closed = true;
  return s;
}

TEST(Tessellate, MeshTetrahedronOnePolygonPerFace) {
  StaticGeometry g;
  g.solids = {tetrahedron()};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 4u);
  expect_vec(soup.polygons[0].normal, {0, 0, -1});
  expect_vec(soup.polygons[1].normal, {0, -1, 0});
  expect_vec(soup.polygons[2].normal, {-1, 0, 0});
  expect_vec(soup.polygons[3].normal, glm::normalize(Vec3(1, 1, 1)));
  EXPECT_TRUE(soup.objects[0].closed);
  EXPECT_FALSE(soup.objects[0].smooth);
  expect_rel(volume(soup, polygons_of(soup, "/scene/solids/0")), 1.0 / 6.0);
}

TEST(Tessellate, MeshTransformScalesThenRotatesThenTranslates) {
  StaticGeometry g;
  Solid s = tetrahedron();
  s.scale = {2.0, 3.0, 1.0};
  s.rotation_y_deg = 90.0;
  s.position = {10.0, 1.0, 0.0};
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  // Vertex 1 (1,0,0) -> scaled (2,0,0) -> rotated (0,0,-2) -> (10,1,-2); volume scales by 6.
  EXPECT_EQ(soup.points(soup.polygons[1])[1], Vec3(10.0, 1.0, -2.0));
  expect_rel(volume(soup, polygons_of(soup, "/scene/solids/0")), 1.0);
  s.scale = {-1.0, 1.0, 1.0};  // a mirror keeps faces outward
  g.solids = {s};
  expect_rel(volume(tessellate_checked(g), {0, 1, 2, 3}), 1.0 / 6.0);
}

TEST(Tessellate, SmoothMeshAveragesNormalsByArea) {
  StaticGeometry g;
  Solid s = tetrahedron();
  s.smooth = true;
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  EXPECT_TRUE(soup.objects[0].smooth);
  // Vertex 0 touches the three axis faces of equal area; it is the first vertex of face 0.
  expect_vec(Vec3(soup.vertex_normals(soup.polygons[0])[0]), -glm::normalize(Vec3(1, 1, 1)), 1e-6);
  // Vertex 3: faces 1 and 2 (area 1/2, normals -y and -x) and face 3 (area sqrt(3)/2, (1,1,1)/sqrt3).
  const Vec3 sum = 0.5 * Vec3(0, -1, 0) + 0.5 * Vec3(-1, 0, 0) + 0.5 * Vec3(1, 1, 1);
  expect_vec(Vec3(soup.vertex_normals(soup.polygons[3])[2]), glm::normalize(sum), 1e-6);
}

TEST(Tessellate, MeshNonConvexFaceBecomesConsecutiveTriangles) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::mesh);
  s.smooth = false;
  // An L-shaped face at y = 1 wound counter-clockwise seen from above (+Y), then a triangle.
  s.mesh = make_mesh_data({{0, 1, 0}, {2, 1, 0}, {2, 1, 1}, {1, 1, 1}, {1, 1, 2}, {0, 1, 2}, {5, 0, 0}, {6, 0, 0}},
                          {{0, 5, 4, 3, 2, 1}, {0, 6, 7}}, {});
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 5u);  // 4 triangles (ids 0..3), then the triangle face (id 4)
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(soup.polygons[i].vertex_count, 3u);
    expect_vec(soup.polygons[i].normal, {0, 1, 0});
  }
  expect_rel(total_area(soup, {0, 1, 2, 3}), 3.0);
  EXPECT_FALSE(soup.objects[0].closed);
}

TEST(Tessellate, MeshLPrismWithNonConvexCapsIsClosed) {
  StaticGeometry g;
  Solid s = make_solid(SolidType::mesh);
  s.smooth = false;
  s.closed = true;
  const Vec2 l_shape[6] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};  // clockwise from above
  std::vector<Vec3> vertices;
  for (double y : {0.0, 1.0}) {
    for (Vec2 p : l_shape) vertices.push_back({p.x, y, p.y});
  }
  std::vector<std::vector<uint32_t>> faces = {{0, 1, 2, 3, 4, 5}, {6, 11, 10, 9, 8, 7}};  // bottom (-Y), top (+Y)
  for (uint32_t i = 0; i < 6; ++i) faces.push_back({i, i + 6, (i + 1) % 6 + 6, (i + 1) % 6});
  s.mesh = make_mesh_data(vertices, faces, {});
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  EXPECT_EQ(soup.polygons.size(), 4u + 4u + 6u);
  const auto all = polygons_of(soup, "/scene/solids/0");
  expect_closed(soup, all);
  expect_rel(volume(soup, all), 3.0);
}

TEST(Tessellate, DegenerateAndNonPlanarMeshFaces) {
  StaticGeometry g;
  Solid s = tetrahedron();
  s.closed = false;
  std::vector<Vec3> vertices = tetrahedron_vertices;
  std::vector<std::vector<uint32_t>> faces = tetrahedron_faces;
  vertices.push_back({2, 0, 0});     // 4: collinear with 0 and 1
  vertices.push_back({3, 0, 0});     // 5
  vertices.push_back({3, 0, 1});     // 6
  vertices.push_back({2, 1e-7, 1});  // 7: 1e-7 off the plane of 4, 5, 6
  faces.push_back({0, 1, 4});        // zero area: dropped
  faces.push_back({4, 7, 6, 5});     // planar only to 1e-7: two triangles
  s.mesh = make_mesh_data(vertices, faces, {});
  g.solids = {s};
  const PolygonSoup soup = tessellate_checked(g);
  ASSERT_EQ(soup.polygons.size(), 4u + 2u);
  EXPECT_EQ(soup.polygons[4].vertex_count, 3u);
  EXPECT_GT(soup.polygons[4].normal.y, 0.999);
}

TEST(Tessellate, EstimateBoundsACombinedScene) {
  StaticGeometry g = door_and_window_wall();
  g.has_floor = true;
  g.floor.cells_x = 4;
  g.floor.cells_z = 3;
  g.floor.colors = {{1, 1, 1}, {0, 0, 0}};
  for (SolidType t : {SolidType::box, SolidType::cylinder, SolidType::pyramid}) g.solids.push_back(make_solid(t));
  Solid prism = make_solid(SolidType::prism);
  prism.points = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  g.solids.push_back(prism);
  g.solids.push_back(tetrahedron());
  const PolygonSoup soup = tessellate_checked(g);
  EXPECT_EQ(soup.polygons.size(), 12u + 31u + 6u + 34u + 5u + 14u + 4u);
  // Object pointers in order: floor, wall, its two openings, then the solids.
  ASSERT_EQ(soup.objects.size(), 9u);
  EXPECT_EQ(element_pointer(soup.objects[3].element), "/scene/walls/0/openings/1");
  EXPECT_EQ(element_pointer(soup.objects[8].element), "/scene/solids/4");
  StaticGeometry empty;
  EXPECT_EQ(estimate_polygon_count(empty), 0u);
  EXPECT_TRUE(tessellate(empty).polygons.empty());
}

TEST(Tessellate, PolygonAreaUsesNewell) {
  const Vec3 tilted[4] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 1}, {0, 1, 1}};  // 2 x sqrt(2)
  EXPECT_NEAR(polygon_area(tilted), 2.0 * std::sqrt(2.0), 1e-15);
  const Vec3 collinear[3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  EXPECT_EQ(polygon_area(collinear), 0.0);
}

}  // namespace
}  // namespace rr

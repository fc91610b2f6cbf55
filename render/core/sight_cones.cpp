// Sight cones (see sight_cones.hpp). The intersection of half-spaces and a box is a convex polytope;
// when it is not empty, each of its faces lies on one of the planes, so it is empty exactly when a
// square covering the box's section of every plane, clipped by all the other half-spaces, is empty.
// Moving every plane out by the tolerance gives a touching contact a face of its own and covers the
// clipping's rounding, so the answer errs only toward "they meet".
#include "render/core/sight_cones.hpp"

#include <array>
#include <cmath>

namespace rr {

void add_sight_cone(const Mat4& m, const ViewRegion& region, std::vector<HalfSpace>& out) {
  // Rows of the (column-major) matrix: clip x, y and w as functions of the world point.
  auto row = [&](int i) { return glm::dvec4(m[0][i], m[1][i], m[2][i], m[3][i]); };
  const glm::dvec4 x = row(0), y = row(1), w = row(3);
  const std::array<glm::dvec4, 5> rows{x - region.x0 * w, region.x1 * w - x, y - region.y0 * w, region.y1 * w - y, w};
  for (const glm::dvec4& r : rows) {
    const Vec3 n(r);
    const double length = glm::length(n);
    if (length > 0.0) out.push_back({n / length, r.w / length});
  }
}

namespace {

// The polygon's part where n . p + d + tolerance >= 0 (Sutherland-Hodgman, one plane).
void clip(std::vector<Vec3>& polygon, const HalfSpace& h, double tolerance, std::vector<Vec3>& scratch) {
  scratch.clear();
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % polygon.size()];
    const double da = glm::dot(h.n, a) + h.d + tolerance, db = glm::dot(h.n, b) + h.d + tolerance;
    if (da >= 0.0) scratch.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) scratch.push_back(a + (da / (da - db)) * (b - a));
  }
  polygon.swap(scratch);
}

}  // namespace

bool box_outside_half_spaces(std::span<const HalfSpace> half_spaces, Vec3 lo, Vec3 hi, double tolerance) {
  // The corner farthest inside each half-space; the box moved out by the tolerance too.
  for (const HalfSpace& h : half_spaces) {
    const Vec3 corner(h.n.x >= 0.0 ? hi.x : lo.x, h.n.y >= 0.0 ? hi.y : lo.y, h.n.z >= 0.0 ? hi.z : lo.z);
    if (glm::dot(h.n, corner) + h.d + 2.0 * tolerance < 0.0) return true;
  }
  return false;
}

bool half_spaces_meet_in_box(std::span<const HalfSpace> half_spaces, Vec3 lo, Vec3 hi, double tolerance) {
  if (box_outside_half_spaces(half_spaces, lo, hi, tolerance)) return false;
  std::vector<HalfSpace> all(half_spaces.begin(), half_spaces.end());
  for (int a = 0; a < 3; ++a) {
    Vec3 n(0.0);
    n[a] = 1.0;
    all.push_back({n, -lo[a]});  // p[a] >= lo[a]
    all.push_back({-n, hi[a]});  // p[a] <= hi[a]
  }
  const Vec3 center = 0.5 * (lo + hi);
  const double size = glm::length(hi - lo) + 4.0 * tolerance + 1.0;
  std::vector<Vec3> polygon, scratch;
  for (size_t i = 0; i < all.size(); ++i) {
    const HalfSpace& h = all[i];
    // A square on the plane, centred on its point nearest the box's centre: it covers every point
    // of the plane within `size` of that centre, so the plane's whole section of the box.
    const Vec3 p0 = center - (glm::dot(h.n, center) + h.d) * h.n;
    const Vec3 u = glm::normalize(glm::cross(h.n, std::abs(h.n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
    const Vec3 v = glm::cross(h.n, u);
    const double s = 2.0 * size;
    polygon = {p0 - s * u - s * v, p0 + s * u - s * v, p0 + s * u + s * v, p0 - s * u + s * v};
    for (size_t j = 0; j < all.size() && !polygon.empty(); ++j) {
      if (j != i) clip(polygon, all[j], tolerance, scratch);
    }
    if (!polygon.empty()) return true;
  }
  return false;
}

}  // namespace rr

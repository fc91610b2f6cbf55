// Crossing polygons (see surface_contact.hpp): boxes first, then the separating axes of two convex
// planar polygons that are not coplanar (the two normals and the cross products of their edges).
#include "render/core/surface_contact.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace rr {

namespace {

struct Box {
  Vec3 lo{std::numeric_limits<double>::max()}, hi{std::numeric_limits<double>::lowest()};
};

Box box_of(std::span<const Vec3> points) {
  Box b;
  for (const Vec3& p : points) b.lo = glm::min(b.lo, p), b.hi = glm::max(b.hi, p);
  return b;
}

// Not apart on any axis (a flat polygon's box has no thickness on one axis, so touching counts).
bool boxes_meet(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k) {
    if (std::min(a.hi[k], b.hi[k]) < std::max(a.lo[k], b.lo[k])) return false;
  }
  return true;
}

std::pair<double, double> extent(std::span<const Vec3> points, Vec3 axis) {
  double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
  for (const Vec3& p : points) {
    const double d = glm::dot(p, axis);
    lo = std::min(lo, d), hi = std::max(hi, d);
  }
  return {lo, hi};
}

// A polygon's extent along an axis up to this (metres) is rounding: it lies flat across the axis.
constexpr double flat_m = 1e-9;

// `points` reach more than `t` beyond the plane (normal, offset) on both of its sides.
bool straddles(std::span<const Vec3> points, Vec3 normal, double offset, double t) {
  auto [lo, hi] = extent(points, normal);
  return lo < offset - t && hi > offset + t;
}

// Two convex planar polygons pass through each other. Each must straddle the other's plane (so
// coplanar and touching pairs never cross), and no edge-cross axis may separate them.
bool polygons_cross(const PolygonSoup& soup, const Polygon& p, const Polygon& q, double t, size_t& work) {
  const std::span<const Vec3> a = soup.points(p), b = soup.points(q);
  work += 2 * (a.size() + b.size());
  if (!straddles(b, p.normal, p.offset, t) || !straddles(a, q.normal, q.offset, t)) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const Vec3 ea = a[(i + 1) % a.size()] - a[i];
    for (size_t j = 0; j < b.size(); ++j) {
      const Vec3 axis = glm::cross(ea, b[(j + 1) % b.size()] - b[j]);
      const double length = glm::length(axis);
      if (!(length > 1e-12)) continue;  // parallel edges: the normals' tests stand for this axis
      work += a.size() + b.size();
      auto [a_lo, a_hi] = extent(a, axis / length);
      auto [b_lo, b_hi] = extent(b, axis / length);
      // A polygon lying flat across the axis projects to a point (up to rounding): within the
      // other's span it is not apart (a table top's face through the side of another's top).
      const double overlap = std::min(a_hi, b_hi) - std::max(a_lo, b_lo);
      const bool flat = a_hi - a_lo <= flat_m || b_hi - b_lo <= flat_m;
      if (flat ? overlap < -flat_m : overlap <= 0.0) return false;
    }
  }
  return true;
}

}  // namespace

ContactResult surfaces_cross(const PolygonSoup& soup, std::span<const uint32_t> a, std::span<const uint32_t> b,
                             double tolerance, size_t& work, size_t budget) {
  Box a_all, b_all;
  std::vector<Box> a_boxes, b_boxes;
  a_boxes.reserve(a.size()), b_boxes.reserve(b.size());
  for (uint32_t i : a) a_boxes.push_back(box_of(soup.points(soup.polygons[i])));
  for (uint32_t i : b) b_boxes.push_back(box_of(soup.points(soup.polygons[i])));
  for (const Box& x : a_boxes) a_all.lo = glm::min(a_all.lo, x.lo), a_all.hi = glm::max(a_all.hi, x.hi);
  for (const Box& x : b_boxes) b_all.lo = glm::min(b_all.lo, x.lo), b_all.hi = glm::max(b_all.hi, x.hi);
  work += a.size() + b.size();
  // Only the polygons that reach into the other set's box can cross one of its polygons.
  std::vector<size_t> near_b;
  for (size_t j = 0; j < b.size(); ++j) {
    if (boxes_meet(b_boxes[j], a_all)) near_b.push_back(j);
  }
  for (size_t i = 0; i < a.size(); ++i) {
    if (!boxes_meet(a_boxes[i], b_all)) continue;
    for (size_t j : near_b) {
      if (work > budget) return ContactResult::out_of_work;
      ++work;
      if (!boxes_meet(a_boxes[i], b_boxes[j])) continue;
      if (polygons_cross(soup, soup.polygons[a[i]], soup.polygons[b[j]], tolerance, work)) return ContactResult::cross;
    }
  }
  return ContactResult::apart;
}

}  // namespace rr

// Solid type "prism": a simple plan polygon (either orientation) extruded `height` up from `base`.
// Side quads and two caps (ear-clipped when not convex); closed, never smooth.
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

#include <vector>

namespace rr::detail {

namespace {

// Side quads (edge i runs from points[i] to points[i+1]), then the top cap, then the bottom cap.
// rotation_y turns the prism about the area centroid of its footprint (the prism has no centre).
void add_prism(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  std::vector<Vec2> plan;
  for (const Vec2& p : s.points) {
    if (plan.empty() || p != plan.back()) plan.push_back(p);
  }
  while (plan.size() > 1 && plan.front() == plan.back()) plan.pop_back();
  if (plan.size() < 3) return;
  const double area2 = twice_signed_area(plan);
  if (s.rotation_y_deg != 0.0 && area2 != 0.0) {
    Vec2 centroid{0.0};
    for (size_t i = 0; i < plan.size(); ++i) {
      const Vec2 p = plan[i] - plan[0], q = plan[(i + 1) % plan.size()] - plan[0];
      centroid += (p + q) * cross2(p, q);
    }
    centroid = plan[0] + centroid / (3.0 * area2);
    for (Vec2& p : plan) p = centroid + rotate_plan(p - centroid, radians(s.rotation_y_deg));
  }
  // In (x, z) a negative signed area is counter-clockwise seen from above; outward is then to the
  // right of each edge. Either input orientation is accepted.
  const double right = area2 < 0.0 ? 1.0 : -1.0;
  const double top = s.base + s.height;
  const size_t n = plan.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = plan[i], b = plan[(i + 1) % n], e = b - a;
    const Vec3 quad[4] = {plan_to_world(a, s.base), plan_to_world(b, s.base), plan_to_world(b, top),
                          plan_to_world(a, top)};
    out.add_polygon(quad, right * Vec3(-e.y, 0.0, e.x), material, object);
  }
  std::vector<Vec3> cap(n);
  for (double y : {top, s.base}) {
    for (size_t i = 0; i < n; ++i) cap[i] = plan_to_world(plan[i], y);
    add_face(out, cap, {}, {0.0, y == top ? 1.0 : -1.0, 0.0}, material, object);
  }
}

// n sides, each cap at most n - 2 triangles.
size_t estimate_prism(const Solid& s) {
  const size_t n = s.points.size();
  return n + 2 * (n > 2 ? n - 2 : 1);
}

}  // namespace

extern const SolidInfo prism_solid = {SolidType::prism,
                                      "prism",
                                      add_prism,
                                      estimate_prism,
                                      [](const Solid&) { return true; },
                                      [](const Solid&) { return false; }};

}  // namespace rr::detail

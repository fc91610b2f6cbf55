// Solid type "pyramid": a rectangular base of (sx, sz) on `base` with its apex `height` above the
// centre, turned by rotation_y. Four triangles and the base; closed, never smooth.
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

namespace rr::detail {

namespace {

// Triangles on the +X, -X, +Z, -Z sides of the pyramid's own frame, then the base quad.
void add_pyramid(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const double a = radians(s.rotation_y_deg);
  const auto corner = [&](double sx, double sz) {
    return plan_to_world(s.center + rotate_plan({sx * 0.5 * s.size.x, sz * 0.5 * s.size.z}, a), s.base);
  };
  const Vec3 apex{s.center.x, s.base + s.size.y, s.center.y};
  const Vec3 side_x = plan_to_world(rotate_plan({1.0, 0.0}, a), 0.0);
  const Vec3 side_z = plan_to_world(rotate_plan({0.0, 1.0}, a), 0.0);
  const Vec3 faces[4][3] = {{corner(1, -1), corner(1, 1), apex},
                            {corner(-1, 1), corner(-1, -1), apex},
                            {corner(1, 1), corner(-1, 1), apex},
                            {corner(-1, -1), corner(1, -1), apex}};
  const Vec3 outward[4] = {side_x, -side_x, side_z, -side_z};
  for (int i = 0; i < 4; ++i) out.add_polygon(faces[i], outward[i], material, object);
  const Vec3 base[4] = {corner(1, -1), corner(1, 1), corner(-1, 1), corner(-1, -1)};
  out.add_polygon(base, {0.0, -1.0, 0.0}, material, object);
}

}  // namespace

extern const SolidInfo pyramid_solid = {SolidType::pyramid,
                                        "pyramid",
                                        add_pyramid,
                                        [](const Solid&) -> size_t { return 5; },
                                        [](const Solid&) { return true; },
                                        [](const Solid&) { return false; }};

}  // namespace rr::detail

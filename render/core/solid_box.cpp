// Solid type "box": a cuboid of size (sx, height, sz) standing on `base`, centred on `center` in the
// plan and turned by rotation_y about its vertical axis. Six faces; closed, never smooth.
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

namespace rr::detail {

namespace {

// Faces +X, -X, +Y (top), -Y (bottom), +Z, -Z of the box's own (unrotated) frame.
void add_box(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const double a = radians(s.rotation_y_deg);
  const Vec2 x = rotate_plan({1.0, 0.0}, a), z = rotate_plan({0.0, 1.0}, a);
  add_cuboid(out, {s.center.x, s.base + 0.5 * s.size.y, s.center.y}, plan_to_world(x, 0.0) * (0.5 * s.size.x),
             {0.0, 0.5 * s.size.y, 0.0}, plan_to_world(z, 0.0) * (0.5 * s.size.z), material, object);
}

}  // namespace

extern const SolidInfo box_solid = {SolidType::box,
                                    "box",
                                    add_box,
                                    [](const Solid&) -> size_t { return 6; },
                                    [](const Solid&) { return true; },
                                    [](const Solid&) { return false; }};

}  // namespace rr::detail

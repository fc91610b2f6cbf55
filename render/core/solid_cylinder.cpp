// Solid type "cylinder": `segments` side quads around `center` (radius, height, from `base`),
// smooth-shaded by default; closed only with its caps.
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rr::detail {

namespace {

// Side quads (segment k spans angles k and k+1, counter-clockwise from the rotated +X seen from
// above), then the top cap, then the bottom cap.
void add_cylinder(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const int n = std::max(3, s.segments);
  const double top = s.base + s.height, a0 = radians(s.rotation_y_deg);
  const auto radial = [&](double k) {
    const double phi = a0 + 2.0 * pi * k / n;
    return Vec3(std::cos(phi), 0.0, -std::sin(phi));
  };
  std::vector<Vec3> bottom_ring, top_ring;
  for (int k = 0; k < n; ++k) {
    const Vec3 p = Vec3(s.center.x, 0.0, s.center.y) + s.radius * radial(k);
    bottom_ring.push_back({p.x, s.base, p.z});
    top_ring.push_back({p.x, top, p.z});
  }
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    const Vec3 quad[4] = {bottom_ring[k], bottom_ring[k1], top_ring[k1], top_ring[k]};
    const glm::vec3 smooth[4] = {glm::vec3(radial(k)), glm::vec3(radial(k + 1)), glm::vec3(radial(k + 1)),
                                 glm::vec3(radial(k))};
    out.add_polygon(quad, radial(k + 0.5), material, object,
                    s.smooth ? std::span<const glm::vec3>(smooth) : std::span<const glm::vec3>());
  }
  if (!s.caps) return;
  out.add_polygon(top_ring, {0.0, 1.0, 0.0}, material, object);
  out.add_polygon(bottom_ring, {0.0, -1.0, 0.0}, material, object);
}

}  // namespace

extern const SolidInfo cylinder_solid = {SolidType::cylinder,
                                         "cylinder",
                                         add_cylinder,
                                         [](const Solid& s) { return size_t(std::max(3, s.segments)) + 2; },
                                         [](const Solid& s) { return s.caps; },
                                         [](const Solid& s) { return s.smooth; }};

}  // namespace rr::detail

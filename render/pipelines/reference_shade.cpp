// Shading of one reference hit (see reference_detail.hpp): the lighting model of shading.hpp in
// doubles at the exact hit point, with the vertex normals interpolated over the polygon's fan (the
// triangulation the rasterizer draws), and one exact shadow ray per light instead of a shadow map.
#include "render/pipelines/reference_detail.hpp"

#include "render/core/shading.hpp"
#include "render/core/shading_detail.hpp"

#include <algorithm>

namespace rr::reference_detail {

namespace {

// The shading normal at p: the vertex normals weighted over the fan triangle holding p, as Phong
// mode interpolates them; the face normal where they cancel out.
Vec3 interpolated_normal(const PolygonSoup& soup, const Polygon& poly, Vec3 p) {
  const auto points = soup.points(poly);
  const auto normals = soup.vertex_normals(poly);
  const shading_detail::FanPoint at = shading_detail::locate_in_fan(points, poly.normal, p);
  const Vec3 n = at.w[0] * Vec3(normals[0]) + at.w[1] * Vec3(normals[at.j]) + at.w[2] * Vec3(normals[at.j + 1]);
  const double length = glm::length(n);
  return length > 0.0 ? n / length : poly.normal;
}

// Whether an opaque polygon other than `self` blocks the segment from p to the light. Casters are
// those the shadow pass draws (shadow.cpp's caster_side): not translucent, not edge-on to the
// light, and for closed objects only the faces turned away from it (same silhouette). The ray
// starts `eps` away from p so that p's own polygon and its neighbours at a shared edge do not
// shadow it by rounding: 1e-9 of the scene size plus 1e-12 of its distance from the origin (the
// rounding of p itself far from the origin).
bool occluded(const ReferenceScene& rs, uint32_t self, Vec3 p, const Light& light) {
  const PolygonSoup& soup = rs.input.soup;
  const bool directional = light.type == LightType::directional;
  const double eps = 1e-9 * rs.scene_size + 1e-12 * rs.scene_magnitude;
  Vec3 direction = -light.direction;
  double t_min = eps, t_max = std::numeric_limits<double>::infinity();
  if (!directional) {
    direction = light.position - p;
    const double distance = glm::length(direction);
    if (!(distance > 2.0 * eps)) return false;
    t_min = eps / distance;
    t_max = 1.0 - t_min;
  }
  const BvhRay ray(p, direction);
  bool blocked = false;
  traverse_bvh(rs.shadow_bvh, ray, t_min, t_max, [&](uint32_t j, double&) {
    if (j == self) return false;
    const Polygon& q = soup.polygons[j];
    const double facing =
        directional ? glm::dot(q.normal, light.direction) : q.offset - glm::dot(q.normal, light.position);
    if (facing == 0.0 || ((q.flags & polygon_closed) && facing < 0.0)) return false;
    blocked = intersect_polygon(soup, q, p, direction, t_min, t_max).has_value();
    return blocked;
  });
  return blocked;
}

}  // namespace

Color shade_hit(const ReferenceScene& rs, const Hit& hit, Vec3 p, std::span<uint8_t> lit) {
  const FrameInput& in = rs.input;
  const Polygon& poly = in.soup.polygons[hit.polygon];
  const Material& material = in.soup.materials[poly.material];
  const double sign = lit_side(poly, in.view.eye);
  const Vec3 n = sign * interpolated_normal(in.soup, poly, p);
  glm::dvec3 irradiance = shading_detail::ambient_irradiance(in.scene), specular(0.0);
  std::fill(lit.begin(), lit.end(), uint8_t(0));
  const auto& lights = in.scene.lights;
  for (size_t l = 0; l < lights.size(); ++l) {
    // As SurfaceShader: a light behind the lit side's plane is not evaluated at all.
    if (!light_reaches(lights[l], sign * poly.normal, sign * poly.offset)) continue;
    if (rs.shadows && occluded(rs, hit.polygon, p, lights[l])) continue;
    if (!lit.empty()) lit[l / 8] |= uint8_t(1u << (l % 8));
    const LightTerms t = light_terms(lights[l], material, p, n, in.view.eye);
    irradiance += t.irradiance;
    specular += t.specular;
  }
  return Color(glm::dvec3(material.color) * irradiance + specular);
}

}  // namespace rr::reference_detail

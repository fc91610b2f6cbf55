// Shading of one reference hit (see reference_detail.hpp): the lighting model of shading.hpp in
// doubles at the exact hit point, with the vertex normals interpolated over the polygon's fan (the
// triangulation the rasterizer draws), and one exact shadow ray per light instead of a shadow map.
#include "render/pipelines/reference_detail.hpp"

#include "render/core/shading.hpp"
#include "render/core/shading_detail.hpp"
#include "render/core/shadow_rays.hpp"
#include "render/core/surface.hpp"

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

// The segment from p to the light, as occluded() and transmitted() cast it.
struct ShadowSegment {
  Vec3 direction;
  double t_min, t_max;
  bool empty;  // a point light within 2 eps of p: never blocked
};

ShadowSegment shadow_segment(const ReferenceScene& rs, Vec3 p, const Light& light) {
  const double eps = 1e-9 * rs.scene_size + 1e-12 * rs.scene_magnitude;
  if (light.type == LightType::directional)
    return {-light.direction, eps, std::numeric_limits<double>::infinity(), false};
  const Vec3 direction = light.position - p;
  const double distance = glm::length(direction);
  if (!(distance > 2.0 * eps)) return {direction, 0.0, 0.0, true};
  return {direction, eps / distance, 1.0 - eps / distance, false};
}

// Whether polygon q counts as a caster of `light`: not edge-on to it, and for a closed object only
// the faces turned away from it (the same silhouette).
bool casts(const Polygon& q, const Light& light) {
  const double facing = light.type == LightType::directional ? glm::dot(q.normal, light.direction)
                                                             : q.offset - glm::dot(q.normal, light.position);
  return facing != 0.0 && !((q.flags & polygon_closed) && facing < 0.0);
}

// Whether an opaque polygon other than `self` blocks the segment from p to the light. Casters are
// those the shadow pass draws (shadow.cpp's caster_side): not translucent, not edge-on to the
// light, and for closed objects only the faces turned away from it (same silhouette). The ray
// starts `eps` away from p so that p's own polygon and its neighbours at a shared edge do not
// shadow it by rounding: 1e-9 of the scene size plus 1e-12 of its distance from the origin (the
// rounding of p itself far from the origin).
bool occluded(const ReferenceScene& rs, uint32_t self, Vec3 p, const Light& light) {
  const PolygonSoup& soup = rs.input.soup;
  ShadowSegment s = shadow_segment(rs, p, light);
  if (s.empty) return false;
  const BvhRay ray(p, s.direction);
  bool blocked = false;
  traverse_bvh(rs.shadow_bvh, ray, s.t_min, s.t_max, [&](uint32_t j, double&) {
    if (j == self || !casts(soup.polygons[j], light)) return false;
    blocked = intersect_polygon(soup, soup.polygons[j], p, s.direction, s.t_min, s.t_max).has_value();
    return blocked;
  });
  return blocked;
}

// The light that the panes (translucent polygons) between p and the light let through: the product
// of pane_transmittance over every pane other than `self` the segment crosses, by the casters' rule.
glm::dvec3 transmitted(const ReferenceScene& rs, uint32_t self, Vec3 p, const Light& light) {
  const PolygonSoup& soup = rs.input.soup;
  glm::dvec3 through(1.0);
  ShadowSegment s = shadow_segment(rs, p, light);
  if (s.empty || rs.glass_bvh.nodes.empty()) return through;
  const BvhRay ray(p, s.direction);
  traverse_bvh(rs.glass_bvh, ray, s.t_min, s.t_max, [&](uint32_t j, double&) {
    const Polygon& q = soup.polygons[j];
    if (j != self && casts(q, light) && intersect_polygon(soup, q, p, s.direction, s.t_min, s.t_max))
      through *= pane_transmittance(soup.materials[q.material]);
    return false;
  });
  return through;
}

}  // namespace

Color shade_hit(const ReferenceScene& rs, const Hit& hit, Vec3 p, double sx, double sy, std::span<uint8_t> lit) {
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
    if (rs.shadows && !rs.glass_bvh.nodes.empty()) {
      const glm::dvec3 through = transmitted(rs, hit.polygon, p, lights[l]);
      irradiance += t.irradiance * through;
      specular += t.specular * through;
      continue;
    }
    irradiance += t.irradiance;
    specular += t.specular;
  }
  if (poly.uv_map != 0) {
    const Color albedo = surface_albedo(in.soup, poly, rs.pixel_rays, sx, sy, {in.options.texture_filter, true});
    return Color(glm::dvec3(albedo) * irradiance + specular);
  }
  return Color(glm::dvec3(material.color) * irradiance + specular);
}

}  // namespace rr::reference_detail

// Ambient + Lambert lighting shared by the pipelines. Colours are display values used as given (no
// gamma), the classic fixed-function model; results are not clamped here (to_byte clamps).
#include "render/shading.hpp"

#include <array>

namespace rr {

namespace {
constexpr std::array<ShadingInfo, 1> shadings = {{
    {ShadingMode::flat, "flat"},
}};
}  // namespace

std::span<const ShadingInfo> shading_table() { return shadings; }

const ShadingInfo* find_shading(std::string_view name) {
  for (const ShadingInfo& s : shadings) {
    if (name == s.name) return &s;
  }
  return nullptr;
}

Color shade_lambert(const Scene& scene, const Material& material, Vec3 p_world, Vec3 n) {
  glm::dvec3 light_sum = glm::dvec3(scene.ambient.color) * double(scene.ambient.intensity);
  for (const Light& light : scene.lights) {
    glm::dvec3 to_light;
    double attenuation = 1.0;
    if (light.type == LightType::directional) {
      to_light = -light.direction;
    } else {
      glm::dvec3 d = light.position - p_world;
      double dist = glm::length(d);
      if (dist <= 0.0) continue;
      to_light = d / dist;
      const Vec3& k = light.attenuation;
      attenuation = 1.0 / (k.x + k.y * dist + k.z * dist * dist);
    }
    double cos_theta = glm::dot(n, to_light);
    if (cos_theta <= 0.0) continue;  // light behind the surface: no diffuse term
    light_sum += glm::dvec3(light.color) * (double(light.intensity) * cos_theta * attenuation);
  }
  return Color(glm::dvec3(material.color) * light_sum);
}

Color shade_flat(const Scene& scene, const PolygonSoup& soup, const Polygon& polygon, Vec3 eye) {
  auto points = soup.points(polygon);
  Vec3 centroid(0.0);
  for (const Vec3& p : points) centroid += p;
  centroid /= double(points.size());
  Vec3 n = polygon.normal;
  // Open surfaces are lit on the side the eye sees; closed ones are only ever seen from the front.
  if (!(polygon.flags & polygon_closed) && glm::dot(n, eye) - polygon.offset < 0.0) n = -n;
  return shade_lambert(scene, soup.materials[polygon.material], centroid, n);
}

SurfaceShader::SurfaceShader(const FrameInput& input, const PolygonSoup& soup)
    : input_(input), soup_(soup), flat_(soup.polygons.size()) {}

void SurfaceShader::prepare(uint32_t index) {
  flat_[index] = shade_flat(input_.scene, soup_, soup_.polygons[index], input_.view.eye);
}

void SurfaceShader::bind(uint32_t index, const DrawScratch&) { current_ = flat_[index]; }

}  // namespace rr

// Blinn-Phong lighting and the three shading modes (see shading.hpp, docs/lighting.md). Per-polygon
// and per-vertex lighting (flat, Gouraud) is computed in doubles in prepare(); Phong evaluates the
// same model per pixel in floats, from the position and normal interpolated across the clipped
// polygon. Each light's term is kept apart from the rest while it has a shadow map, so that the
// pixel can scale it by its visibility; every other light is summed in light order.
#include "render/core/shading.hpp"

#include "render/core/shading_detail.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace rr {

using shading_detail::ambient_irradiance;
using shading_detail::FanPoint;
using shading_detail::locate_in_fan;

LightTerms light_terms(const Light& light, const Material& material, Vec3 p, Vec3 n, Vec3 eye) {
  LightTerms t;
  glm::dvec3 to_light;
  double attenuation = 1.0;
  if (light.type == LightType::directional) {
    to_light = -light.direction;
  } else {
    const glm::dvec3 d = light.position - p;
    const double dist = glm::length(d);
    if (dist <= 0.0) return t;
    to_light = d / dist;
    const Vec3& k = light.attenuation;
    attenuation = 1.0 / (k.x + k.y * dist + k.z * dist * dist);
  }
  const double cos_theta = glm::dot(n, to_light);
  if (cos_theta <= 0.0) return t;  // light behind the surface: neither diffuse nor specular
  const glm::dvec3 radiance = glm::dvec3(light.color) * double(light.intensity);
  t.irradiance = radiance * (cos_theta * attenuation);
  const MaterialParams& m = material.params;
  if (m.specular > 0.0f) {
    const glm::dvec3 to_eye = eye - p;
    const glm::dvec3 h = to_light + (glm::length(to_eye) > 0.0 ? glm::normalize(to_eye) : n);
    const double n_dot_h = glm::length(h) > 0.0 ? glm::dot(n, glm::normalize(h)) : 0.0;
    if (n_dot_h > 0.0) {
      t.specular = glm::dvec3(m.specular_color) * radiance *
                   (double(m.specular) * std::pow(n_dot_h, double(m.shininess)) * attenuation);
    }
  }
  return t;
}

Color shade_point(const Scene& scene, const Material& material, Vec3 p, Vec3 n, Vec3 eye) {
  glm::dvec3 irradiance = ambient_irradiance(scene), specular(0.0);
  for (const Light& light : scene.lights) {
    const LightTerms t = light_terms(light, material, p, n, eye);
    irradiance += t.irradiance;
    specular += t.specular;
  }
  return Color(glm::dvec3(material.color) * irradiance + specular);
}

// --- SurfaceShader: prepare ------------------------------------------------------------------------

SurfaceShader::SurfaceShader(const FrameInput& input, const PolygonSoup& soup)
    : input_(input),
      soup_(soup),
      lights_evaluated_(input.lights_evaluated),
      maps_(input.shadows && !input.shadows->empty() ? input.shadows : nullptr),
      rays_(maps_ ? nullptr : input.shadow_rays),
      glass_(rays_ ? (rays_->glass.nodes.empty() ? nullptr : rays_)
             : maps_ && input.glass_rays && !input.glass_rays->glass.nodes.empty() ? input.glass_rays
                                                                                   : nullptr),
      mode_(input.options.shading),
      slots_(maps_   ? maps_->lights.size()
             : rays_ ? input.scene.lights.size()
                     : 0),
      term_begin_(mode_ == ShadingMode::phong ? 0 : soup.polygons.size(), 0),
      slot_sums_(slots_),
      textured_soup_(!soup.uv_maps.empty()),
      pixel_rays_(pixel_rays(input.view)),
      sampling_{input.options.texture_filter, false},
      memos_(rays_ ? slots_ : 0),
      mask_(input.shadow_mask),
      mask_bytes_(input.shadow_mask_bytes) {}

SurfaceShader::SurfaceShader(const SurfaceShader& prepared, size_t* lights_evaluated)
    : input_(prepared.input_),
      soup_(prepared.soup_),
      prepared_(&prepared),
      lights_evaluated_(lights_evaluated),
      maps_(prepared.maps_),
      rays_(prepared.rays_),
      glass_(prepared.glass_),
      mode_(prepared.mode_),
      slots_(prepared.slots_),
      slot_sums_(slots_),
      textured_soup_(prepared.textured_soup_),
      pixel_rays_(prepared.pixel_rays_),
      sampling_(prepared.sampling_),
      memos_(rays_ ? slots_ : 0),
      mask_(prepared.mask_),
      mask_bytes_(prepared.mask_bytes_) {}

SurfaceShader::~SurfaceShader() {
  if (lights_evaluated_) *lights_evaluated_ += evaluated_ + evaluated_per_pixel_;
}

void SurfaceShader::collect_reaching(const Polygon& source) {
  sign_ = lit_side(source, input_.view.eye);
  reaching_.clear();
  for (uint32_t l = 0; l < input_.scene.lights.size(); ++l) {
    if (skipped(l) || blocked(l, source.id)) continue;
    if (light_reaches(input_.scene.lights[l], sign_ * source.normal, sign_ * source.offset)) reaching_.push_back(l);
  }
}

// Writes [unshadowed sum incl. ambient, one term per shadow slot] for one point: the colour is
// material * irradiance + specular, summed in doubles in light order (as shade_point does).
void SurfaceShader::add_terms(const Material& material, Vec3 p, Vec3 n, Color* out, Color* specular_out) {
  if (specular_out) {
    std::fill(slot_sums_.begin(), slot_sums_.end(), glm::dvec3(0.0));
    std::vector<glm::dvec3>& slot_specular = slot_specular_;
    slot_specular.assign(slots_, glm::dvec3(0.0));
    glm::dvec3 irradiance = ambient_irradiance(input_.scene), specular(0.0);
    for (uint32_t l : reaching_) {
      const LightTerms t = light_terms(input_.scene.lights[l], material, p, n, input_.view.eye);
      ++evaluated_;
      const int32_t slot = slot_of(l);
      if (slot < 0) {
        irradiance += t.irradiance;
        specular += t.specular;
      } else {
        slot_sums_[size_t(slot)] += t.irradiance;
        slot_specular[size_t(slot)] += t.specular;
      }
    }
    out[0] = Color(irradiance);
    specular_out[0] = Color(specular);
    for (size_t s = 0; s < slots_; ++s)
      out[1 + s] = Color(slot_sums_[s]), specular_out[1 + s] = Color(slot_specular[s]);
    return;
  }
  const glm::dvec3 color(material.color);
  glm::dvec3 irradiance = ambient_irradiance(input_.scene), specular(0.0);
  std::fill(slot_sums_.begin(), slot_sums_.end(), glm::dvec3(0.0));
  for (uint32_t l : reaching_) {
    const LightTerms t = light_terms(input_.scene.lights[l], material, p, n, input_.view.eye);
    ++evaluated_;
    const int32_t slot = slot_of(l);
    if (slot < 0) {
      irradiance += t.irradiance;
      specular += t.specular;
    } else {
      slot_sums_[size_t(slot)] += color * t.irradiance + t.specular;
    }
  }
  out[0] = Color(color * irradiance + specular);
  for (size_t s = 0; s < slots_; ++s) out[1 + s] = Color(slot_sums_[s]);
}

namespace {

// The polygon whose id is `id`: ids are indices in a tessellated soup; a soup holding a view's
// selection of one (render/pipelines/view_selection.hpp) keeps the ids, increasing, with gaps.
const Polygon& polygon_with_id(const PolygonSoup& soup, uint32_t id) {
  const auto& polygons = soup.polygons;
  if (id < polygons.size() && polygons[id].id == id) return polygons[id];
  auto it = std::lower_bound(polygons.begin(), polygons.end(), id,
                             [](const Polygon& p, uint32_t value) { return p.id < value; });
  assert(it != polygons.end() && it->id == id);
  return *it;
}

}  // namespace

void SurfaceShader::prepare(uint32_t index) {
  assert(prepared_ == this && "a binding copy shares its terms and prepares nothing");
  if (mode_ == ShadingMode::phong) return;  // everything happens per pixel
  const Polygon& poly = soup_.polygons[index];
  const bool fragment_soup = &soup_ != &input_.soup;
  const Polygon& source = fragment_soup ? polygon_with_id(input_.soup, poly.id) : poly;
  collect_reaching(source);
  const Material& material = soup_.materials[poly.material];
  const size_t width = 1 + slots_;
  term_begin_[index] = uint32_t(terms_.size());
  if (mode_ == ShadingMode::gouraud) {
    prepare_gouraud(index, source);
    return;
  }
  // Flat: the source polygon's lighting at its centroid, with its face normal.
  Vec3 centroid(0.0);
  for (const Vec3& p : input_.soup.points(source)) centroid += p;
  centroid /= double(source.vertex_count);
  terms_.resize(terms_.size() + width * layers(poly));
  Color* terms = &terms_[term_begin_[index]];
  add_terms(material, centroid, sign_ * source.normal, terms, poly.uv_map != 0 ? terms + width : nullptr);
}

// Lighting at the source polygon's vertices; a fragment's vertices take the source's colour field
// (its fan interpolation) at their positions, so a split polygon looks like the whole one.
void SurfaceShader::prepare_gouraud(uint32_t index, const Polygon& source) {
  const Polygon& poly = soup_.polygons[index];
  const Material& material = soup_.materials[poly.material];
  const size_t width = 1 + slots_;
  const bool textured = poly.uv_map != 0;
  const size_t stride = width * layers(poly);  // per vertex
  const auto points = input_.soup.points(source);
  const auto normals = input_.soup.vertex_normals(source);
  const size_t begin = terms_.size();
  terms_.resize(begin + size_t(poly.vertex_count) * stride);
  if (&soup_ == &input_.soup) {
    for (size_t j = 0; j < points.size(); ++j) {
      Color* terms = &terms_[begin + j * stride];
      add_terms(material, points[j], sign_ * Vec3(normals[j]), terms, textured ? terms + width : nullptr);
    }
    return;
  }
  scratch_terms_.resize(points.size() * stride);
  for (size_t j = 0; j < points.size(); ++j) {
    Color* terms = &scratch_terms_[j * stride];
    add_terms(material, points[j], sign_ * Vec3(normals[j]), terms, textured ? terms + width : nullptr);
  }
  const auto own = soup_.points(poly);
  for (size_t j = 0; j < own.size(); ++j) {
    const FanPoint at = locate_in_fan(points, source.normal, own[j]);
    const size_t corner[3] = {0, at.j, at.j + 1};
    for (size_t t = 0; t < stride; ++t) {
      glm::dvec3 sum(0.0);
      for (int c = 0; c < 3; ++c) sum += at.w[c] * glm::dvec3(scratch_terms_[corner[c] * stride + t]);
      terms_[begin + j * stride + t] = Color(sum);
    }
  }
}

}  // namespace rr

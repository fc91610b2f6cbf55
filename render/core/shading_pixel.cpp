// SurfaceShader's per-drawn-polygon and per-pixel half (see shading.hpp): bind() gathers what the
// pixels of one clipped polygon need (lights reaching its plane, shadow coordinates and Gouraud
// colours at the clipped vertices, Phong positions and normals), so fragment() only interpolates
// with the rasterizer's perspective-correct weights and allocates nothing.
#include "render/core/shading.hpp"

#include "render/core/shading_detail.hpp"
#include "render/core/shadow_rays.hpp"

#include <algorithm>
#include <cmath>

namespace rr {

using shading_detail::ambient_irradiance;
using shading_detail::FanPoint;
using shading_detail::locate_in_fan;

void SurfaceShader::bind(uint32_t index, const DrawScratch& scratch) {
  const Polygon& poly = soup_.polygons[index];
  const Material& material = soup_.materials[poly.material];
  const Vec3 eye = input_.view.eye;
  sign_ = lit_side(poly, eye);
  bound_ = &poly;
  textured_ = poly.uv_map != 0;
  active_.clear();
  shadowed_.clear();
  mask_lights_.clear();
  const auto& lights = input_.scene.lights;
  for (uint32_t l = 0; l < lights.size(); ++l) {
    const Light& light = lights[l];
    if (skipped(l) || blocked(l, poly.id) || !light_reaches(light, sign_ * poly.normal, sign_ * poly.offset)) continue;
    ActiveLight a;
    const int32_t slot = slot_of(l);
    if (slot >= 0 && maps_) {
      const ShadowLight& sl = maps_->lights[size_t(slot)];
      shadowed_.push_back(
          {&sl, make_shadow_receiver(*maps_, sl, poly.normal, poly.offset, (poly.flags & polygon_closed) != 0), slot,
           &light});
      a.shadow = int32_t(shadowed_.size() - 1);
    } else if (slot >= 0) {
      shadowed_.push_back({nullptr, {}, slot, &light});
      a.shadow = int32_t(shadowed_.size() - 1);
    }
    if (mask_) mask_lights_.push_back({l, a.shadow});
    if (mode_ != ShadingMode::phong) continue;
    const glm::vec3 radiance = light.color * light.intensity;
    a.point = light.type == LightType::point;
    a.to_light = glm::vec3(-light.direction);
    a.position = glm::vec3(light.position - eye);
    a.attenuation = glm::vec3(light.attenuation);
    a.diffuse = textured_ ? radiance : material.color * radiance;  // textured: times the albedo per pixel
    a.has_specular = material.params.specular > 0.0f;
    a.specular = material.params.specular * material.params.specular_color * radiance;
    active_.push_back(a);
  }
  const auto& clipped = scratch.clipped;
  const size_t shadowed = shadowed_.size();
  if (rays_ || glass_) {
    self_ = poly.id;
    world_.resize(clipped.size());
    for (size_t j = 0; j < clipped.size(); ++j) world_[j] = clipped[j].p_world;
  }
  if (!rays_) {
    coords_.resize(clipped.size() * shadowed);
    for (size_t j = 0; j < clipped.size(); ++j) {
      for (size_t s = 0; s < shadowed; ++s)
        coords_[j * shadowed + s] = shadow_coords(*shadowed_[s].light, clipped[j].p_world);
    }
  }
  switch (mode_) {
    case ShadingMode::flat: {
      const Color* terms = &prepared_->terms_[prepared_->term_begin_[index]];
      const size_t width = 1 + slots_, out_width = 1 + shadowed, count = layers(poly);
      bound_terms_.resize(out_width * count);
      for (size_t layer = 0; layer < count; ++layer) {
        const Color* in = terms + layer * width;
        Color* out = &bound_terms_[layer * out_width];
        out[0] = in[0];
        for (size_t s = 0; s < shadowed; ++s) out[1 + s] = in[1 + size_t(shadowed_[s].slot)];
      }
      current_ = bound_terms_[0];
      constant_ = shadowed == 0 && !textured_;
      break;
    }
    case ShadingMode::gouraud:
      bind_gouraud(index, scratch);
      constant_ = false;
      break;
    case ShadingMode::phong:
      ambient_ = textured_ ? Color(ambient_irradiance(input_.scene))
                           : Color(glm::dvec3(material.color) * ambient_irradiance(input_.scene));
      if (material.params.specular > 0.0f) table_ = bind_specular_table(material.params.shininess);
      eye_to_p_.resize(clipped.size());
      normal_.resize(clipped.size());
      for (size_t j = 0; j < clipped.size(); ++j) {
        eye_to_p_[j] = glm::vec3(clipped[j].p_world - eye);
        normal_[j] = float(sign_) * clipped[j].normal;
      }
      constant_ = false;
      break;
  }
}

// Gouraud colours at the clipped vertices: the prepared vertex colours when clipping left the
// polygon whole, else the polygon's fan interpolation at the new vertices, so that clipping never
// changes the colour of a point.
void SurfaceShader::bind_gouraud(uint32_t index, const DrawScratch& scratch) {
  const Polygon& poly = soup_.polygons[index];
  const Color* terms = &prepared_->terms_[prepared_->term_begin_[index]];
  const size_t width = 1 + slots_, out_width = 1 + shadowed_.size(), count = layers(poly);
  const size_t stride = width * count, out_stride = out_width * count;
  const auto points = soup_.points(poly);
  const auto& clipped = scratch.clipped;
  bool whole = clipped.size() == points.size();
  for (size_t j = 0; whole && j < clipped.size(); ++j) whole = clipped[j].p_world == points[j];
  bound_terms_.resize(clipped.size() * out_stride);
  // Entry t of a vertex's bound terms: layer t / out_width, and in it the unshadowed sum or a light.
  auto pick = [&](const Color* vertex, size_t t) {
    const Color* layer = vertex + (t / out_width) * width;
    const size_t at = t % out_width;
    return at == 0 ? layer[0] : layer[1 + size_t(shadowed_[at - 1].slot)];
  };
  for (size_t j = 0; j < clipped.size(); ++j) {
    Color* out = &bound_terms_[j * out_stride];
    if (whole) {
      for (size_t t = 0; t < out_stride; ++t) out[t] = pick(terms + j * stride, t);
      continue;
    }
    const FanPoint at = locate_in_fan(points, poly.normal, clipped[j].p_world);
    for (size_t t = 0; t < out_stride; ++t) {
      out[t] = float(at.w[0]) * pick(terms, t) + float(at.w[1]) * pick(terms + at.j * stride, t) +
               float(at.w[2]) * pick(terms + (at.j + 1) * stride, t);
    }
  }
}

// A shadow ray from p_world, the point interpolated in doubles across the drawn polygon (so it lies
// on the polygon's plane to within rounding of its vertices, far below the ray's epsilon): the polygon
// itself is left out of the casters by its id, as the reference leaves out the polygon it hit, rather
// than moving the origin off the surface, so that a decision is the reference's at the same point.
float SurfaceShader::ray_visibility(const Shadowed& light, Vec3 p_world) const {
  if (input_.lamps_blocked && input_.lamps_blocked->fixture_closes(uint32_t(light.slot), p_world)) return 0.0f;
  return shadow_ray_blocked(*rays_, self_, p_world, *light.ray_light, &memos_[size_t(light.slot)]) ? 0.0f : 1.0f;
}

float SurfaceShader::visibility(size_t s, const Fragment& f, size_t k) const {
  if (rays_) return ray_visibility(shadowed_[s], world_at(f, k));
  const size_t n = shadowed_.size();
  const Vec3 coords = f.b[0] * coords_[s] + f.b[1] * coords_[(k + 1) * n + s] + f.b[2] * coords_[(k + 2) * n + s];
  return shadow_visibility(*maps_, *shadowed_[s].light, shadowed_[s].receiver, coords);
}

// A light counts as reaching the pixel when at least half of its PCF taps see it.
void SurfaceShader::write_mask(const Fragment& f, size_t k) const {
  uint8_t* const bits = mask_ + (size_t(f.y) * size_t(input_.view.width) + size_t(f.x)) * mask_bytes_;
  std::fill(bits, bits + mask_bytes_, uint8_t(0));
  for (const auto& [light, shadow] : mask_lights_) {
    if (shadow < 0 || visibility(size_t(shadow), f, k) >= 0.5f) bits[light / 8] |= uint8_t(1u << (light % 8));
  }
}

Color SurfaceShader::shade_pixel(const Fragment& f, size_t k) const {
  if (textured_) return shade_textured(f, k);
  if (mode_ == ShadingMode::phong) return shade_phong(f, k);
  const size_t n = shadowed_.size();
  if (mode_ == ShadingMode::flat) {
    Color c = bound_terms_[0];
    for (size_t s = 0; s < n; ++s) {
      const float v = visibility(s, f, k);
      c += glass_ && v > 0.0f ? (v * tint(s, f, k)) * bound_terms_[1 + s] : v * bound_terms_[1 + s];
    }
    return c;
  }
  // Gouraud: the fan triangle (0, k+1, k+2) of the clipped polygon, perspective-correct weights.
  const size_t width = 1 + n;
  const float b0 = float(f.b[0]), b1 = float(f.b[1]), b2 = float(f.b[2]);
  const Color* t0 = &bound_terms_[0];
  const Color* t1 = &bound_terms_[(k + 1) * width];
  const Color* t2 = &bound_terms_[(k + 2) * width];
  Color c = b0 * t0[0] + b1 * t1[0] + b2 * t2[0];
  for (size_t s = 0; s < n; ++s) {
    const float v = visibility(s, f, k);
    if (v <= 0.0f) continue;
    const Color term = b0 * t0[1 + s] + b1 * t1[1 + s] + b2 * t2[1 + s];
    c += glass_ ? (v * tint(s, f, k)) * term : v * term;
  }
  return c;
}

SurfaceShader::PhongPoint SurfaceShader::phong_point(const Fragment& f, size_t k) const {
  const float b0 = float(f.b[0]), b1 = float(f.b[1]), b2 = float(f.b[2]);
  const glm::vec3 q = b0 * eye_to_p_[0] + b1 * eye_to_p_[k + 1] + b2 * eye_to_p_[k + 2];
  glm::vec3 n = b0 * normal_[0] + b1 * normal_[k + 1] + b2 * normal_[k + 2];
  const float n_len = glm::length(n);
  n = n_len > 0.0f ? n / n_len : normal_[0];
  const float q_len = glm::length(q);
  return {q, n, q_len > 0.0f ? -q / q_len : n};
}

bool SurfaceShader::phong_light(const ActiveLight& a, glm::vec3 q, glm::vec3 n, glm::vec3 to_eye,
                                PhongLight& out) const {
  glm::vec3 l = a.to_light;
  out.attenuation = 1.0f;
  if (a.point) {
    const glm::vec3 d = a.position - q;
    const float dist = glm::length(d);
    if (!(dist > 0.0f)) return false;
    l = d / dist;
    out.attenuation = 1.0f / (a.attenuation.x + a.attenuation.y * dist + a.attenuation.z * dist * dist);
  }
  const float n_dot_l = glm::dot(n, l);
  if (n_dot_l <= 0.0f) return false;
  out.diffuse = a.diffuse * n_dot_l;
  out.specular = glm::vec3(0.0f);
  if (a.has_specular) {
    const glm::vec3 h = l + to_eye;
    const float h_len = glm::length(h);
    const float n_dot_h = h_len > 0.0f ? glm::dot(n, h) / h_len : 0.0f;
    if (n_dot_h > 0.0f) out.specular = a.specular * specular_tables_[table_](n_dot_h);
  }
  return true;
}

// The per-pixel Blinn-Phong of light_terms, in floats: positions relative to the eye keep float
// precision far from the world origin. The lobe comes from the material's SpecularTable, as in
// span_phong, so every pipeline shades a point the same.
Color SurfaceShader::shade_phong(const Fragment& f, size_t k) const {
  const PhongPoint at = phong_point(f, k);
  Color c = ambient_;
  evaluated_per_pixel_ += active_.size();
  for (const ActiveLight& a : active_) {
    const float vis = a.shadow >= 0 ? visibility(size_t(a.shadow), f, k) : 1.0f;
    if (vis <= 0.0f) continue;
    PhongLight t;
    if (!phong_light(a, at.q, at.n, at.to_eye, t)) continue;
    const glm::vec3 term = t.diffuse + t.specular;
    c += glass_ && a.shadow >= 0 ? term * ((t.attenuation * vis) * tint(size_t(a.shadow), f, k))
                                 : term * (t.attenuation * vis);
  }
  return c;
}

Color SurfaceShader::shade_textured(const Fragment& f, size_t k) const {
  const Color albedo = surface_albedo(soup_, *bound_, pixel_rays_, f.x + 0.5, f.y + 0.5, sampling_);
  const size_t n = shadowed_.size(), width = 1 + n;
  Color diffuse(0.0f), specular(0.0f);
  auto add = [&](size_t s, float v, Color d, Color sp) {
    const Color scale = glass_ ? v * tint(s, f, k) : Color(v);
    diffuse += scale * d;
    specular += scale * sp;
  };
  switch (mode_) {
    case ShadingMode::flat: {
      diffuse = bound_terms_[0];
      specular = bound_terms_[width];
      for (size_t s = 0; s < n; ++s) {
        const float v = visibility(s, f, k);
        if (v > 0.0f) add(s, v, bound_terms_[1 + s], bound_terms_[width + 1 + s]);
      }
      break;
    }
    case ShadingMode::gouraud: {
      const float b0 = float(f.b[0]), b1 = float(f.b[1]), b2 = float(f.b[2]);
      const size_t stride = 2 * width;
      const Color* t0 = &bound_terms_[0];
      const Color* t1 = &bound_terms_[(k + 1) * stride];
      const Color* t2 = &bound_terms_[(k + 2) * stride];
      auto at = [&](size_t i) { return b0 * t0[i] + b1 * t1[i] + b2 * t2[i]; };
      diffuse = at(0);
      specular = at(width);
      for (size_t s = 0; s < n; ++s) {
        const float v = visibility(s, f, k);
        if (v > 0.0f) add(s, v, at(1 + s), at(width + 1 + s));
      }
      break;
    }
    case ShadingMode::phong: {
      const PhongPoint p = phong_point(f, k);
      diffuse = ambient_;
      evaluated_per_pixel_ += active_.size();
      for (const ActiveLight& a : active_) {
        const float vis = a.shadow >= 0 ? visibility(size_t(a.shadow), f, k) : 1.0f;
        PhongLight t;
        if (vis <= 0.0f || !phong_light(a, p.q, p.n, p.to_eye, t)) continue;
        if (a.shadow >= 0) {
          add(size_t(a.shadow), t.attenuation * vis, t.diffuse, t.specular);
        } else {
          diffuse += t.attenuation * t.diffuse;
          specular += t.attenuation * t.specular;
        }
      }
      break;
    }
  }
  return albedo * diffuse + specular;
}

}  // namespace rr

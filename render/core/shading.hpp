// Lighting and shading shared by every pipeline (docs/lighting.md). The model: ambient + Blinn-Phong
// (Lambert diffuse and a specular lobe on the half vector) from directional and point lights, each
// light scaled by its shadow-map visibility, or by 0 or 1 from an exact shadow ray (shadow.method rays), and tinted
// by the panes it passes through (shadow_ray_transmittance, with either method). Input:
// world-space positions and unit normals; output: display colours (no gamma; to_byte clamps). Open surfaces (not part
// of a closed object) are lit on the side facing the eye, so a single triangle seen from behind is not black.
#pragma once

#include "render/core/draw.hpp"
#include "render/core/frame.hpp"
#include "render/core/kernels.hpp"
#include "render/core/scene.hpp"
#include "render/core/shadow.hpp"
#include "render/core/shadow_rays.hpp"
#include "render/core/sight_cones.hpp"
#include "render/core/surface.hpp"
#include "render/core/tessellate.hpp"

#include <algorithm>
#include <span>
#include <string_view>
#include <vector>

namespace rr {

// The reference model, in doubles. `n` is the unit normal on the side being lit.
// One light at p, attenuated and unshadowed: its colour on the surface is
// material.color * irradiance + specular. Zero when the light is behind n.
struct LightTerms {
  glm::dvec3 irradiance{0.0};  // light colour x intensity x cos x attenuation
  glm::dvec3 specular{0.0};    // strength x specular colour x light colour x intensity x (n.h)^shininess x attenuation
};
LightTerms light_terms(const Light& light, const Material& material, Vec3 p_world, Vec3 n, Vec3 eye);
// Ambient + every light, unshadowed.
Color shade_point(const Scene& scene, const Material& material, Vec3 p_world, Vec3 n, Vec3 eye);

// x^shininess for x in [0, 1], from a table of 1024 intervals over [x_min, 1] (x_min =
// specular_cutoff^(1 / shininess)), linearly interpolated; 0 below x_min. Its absolute error is below
// specular_table_error for every shininess in [1, 10000] (the scene format's range): the
// interpolation error is at most (interval width)^2 / 8 x max |f''|, which is < 1.7e-5 whatever the
// exponent because the table's span shrinks like 1 / shininess, plus the cutoff's 2^-17.
constexpr float specular_cutoff = 1.0f / 131072.0f;
constexpr float specular_table_error = 3e-5f;
class SpecularTable {
 public:
  static constexpr int intervals = 1024;
  explicit SpecularTable(float shininess);
  float shininess() const { return shininess_; }
  // The same mapping for the span kernels (kernels.hpp).
  SpecularLookup lookup() const { return {values_.data(), x_min_, scale_, float(intervals) - 0.5f}; }
  float operator()(float x) const {
    const float t = (x - x_min_) * scale_;
    if (!(t > 0.0f)) return 0.0f;  // also NaN
    const float at = std::min(t, float(intervals) - 0.5f);
    const int i = int(at);
    const float frac = std::min(t - float(i), 1.0f);
    return values_[size_t(i)] + frac * (values_[size_t(i) + 1] - values_[size_t(i)]);
  }

 private:
  float shininess_, x_min_, scale_;
  std::vector<float> values_;  // intervals + 1 samples
};

// Shading of the polygons of one frame, shared by every pipeline:
//   prepare(i)     once per polygon that may be visible (the "shade" stage): flat colours and
//                  Gouraud vertex colours are computed here, once per polygon;
//   bind(i, s)     after project_polygon, before drawing it: selects the polygon, the lights that
//                  reach its plane and the attributes of its clipped vertices;
//   fragment(f, k) per covered pixel: the colour. Shadow lookups and shadow rays use the world
//                  position interpolated across the drawn polygon, so every pipeline gets shadows.
// Colours of a polygon drawn as fragments (painter splits, BSP fragments) are those of its source
// polygon at the same points: a fragment's id is its source's index in input.soup.
// The destructor adds the lights evaluated (per polygon for flat, per vertex for Gouraud, per pixel
// for Phong) to *input.lights_evaluated, which render_frame reports.
class SurfaceShader {
 public:
  // `soup` holds the polygons being drawn: input.soup, or fragments made from it (painter splits,
  // BSP fragments) that keep their source's id, material, object, flags and plane.
  SurfaceShader(const FrameInput& input, const PolygonSoup& soup);
  ~SurfaceShader();
  // A copy for another thread drawing the same frame: shares `prepared`'s per-polygon terms (read
  // only; prepare() is never called on the copy) and binds and shades on its own. Its light
  // evaluations are added to *lights_evaluated when it is destroyed.
  SurfaceShader(const SurfaceShader& prepared, size_t* lights_evaluated);
  SurfaceShader(const SurfaceShader&) = delete;
  SurfaceShader& operator=(const SurfaceShader&) = delete;

  void prepare(uint32_t index);
  void bind(uint32_t index, const DrawScratch& scratch);
  Color fragment(const Fragment& f, size_t k) const {
    if (mask_) [[unlikely]]
      write_mask(f, k);
    return constant_ ? current_ : shade_pixel(f, k);
  }
  // True when every polygon has one colour (flat shading, no shadow map, no shadow mask asked for):
  // then polygon_color(index) is the colour of a prepared polygon, and drawing it needs no bind().
  bool constant_per_polygon() const { return mode_ == ShadingMode::flat && slots_ == 0 && !mask_ && !textured_soup_; }
  Color polygon_color(uint32_t index) const { return prepared_->terms_[prepared_->term_begin_[index]]; }

  // The span API (shading_span.cpp): the colours of up to span_capacity pixels of one row of fan
  // triangle `k` of the bound polygon, the same as fragment() gives each of them, except that Phong
  // takes the specular lobe from a SpecularTable. The loops run over structure-of-arrays buffers,
  // light by light, so the per-pixel work has no calls or mode branches.
  static constexpr size_t span_capacity = kernel_span;
  struct Span {
    int x = 0, y = 0;  // first pixel; the others follow along +x
    size_t count = 0;
    size_t k = 0;                            // fan triangle (0, k+1, k+2) of the clipped polygon
    alignas(16) double b[3][span_capacity];  // perspective-correct weights, as in Fragment::b
  };
  struct SpanColors {
    alignas(16) float r[span_capacity], g[span_capacity], b[span_capacity];
  };
  void shade_span(const Span& span, SpanColors& out) const;
  // The colours as display bytes, 3 per pixel: to_byte(c) for each channel, in a loop that vectorizes.
  static void write_bytes(const SpanColors& colors, size_t count, uint8_t* rgb);

 private:
  // A light that reaches the bound polygon, in floats for the per-pixel loop.
  struct ActiveLight {
    glm::vec3 to_light{0.0f};  // directional: unit vector toward the light
    glm::vec3 position{0.0f};  // point: relative to the eye
    glm::vec3 attenuation{1.0f, 0.0f, 0.0f};
    glm::vec3 diffuse{0.0f};   // material colour x light colour x intensity
    glm::vec3 specular{0.0f};  // strength x specular colour x light colour x intensity
    bool point = false;
    bool has_specular = false;
    int32_t shadow = -1;  // index into shadowed_, or -1: never shadowed
  };
  struct Shadowed {
    const ShadowLight* light;  // shadow maps; null for a shadow ray
    ShadowReceiver receiver;
    int32_t slot;                      // index into ShadowMaps::lights, or the scene light with rays
    const Light* ray_light = nullptr;  // shadow rays and tints: the light the ray goes toward
  };
  // The terms slot of scene light l: its index among the lights with maps, l itself with shadow
  // rays, -1 when it is never shadowed.
  int32_t slot_of(uint32_t l) const { return maps_ ? maps_->slot_of_light[l] : rays_ ? int32_t(l) : -1; }
  bool skipped(uint32_t l) const { return input_.lights_skipped && (*input_.lights_skipped)[l]; }
  // Light l cannot light any point of the polygon with id `id`: every ray toward it is blocked.
  bool blocked(uint32_t l, uint32_t id) const { return input_.lamps_blocked && input_.lamps_blocked->blocked(id, l); }
  float ray_visibility(const Shadowed& light, Vec3 p_world) const;
  Vec3 world_at(const Fragment& f, size_t k) const {
    return f.b[0] * world_[0] + f.b[1] * world_[k + 1] + f.b[2] * world_[k + 2];
  }
  // What the panes between the fragment and shadowed light s let through (glass_ only).
  Color tint(size_t s, const Fragment& f, size_t k) const {
    return shadow_ray_transmittance(*glass_, input_.soup, self_, world_at(f, k), *shadowed_[s].ray_light);
  }

  Color shade_pixel(const Fragment& f, size_t k) const;
  // A textured polygon's pixel: its albedo (surface_albedo) times the diffuse light, plus the
  // specular light, each summed as the untextured modes sum their folded terms.
  Color shade_textured(const Fragment& f, size_t k) const;
  struct PhongLight {
    glm::vec3 diffuse{0.0f}, specular{0.0f};  // unattenuated, unshadowed
    float attenuation = 1.0f;
  };
  // Light a's Blinn-Phong terms at q (relative to the eye) with unit normal n; false when it adds
  // nothing there.
  bool phong_light(const ActiveLight& a, glm::vec3 q, glm::vec3 n, glm::vec3 to_eye, PhongLight& out) const;
  struct PhongPoint {
    glm::vec3 q, n, to_eye;
  };
  PhongPoint phong_point(const Fragment& f, size_t k) const;
  void write_mask(const Fragment& f, size_t k) const;
  float visibility(size_t s, const Fragment& f, size_t k) const;
  Color shade_phong(const Fragment& f, size_t k) const;
  void span_visibility(const Span& span, size_t s, float* vis) const;
  // Per pixel of the span where vis > 0, the tint of shadowed light s; 1 elsewhere (glass_ only).
  void span_tint(const Span& span, size_t s, const float* vis, SpanColors& tint) const;
  void span_flat(const Span& span, SpanColors& out) const;
  void span_gouraud(const Span& span, SpanColors& out) const;
  void span_phong(const Span& span, SpanColors& out) const;
  void span_phong_light(const ActiveLight& a, const PhongPixels& p, size_t count, const float* vis,
                        const SpanColors* tint, SpanColors& out) const;
  size_t bind_specular_table(float shininess);
  void collect_reaching(const Polygon& source);
  // With `specular` (textured polygons): `terms` gets the irradiance alone (white albedo) and
  // `specular` the specular terms, in the same layout.
  void add_terms(const Material& material, Vec3 p, Vec3 n, Color* terms, Color* specular = nullptr);
  // Entries of terms_ per polygon (flat) or vertex (Gouraud): 1 + slots_, twice for a textured one.
  size_t layers(const Polygon& poly) const { return poly.uv_map != 0 ? 2 : 1; }
  void prepare_gouraud(uint32_t index, const Polygon& source);
  void bind_gouraud(uint32_t index, const DrawScratch& scratch);

  const FrameInput& input_;
  const PolygonSoup& soup_;
  const SurfaceShader* prepared_ = this;  // holds term_begin_ and terms_
  size_t* lights_evaluated_;
  const ShadowMaps* maps_;
  const ShadowBvh* rays_;   // shadow.method rays: the tree of input_.soup (never with maps_)
  const ShadowBvh* glass_;  // a tree of input_.soup with panes, which tint shadowed lights; else null
  ShadingMode mode_;
  size_t slots_;                           // lights with shadow maps, or every scene light with rays
  std::vector<uint32_t> term_begin_;       // per polygon: its first entry in terms_
  std::vector<Color> terms_;               // [unshadowed sum, one per slot], per polygon (flat) or vertex
  std::vector<Color> scratch_terms_;       // source vertex terms while preparing a fragment
  std::vector<uint32_t> reaching_;         // lights that reach the polygon being prepared
  std::vector<glm::dvec3> slot_sums_;      // per slot, while adding terms
  std::vector<glm::dvec3> slot_specular_;  // per slot, a textured polygon's specular terms
  double sign_ = 1.0;                      // lit side of the polygon being prepared or bound
  bool textured_soup_ = false;             // some polygon has a texture
  PixelRays pixel_rays_;
  TextureSampling sampling_;
  // The bound polygon.
  const Polygon* bound_ = nullptr;
  bool textured_ = false;  // it has a texture: bound_terms_ holds a diffuse and a specular layer
  bool constant_ = true;
  Color current_{0.0f};
  Color ambient_{0.0f};
  std::vector<SpecularTable> specular_tables_;  // Phong: built on first use, one per shininess
  size_t table_ = 0;                            // the bound polygon's, in specular_tables_
  std::vector<ActiveLight> active_;
  std::vector<Shadowed> shadowed_;
  std::vector<Color> bound_terms_;  // flat: 1 + shadowed; Gouraud: that per clipped vertex
  std::vector<Vec3> coords_;        // per clipped vertex x shadowed_: shadow_coords
  std::vector<Vec3> world_;         // shadow rays or glass_: per clipped vertex, its world position
  uint32_t self_ = 0;               // shadow rays or glass_: the bound polygon's id (casts on itself never)
  // Shadow rays, per scene light: the caster that last blocked one of this shader's rays (each
  // binding copy is one thread's). Any blocker proves a ray blocked, so it is tried first.
  mutable std::vector<ShadowRayMemo> memos_;
  std::vector<glm::vec3> eye_to_p_, normal_;  // Phong: per clipped vertex
  size_t evaluated_ = 0;
  mutable size_t evaluated_per_pixel_ = 0;
  // Frame::shadow_mask (null when not requested), mask_bytes_ a pixel: the bound polygon's lights
  // that reach it, as (light index, index into shadowed_ or -1).
  uint8_t* mask_ = nullptr;
  size_t mask_bytes_ = 1;
  std::vector<std::pair<uint32_t, int32_t>> mask_lights_;
};

}  // namespace rr

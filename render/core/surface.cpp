#include "render/core/surface.hpp"

#include <algorithm>
#include <cmath>

namespace rr {

PixelRays pixel_rays(const ViewTransform& view) {
  // View space: the screen point (sx, sy) has normalized device coordinates x = 2 sx / W - 1 and
  // y = 1 - 2 sy / H; on the plane z = -1 that is ((x + P[2][0]) / P[0][0], (y + P[2][1]) / P[1][1]).
  const Mat4& proj = view.clip_from_view;
  const Mat3 world_from_view = glm::inverse(Mat3(view.view_from_world));
  const double w = double(view.width), h = double(view.height);
  PixelRays r;
  r.eye = view.eye;
  r.base = world_from_view * Vec3((-1.0 + proj[2][0]) / proj[0][0], (1.0 + proj[2][1]) / proj[1][1], -1.0);
  r.dx = world_from_view * Vec3(2.0 / (w * proj[0][0]), 0.0, 0.0);
  r.dy = world_from_view * Vec3(0.0, -2.0 / (h * proj[1][1]), 0.0);
  return r;
}

PlaneFootprint footprint_on_plane(const PixelRays& rays, Vec3 n, double offset, double sx, double sy) {
  PlaneFootprint f;
  const Vec3 d = rays.base + sx * rays.dx + sy * rays.dy;
  const double nd = glm::dot(n, d);
  const double t = (offset - glm::dot(n, rays.eye)) / nd;
  if (!(t > 0.0) || !std::isfinite(t)) return f;
  f.p = rays.eye + t * d;
  f.dp_dx = t * (rays.dx - d * (glm::dot(n, rays.dx) / nd));
  f.dp_dy = t * (rays.dy - d * (glm::dot(n, rays.dy) / nd));
  f.valid = true;
  return f;
}

int reference_taps(glm::dvec2 dtexel_dx, glm::dvec2 dtexel_dy) {
  const double rho = std::max(glm::length(dtexel_dx), glm::length(dtexel_dy));
  if (!(rho < reference_max_taps)) return reference_max_taps;  // also NaN
  return std::clamp(int(std::ceil(2.0 * rho)), reference_min_taps, reference_max_taps);
}

namespace {

Color mean_of(const TextureImage& image) {
  const MipLevel& last = image.levels.back();
  return Color(last.rgb[0], last.rgb[1], last.rgb[2]) / 255.0f;
}

Color box_filtered(const TextureImage& image, const UvMap& map, const PixelRays& rays, Vec3 n, double offset, double sx,
                   double sy, int taps) {
  glm::dvec3 sum(0.0);
  int count = 0;
  for (int j = 0; j < taps; ++j) {
    for (int i = 0; i < taps; ++i) {
      const double x = sx + (i + 0.5) / taps - 0.5, y = sy + (j + 0.5) / taps - 0.5;
      const PlaneFootprint f = footprint_on_plane(rays, n, offset, x, y);
      if (!f.valid) continue;
      sum += glm::dvec3(texel_bilinear(image, map.at(f.p)));
      ++count;
    }
  }
  return count > 0 ? Color(sum / double(count)) : mean_of(image);
}

}  // namespace

Color surface_albedo(const PolygonSoup& soup, const Polygon& polygon, const PixelRays& rays, double sx, double sy,
                     const TextureSampling& sampling) {
  const Material& material = soup.materials[polygon.material];
  if (polygon.uv_map == 0 || !material.texture || !material.texture->decoded) return material.color;
  const TextureImage& image = *material.texture->decoded;
  const UvMap& map = soup.uv_maps[polygon.uv_map - 1];
  const PlaneFootprint f = footprint_on_plane(rays, polygon.normal, polygon.offset, sx, sy);
  if (!f.valid) return material.color * mean_of(image);
  if (sampling.reference) {
    const glm::dvec2 texels(image.width(), image.height());
    const int taps = reference_taps(map.along(f.dp_dx) * texels, map.along(f.dp_dy) * texels);
    return material.color * box_filtered(image, map, rays, polygon.normal, polygon.offset, sx, sy, taps);
  }
  return material.color * sample_texture(image, sampling.filter, map.at(f.p), map.along(f.dp_dx), map.along(f.dp_dy));
}

}  // namespace rr

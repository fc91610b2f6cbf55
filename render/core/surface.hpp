// A surface's colour at a pixel: the one lookup that every shading path and the reference use
// (docs/textures.md). An untextured material's colour is its `color`; a textured one's is `color`
// times its image filtered over the pixel's footprint on the polygon's plane. The footprint comes
// from the pixel's ray meeting that plane, not from the drawn polygon's vertices, so a polygon
// clipped, split by BSP or cut by Newell's ordering gets the same colour at the same pixel.
#pragma once

#include "render/core/camera.hpp"
#include "render/core/tessellate.hpp"
#include "render/core/texture.hpp"

namespace rr {

// The rays of a view through screen points: from `eye` along base + sx * dx + sy * dy (not unit)
// for the screen point (sx, sy) in pixels (pixel (x, y) has its centre at (x + 0.5, y + 0.5)).
struct PixelRays {
  Vec3 eye{0.0}, base{0.0, 0.0, -1.0}, dx{0.0}, dy{0.0};
};
PixelRays pixel_rays(const ViewTransform& view);

// Where the ray through (sx, sy) meets the plane dot(n, p) = offset, and how that point moves per
// pixel along the screen's x and y. `valid` is false when the ray runs parallel to the plane or
// meets it behind the eye.
struct PlaneFootprint {
  Vec3 p{0.0}, dp_dx{0.0}, dp_dy{0.0};
  bool valid = false;
};
PlaneFootprint footprint_on_plane(const PixelRays& rays, Vec3 n, double offset, double sx, double sy);

// How a lookup filters: `filter` (options.texture_filter), or, for the reference, a box filter over
// the pixel: n x n rays through the pixel, each meeting the plane exactly and taking a bilinear tap of
// the full-resolution image, n = 2 rho rounded up (rho: the footprint's longer side in texels) within
// [reference_min_taps, reference_max_taps], so that each texel the pixel covers gets several taps.
struct TextureSampling {
  TextureFilter filter = TextureFilter::trilinear;
  bool reference = false;
};
inline constexpr int reference_min_taps = 4;
inline constexpr int reference_max_taps = 64;

// The taps per side the reference takes for a footprint (derivatives in texels of level 0).
int reference_taps(glm::dvec2 dtexel_dx, glm::dvec2 dtexel_dy);

// The albedo of `polygon` (of `soup`) seen through screen point (sx, sy): its material's colour,
// times the filtered texel when the polygon is textured. A footprint that is not valid takes the
// image's mean (its last mip level).
Color surface_albedo(const PolygonSoup& soup, const Polygon& polygon, const PixelRays& rays, double sx, double sy,
                     const TextureSampling& sampling);

}  // namespace rr

// A ray against one convex polygon of a soup, in doubles (world space): the exact test of the
// reference's rays and of the pipelines' shadow rays, so that both decide a ray the same way.
#pragma once

#include "render/core/math.hpp"
#include "render/core/tessellate.hpp"

#include <optional>

namespace rr {

// Where origin + t * direction (t_min < t < t_max) meets the convex polygon, boundary included;
// nullopt when it misses or runs parallel to its plane. World space, doubles; used by the shadow
// rays (the reference's and shadow_rays.hpp's) and by tests comparing the BVH with a brute-force search.
std::optional<double> intersect_polygon(const PolygonSoup& soup, const Polygon& polygon, Vec3 origin, Vec3 direction,
                                        double t_min, double t_max);

}  // namespace rr

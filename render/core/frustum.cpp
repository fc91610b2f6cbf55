// The view frustum and whole-object culling (see frustum.hpp).
#include "render/core/frustum.hpp"

#include <algorithm>
#include <limits>

namespace rr {

Frustum::Frustum(const ViewTransform& view) {
  const Mat4& m = view.clip_from_world;  // column-major: m[column][row]
  auto row = [&](int r) { return Vec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
  planes[0] = row(3) + row(0), planes[1] = row(3) - row(0);
  planes[2] = row(3) + row(1), planes[3] = row(3) - row(1);
  planes[4] = row(3) + row(2), planes[5] = row(3) - row(2);
}

bool Frustum::outside(Vec3 lo, Vec3 hi) const {
  for (const Vec4& s : planes) {
    // The box corner farthest along the plane's normal; if even it is outside, the box is.
    const Vec3 p(s.x >= 0 ? hi.x : lo.x, s.y >= 0 ? hi.y : lo.y, s.z >= 0 ? hi.z : lo.z);
    if (s.x * p.x + s.y * p.y + s.z * p.z + s.w < 0.0) return true;
  }
  return false;
}

ObjectsInView objects_in_view(const PolygonSoup& soup, const ViewTransform& view) {
  const size_t n = soup.objects.size();
  std::vector<Vec3> lo(n), hi(n);
  if (std::all_of(soup.objects.begin(), soup.objects.end(), [](const SceneObject& o) { return o.bounded; })) {
    for (size_t i = 0; i < n; ++i) lo[i] = soup.objects[i].lo, hi[i] = soup.objects[i].hi;
  } else {
    const Vec3 inf(std::numeric_limits<double>::infinity());
    std::fill(lo.begin(), lo.end(), inf);
    std::fill(hi.begin(), hi.end(), -inf);
    for (const Polygon& p : soup.polygons) {
      for (const Vec3& q : soup.points(p)) {
        lo[p.object] = glm::min(lo[p.object], q);
        hi[p.object] = glm::max(hi[p.object], q);
      }
    }
  }
  const Frustum frustum(view);
  ObjectsInView out;
  out.visible.assign(n, 1);
  for (size_t i = 0; i < n; ++i) {
    if (lo[i].x > hi[i].x || !frustum.outside(lo[i], hi[i])) continue;  // no polygon, or in view
    out.visible[i] = 0;
    ++out.culled;
  }
  return out;
}

}  // namespace rr

// Clipping and projection of one polygon (see draw.hpp).
#include "render/core/draw.hpp"

namespace rr {

bool project_polygon(const ViewTransform& view, const PolygonSoup& soup, const Polygon& polygon, DrawScratch& scratch) {
  auto points = soup.points(polygon);
  auto normals = soup.vertex_normals(polygon);
  scratch.in.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    scratch.in[i] = {view.clip_from_world * Vec4(points[i], 1.0), points[i], normals[i]};
  }
  if (!clip_polygon(scratch.in, scratch.clipped, scratch.tmp)) return false;
  scratch.screen.resize(scratch.clipped.size());
  for (size_t i = 0; i < scratch.clipped.size(); ++i) {
    const Vec4& p = scratch.clipped[i].p_clip;
    Vec2 s = screen_from_clip(view, p);
    scratch.screen[i] = {s.x, s.y, 1.0 / p.w};
  }
  return true;
}

}  // namespace rr

// The zbuffer pipeline (see zbuffer.hpp). Depth is 1/w, i.e. 1 / view depth, stored as float:
// larger is nearer, and its relative precision is uniform in view depth, unlike the hyperbolic
// OpenGL z (1 mm at 10 m differs by 1e-5 relative, far above float's 6e-8).
#include "render/zbuffer.hpp"

#include "render/draw.hpp"
#include "render/shading.hpp"
#include "render/timer.hpp"

#include <algorithm>

namespace rr {

namespace {

// Mean view depth of a polygon (distance along the view axis), for back-to-front sorting.
double mean_view_depth(const ViewTransform& view, const PolygonSoup& soup, const Polygon& poly) {
  double sum = 0.0;
  for (const Vec3& p : soup.points(poly)) sum += -(view.view_from_world * Vec4(p, 1.0)).z;
  return sum / double(poly.vertex_count);
}

}  // namespace

void draw_zbuffer(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings) {
  const PolygonSoup& soup = input.soup;
  Stopwatch clock;
  SurfaceShader shader(input, soup);
  std::vector<uint32_t> opaque, translucent;
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
    const Polygon& poly = soup.polygons[i];
    if (is_back_facing(poly, input.view.eye) || !input.object_may_show(poly)) continue;
    shader.prepare(i);
    (poly.flags & polygon_translucent ? translucent : opaque).push_back(i);
  }
  timings.shade_ms += clock.lap_ms();

  std::vector<float> depth(size_t(frame.image.width) * size_t(frame.image.height), 0.0f);
  FrameTarget target{frame.image, frame.ids, &depth, {0, 0, frame.image.width, frame.image.height}};
  DrawScratch scratch;
  auto draw = [&](uint32_t i, DepthMode mode) {
    const Polygon& poly = soup.polygons[i];
    if (!project_polygon(input.view, soup, poly, scratch)) return;
    ++stats.polygons_drawn;
    stats.triangles += scratch.screen.size() - 2;
    shader.bind(i, scratch);
    float alpha = mode == DepthMode::test_only ? soup.materials[poly.material].opacity : 1.0f;
    stats.fragments += draw_projected(target, scratch, poly.id, alpha, mode,
                                      [&](const Fragment& f, size_t k) { return shader.fragment(f, k); });
  };
  for (uint32_t i : opaque) draw(i, DepthMode::test_and_write);
  std::vector<std::pair<double, uint32_t>> order;
  for (uint32_t i : translucent) order.push_back({mean_view_depth(input.view, soup, soup.polygons[i]), i});
  std::sort(order.begin(), order.end(), std::greater<>());  // far to near; ties: higher index first
  for (const auto& [d, i] : order) draw(i, DepthMode::test_only);
  stats.polygons_culled = soup.polygons.size() - stats.polygons_drawn;  // back-facing or off-view
  timings.raster_ms += clock.lap_ms();
}

}  // namespace rr

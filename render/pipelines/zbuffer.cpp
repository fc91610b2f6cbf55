// The zbuffer pipeline (see zbuffer.hpp). Depth is 1/w, i.e. 1 / view depth, stored as float:
// larger is nearer, and its relative precision is uniform in view depth, unlike the hyperbolic
// OpenGL z (1 mm at 10 m differs by 1e-5 relative, far above float's 6e-8). Drawing goes through
// the tiled visibility buffer (visibility.hpp): opaque polygons are resolved first and each visible
// pixel is shaded once; translucent ones are blended over them back to front.
#include "render/pipelines/zbuffer.hpp"

#include "render/core/draw.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/visibility.hpp"

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
  CancelMeter meter(input.context.cancel, 4096);  // units: polygons prepared
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
    meter.add(1);
    const Polygon& poly = soup.polygons[i];
    if (is_back_facing(poly, input.view.eye) || !input.object_may_show(poly) || !input.polygon_may_show(i)) continue;
    shader.prepare(i);
    (poly.flags & polygon_translucent ? translucent : opaque).push_back(i);
  }
  timings.shade_ms += clock.lap_ms();

  std::vector<std::pair<double, uint32_t>> order;
  for (uint32_t i : translucent) order.push_back({mean_view_depth(input.view, soup, soup.polygons[i]), i});
  std::sort(order.begin(), order.end(), std::greater<>());  // far to near; ties: higher index first
  for (size_t n = 0; n < order.size(); ++n) translucent[n] = order[n].second;
  // Kept by this thread for its next frame, so the bins' memory is not allocated again.
  thread_local VisibilityInput vis;
  stats.polygons_projected += opaque.size() + translucent.size();
  bin_polygons(input, opaque, translucent, vis, stats);
  stats.polygons_culled = soup.polygons.size() - stats.polygons_drawn;  // back-facing or off-view
  timings.raster_ms += clock.lap_ms();
  check_cancel(input.context.cancel);
  draw_visibility(input, vis, shader, input.context.threads, frame, stats, timings);
}

}  // namespace rr

// The reference ray caster (see reference.hpp, docs/accuracy.md). Set-up projects every polygon
// that is not back-facing exactly as the rasterizer's front end does (project_polygon: near, far and
// guard-band clipping) and builds a BVH of them in world space; each pixel's ray then visits the
// polygons whose boxes it enters, keeps those whose projection covers the pixel centre, and takes
// its depth from the exact ray-plane intersection. Rows are independent and each is written by one
// thread, so the image does not depend on the thread count.
#include "render/pipelines/reference.hpp"

#include "render/core/coplanar.hpp"
#include "render/core/draw.hpp"
#include "render/core/parallel.hpp"
#include "render/core/sample_pattern.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/reference_detail.hpp"

#include <algorithm>
#include <atomic>
#include <thread>

namespace rr {

namespace {
// raster.hpp's top-left rule, on an edge of a positively wound polygon (y down): a top edge is
// horizontal going right, a left edge goes up.
bool is_top_left(double dx, double dy) { return (dy == 0.0 && dx > 0.0) || dy < 0.0; }
}  // namespace

bool covers_screen_point(std::span<const Vec2> xy, double px, double py) {
  const size_t n = xy.size();
  double twice_area = 0.0;
  for (size_t j = 0; j < n; ++j) twice_area += xy[j].x * xy[(j + 1) % n].y - xy[(j + 1) % n].x * xy[j].y;
  if (twice_area == 0.0 || n < 3) return false;
  // Walk the edges in the rasterizer's positive winding (area > 0 with y down).
  const bool reverse = twice_area < 0.0;
  for (size_t j = 0; j < n; ++j) {
    Vec2 a = xy[j], b = xy[(j + 1) % n];
    if (reverse) std::swap(a, b);
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double e = dx * (py - a.y) - dy * (px - a.x);  // > 0 inside, as raster.hpp
    if (e < 0.0 || (e == 0.0 && !is_top_left(dx, dy))) return false;
  }
  return true;
}

namespace reference_detail {

ReferenceScene prepare_reference(const FrameInput& input, RenderStats& stats) {
  ReferenceScene rs(input);
  const PolygonSoup& soup = input.soup;
  rs.screen_begin.assign(soup.polygons.size() + 1, 0);
  std::vector<uint32_t> visible;
  DrawScratch scratch;
  CancelMeter meter(input.context.cancel, 4096);  // units: polygons projected
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
    meter.add(1);
    rs.screen_begin[i] = uint32_t(rs.screen_xy.size());
    const Polygon& poly = soup.polygons[i];
    if (is_back_facing(poly, input.view.eye) || !project_polygon(input.view, soup, poly, scratch)) continue;
    for (const RasterVertex& v : scratch.screen) rs.screen_xy.push_back({v.x, v.y});
    visible.push_back(i);
  }
  rs.screen_begin[soup.polygons.size()] = uint32_t(rs.screen_xy.size());
  stats.polygons_drawn = visible.size();
  stats.polygons_culled = soup.polygons.size() - visible.size();
  check_cancel(input.context.cancel);
  rs.view_bvh = build_polygon_bvh(soup, visible);
  rs.shadows = input.options.shadows && !input.scene.lights.empty();
  if (rs.shadows) {
    std::vector<uint32_t> casters, panes;
    for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
      (soup.polygons[i].flags & polygon_translucent ? panes : casters).push_back(i);
    }
    rs.shadow_bvh = build_polygon_bvh(soup, casters);
    rs.glass_bvh = build_polygon_bvh(soup, panes);
  }
  Box scene_box;
  for (const Vec3& p : soup.positions) scene_box.grow(p);
  if (!scene_box.empty()) {
    rs.scene_size = glm::length(scene_box.hi - scene_box.lo);
    rs.scene_magnitude = std::max(glm::length(scene_box.lo), glm::length(scene_box.hi));
  }
  rs.coplanar_tolerance = coplanar_tolerance(soup);
  rs.world_from_clip = glm::inverse(input.view.clip_from_world);
  rs.pixel_rays = pixel_rays(input.view);
  return rs;
}

// Depth order with the z-buffer's tie rule: a tie (relative reference_depth_tie) goes to the lower id.
bool nearer(double depth, uint32_t id, double best_depth, uint32_t best_id) {
  const double tolerance = reference_depth_tie * std::max(depth, best_depth);
  if (std::abs(depth - best_depth) <= tolerance) return id < best_id;
  return depth < best_depth;
}

// The opaque hits' order: polygons of one plane group (coplanar.hpp) tie whatever their computed
// depths, since two triangulations of one plane give depths that differ in the last bits; others as
// nearer().
bool nearer_opaque(const PolygonSoup& soup, double depth, uint32_t i, double best_depth, uint32_t best) {
  const uint32_t group = soup.polygons[i].plane_group;
  if (group != 0 && group == soup.polygons[best].plane_group) return i < best;
  return nearer(depth, i, best_depth, best);
}

PixelHits cast_ray(const ReferenceScene& rs, double sx, double sy, std::vector<Hit>& translucent) {
  const ViewTransform& view = rs.input.view;
  const double x_ndc = 2.0 * sx / view.width - 1.0, y_ndc = 1.0 - 2.0 * sy / view.height;
  const Vec4 far = rs.world_from_clip * Vec4(x_ndc, y_ndc, 1.0, 1.0);
  const BvhRay ray(view.eye, Vec3(far) / far.w - view.eye);  // t = 1 on the far plane
  const double depth_per_t = -(view.view_from_world * Vec4(ray.direction, 0.0)).z;
  const PolygonSoup& soup = rs.input.soup;
  PixelHits out;
  translucent.clear();
  double t_max = std::numeric_limits<double>::infinity();
  traverse_bvh(rs.view_bvh, ray, 0.0, t_max, [&](uint32_t i, double& t_limit) {
    const Polygon& poly = soup.polygons[i];
    const std::span<const Vec2> xy(rs.screen_xy.data() + rs.screen_begin[i],
                                   rs.screen_begin[i + 1] - rs.screen_begin[i]);
    if (!covers_screen_point(xy, sx, sy)) return false;
    const double denom = glm::dot(poly.normal, ray.direction);
    if (denom == 0.0) return false;  // the eye is in its plane: the projection has no area anyway
    const double t = (poly.offset - glm::dot(poly.normal, ray.origin)) / denom;
    const Hit hit{i, t, t * depth_per_t};
    if (poly.flags & polygon_translucent) {
      translucent.push_back(hit);
    } else if (out.opaque.polygon == background_id ||
               nearer_opaque(soup, hit.depth, i, out.opaque.depth, out.opaque.polygon)) {
      out.opaque = hit;
      // Still visit ties: by depth, and the rest of the hit's plane group, up to the group's
      // tolerance either side of its plane along this ray.
      const double group_slack = poly.plane_group ? 2.0 * rs.coplanar_tolerance / std::abs(denom) : 0.0;
      t_limit = t * (1.0 + 4.0 * reference_depth_tie) + group_slack;
    }
    return false;
  });
  // Translucent hits in front of the opaque one (a tie hides them, as the z-buffer's strict test),
  // far to near; equal depths draw the higher index first, as zbuffer.cpp's sort.
  std::erase_if(translucent, [&](const Hit& h) {
    return out.opaque.polygon != background_id && !nearer(h.depth, 1, out.opaque.depth, 0);
  });
  std::sort(translucent.begin(), translucent.end(),
            [](const Hit& a, const Hit& b) { return a.depth != b.depth ? a.depth > b.depth : a.polygon > b.polygon; });
  out.ray_origin = ray.origin;
  out.ray_direction = ray.direction;
  return out;
}

}  // namespace reference_detail

using namespace reference_detail;

namespace {

// One ray's colour, composited as the z-buffer draws: the opaque hit over the pixel's `rgb`
// (the background), then each translucent hit far to near, each step rounded to bytes. `id` and
// `mask` get the last polygon painted and its lit lights (left alone where nothing is hit).
struct RayPaint {
  uint8_t* rgb;
  uint32_t* id;
  uint8_t* mask;  // null: no shadow mask
  size_t mask_bytes = 1;
};

bool paint_ray(const ReferenceScene& rs, double sx, double sy, std::vector<Hit>& translucent, const RayPaint& out) {
  const PolygonSoup& soup = rs.input.soup;
  const PixelHits px = cast_ray(rs, sx, sy, translucent);
  auto paint = [&](const Hit& hit, float alpha) {
    const std::span<uint8_t> lit = out.mask ? std::span<uint8_t>(out.mask, out.mask_bytes) : std::span<uint8_t>();
    const Color c = shade_hit(rs, hit, px.ray_origin + hit.t * px.ray_direction, sx, sy, lit);
    *out.id = soup.polygons[hit.polygon].id;
    for (int ch = 0; ch < 3; ++ch) {
      out.rgb[ch] =
          alpha >= 1.0f ? to_byte(c[ch]) : to_byte(alpha * c[ch] + (1.0f - alpha) * float(out.rgb[ch]) / 255.0f);
    }
  };
  if (px.opaque.polygon != background_id) paint(px.opaque, 1.0f);
  for (const Hit& h : translucent) paint(h, soup.materials[soup.polygons[h.polygon].material].opacity);
  return px.opaque.polygon != background_id || !translucent.empty();
}

// Pixel (x, y) with `samples` rays on sample_pattern(samples): the id and shadow mask come from the
// centre ray (the visibility checks keep their meaning), the colour is the mean of the sub-sample
// rays' byte colours, each painted over the background as one centre ray is, rounded to nearest.
bool paint_supersampled(const ReferenceScene& rs, int x, int y, std::span<const glm::vec2> pattern,
                        std::vector<Hit>& translucent, const RayPaint& out) {
  const uint8_t background[3] = {out.rgb[0], out.rgb[1], out.rgb[2]};
  const bool hit = paint_ray(rs, x + 0.5, y + 0.5, translucent, out);
  uint32_t sum[3] = {0, 0, 0}, scratch_id = 0;
  for (const glm::vec2& offset : pattern) {
    uint8_t rgb[3] = {background[0], background[1], background[2]};
    paint_ray(rs, x + double(offset.x), y + double(offset.y), translucent, RayPaint{rgb, &scratch_id, nullptr});
    for (int ch = 0; ch < 3; ++ch) sum[ch] += rgb[ch];
  }
  const uint32_t n = uint32_t(pattern.size());
  for (int ch = 0; ch < 3; ++ch) out.rgb[ch] = uint8_t((sum[ch] + n / 2) / n);
  return hit;
}

void draw_row(const ReferenceScene& rs, int y, Frame& frame, size_t& hits, std::vector<Hit>& translucent) {
  const int samples = rs.input.options.antialias;
  const std::span<const glm::vec2> pattern = sample_pattern(samples);
  for (int x = 0; x < frame.image.width; ++x) {
    const size_t i = size_t(y) * size_t(frame.image.width) + size_t(x);
    const RayPaint out{frame.image.rgb.data() + i * 3, &frame.ids.ids[i],
                       frame.shadow_mask.empty() ? nullptr : &frame.shadow_mask[i * frame.shadow_mask_bytes],
                       frame.shadow_mask_bytes};
    hits += samples == 1 ? paint_ray(rs, x + 0.5, y + 0.5, translucent, out)
                         : paint_supersampled(rs, x, y, pattern, translucent, out);
  }
}

}  // namespace

void draw_reference(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings) {
  Stopwatch clock;
  const ReferenceScene rs = prepare_reference(input, stats);
  stats.shadow_skipped = !rs.shadows;
  timings.build_ms += clock.lap_ms();
  // One task per row on the render pool; each row is written by exactly one worker.
  const int height = frame.image.height;
  const unsigned threads = std::clamp(std::thread::hardware_concurrency(), 1u, 8u);
  std::vector<size_t> hits(threads, 0);
  std::vector<std::vector<Hit>> translucent(threads);
  std::atomic<bool> cancelled{false};
  parallel_for(threads, size_t(height), [&](size_t y, unsigned worker) {
    if (cancelled.load(std::memory_order_relaxed)) return;
    if (input.context.cancel && input.context.cancel->expired()) {
      cancelled = true;
      return;
    }
    draw_row(rs, int(y), frame, hits[worker], translucent[worker]);
  });
  if (cancelled) throw RenderCancelled();
  stats.fragments = 0;
  for (size_t h : hits) stats.fragments += h;
  timings.raster_ms += clock.lap_ms();
}

}  // namespace rr

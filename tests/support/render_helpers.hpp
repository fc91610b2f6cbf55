// Header-only helpers for tests that render small requests and check pixels against exact
// geometry: render a JSON request, cast the ray of a pixel centre, and read pixels back.
#pragma once

#include "render/core/camera.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace rr::testing {

struct SceneRender {
  RenderRequest request;
  PolygonSoup soup;
  ViewTransform view;
  RenderResult result;
};

inline SceneRender render_json(const nlohmann::json& request) {
  SceneRender out;
  out.request = request_from_json(request);
  out.soup = tessellate(out.request.scene.geometry);
  out.view = make_view(out.request.camera, out.request.options.width, out.request.options.height);
  out.result = render_frame(out.request.scene, out.soup, out.request.camera, out.request.options);
  return out;
}

// A request's JSON text through the path every caller takes: parse_request, prepare_scene, render().
struct TextRender {
  RenderRequest request;  // camera and options (the scene was moved into the prepared scene)
  RenderResult result;    // the frame with the report's timings and stats
  std::string png;        // in the request's PNG mode
  std::string scene_id;
};

inline TextRender render_text(std::string_view text, const RenderContext& context = {}) {
  TextRender out;
  out.request = parse_request(text);
  const PreparedScene scene = prepare_scene(std::move(out.request.scene));
  RenderOutcome rendered = render(out.request, scene, context);
  out.result = {std::move(rendered.frame), rendered.report.timings, std::move(rendered.report.stats)};
  out.png = std::move(rendered.png);
  out.scene_id = rendered.report.scene_id;
  return out;
}

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit
};

// The ray through the centre of pixel (x, y), from the eye.
inline Ray pixel_ray(const ViewTransform& view, int x, int y) {
  const double x_ndc = 2.0 * (x + 0.5) / view.width - 1.0, y_ndc = 1.0 - 2.0 * (y + 0.5) / view.height;
  const Mat4 world_from_clip = glm::inverse(view.clip_from_world);
  const Vec4 far = world_from_clip * Vec4(x_ndc, y_ndc, 1.0, 1.0);
  return {view.eye, glm::normalize(Vec3(far) / far.w - view.eye)};
}

// Where the ray of pixel (x, y) meets the plane dot(normal, p) == offset (in front of the eye).
inline std::optional<Vec3> pixel_on_plane(const ViewTransform& view, int x, int y, Vec3 normal, double offset) {
  const Ray r = pixel_ray(view, x, y);
  const double denom = glm::dot(normal, r.direction);
  if (denom == 0.0) return std::nullopt;
  const double t = (offset - glm::dot(normal, r.origin)) / denom;
  if (!(t > 0.0)) return std::nullopt;
  return r.origin + t * r.direction;
}

// Whether the ray origin + t * direction, t > 0, passes through the axis-aligned box [lo, hi].
inline bool ray_hits_box(Vec3 origin, Vec3 direction, Vec3 lo, Vec3 hi) {
  double t0 = 1e-12, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    if (direction[a] == 0.0) {
      if (origin[a] < lo[a] || origin[a] > hi[a]) return false;
      continue;
    }
    double ta = (lo[a] - origin[a]) / direction[a], tb = (hi[a] - origin[a]) / direction[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1;
}

inline int channel(const Image& image, int x, int y, int c = 0) { return image.pixel(x, y)[c]; }

}  // namespace rr::testing

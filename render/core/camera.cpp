// Camera -> view/projection matrices, and homogeneous clipping. GLM's lookAt/perspective are
// right-handed with OpenGL clip space (z in [-w, w]), which is the convention documented in
// camera.hpp and docs/scene-format.md.
#include "render/core/camera.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace rr {

ViewTransform make_view(const Camera& camera, int width, int height) {
  ViewTransform view;
  view.width = width;
  view.height = height;
  view.eye = camera.position;
  view.near = camera.near;
  view.far = camera.far;
  view.view_from_world = glm::lookAt(camera.position, camera.target, camera.up);
  double aspect = double(width) / double(height);
  view.clip_from_view = glm::perspective(radians(camera.fov_y_deg), aspect, camera.near, camera.far);
  view.clip_from_world = view.clip_from_view * view.view_from_world;
  return view;
}

Vec3 frame_direction() {
  const double elevation = radians(55.0);
  return {0.0, -std::sin(elevation), -std::cos(elevation)};
}

Camera frame_bounds(const Camera& base, Vec3 lo, Vec3 hi, int width, int height) {
  Camera out = base;
  out.frame_all = false;
  const Vec3 centre = (lo + hi) * 0.5;
  const double radius = std::max(0.5, glm::length(hi - lo) * 0.5);  // an empty or tiny scene: 1 m across
  const double half_y = radians(base.fov_y_deg) * 0.5;
  const double half_x = std::atan(std::tan(half_y) * double(width) / double(height));
  // A sphere of radius r lies inside a cone of half-angle a seen from distance r / sin(a); the cone
  // of the narrower half-angle lies inside the view pyramid.
  const double distance = radius / std::sin(std::min(half_x, half_y)) * 1.05;
  out.target = centre;
  out.position = centre - frame_direction() * distance;
  out.far = std::max(base.far, (distance + radius) * 1.01);
  return out;
}

Vec2 screen_from_clip(const ViewTransform& view, Vec4 p_clip) {
  double inv_w = 1.0 / p_clip.w;
  double x_ndc = p_clip.x * inv_w, y_ndc = p_clip.y * inv_w;
  return {(x_ndc + 1.0) * 0.5 * view.width, (1.0 - y_ndc) * 0.5 * view.height};
}

Vec2 project_to_screen(const ViewTransform& view, Vec3 p_world) {
  return screen_from_clip(view, view.clip_from_world * Vec4(p_world, 1.0));
}

namespace {

// Signed distance of a clip-space point to one clip plane; >= 0 is inside.
using PlaneFn = double (*)(const Vec4&);
constexpr std::array<PlaneFn, 6> clip_planes = {
    [](const Vec4& p) { return p.z + p.w; },  // near: z >= -w
    [](const Vec4& p) { return p.w - p.z; },  // far: z <= w
    [](const Vec4& p) { return clip_guard_band * p.w + p.x; },
    [](const Vec4& p) { return clip_guard_band * p.w - p.x; },
    [](const Vec4& p) { return clip_guard_band * p.w + p.y; },
    [](const Vec4& p) { return clip_guard_band * p.w - p.y; },
};

ClipVertex lerp(const ClipVertex& a, const ClipVertex& b, double t) {
  return {a.p_clip + (b.p_clip - a.p_clip) * t, a.p_world + (b.p_world - a.p_world) * t,
          a.normal + (b.normal - a.normal) * float(t)};
}

// One Sutherland-Hodgman pass. The intersection parameter is computed from the edge's endpoint
// in a fixed order (inside to outside) so that two polygons sharing an edge get bit-identical
// new vertices, and shared edges stay watertight after clipping.
void clip_against(PlaneFn plane, const std::vector<ClipVertex>& in, std::vector<ClipVertex>& out) {
  out.clear();
  size_t n = in.size();
  for (size_t i = 0; i < n; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % n];
    double da = plane(a.p_clip), db = plane(b.p_clip);
    if (da >= 0.0) out.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) {
      out.push_back(da >= 0.0 ? lerp(a, b, da / (da - db)) : lerp(b, a, db / (db - da)));
    }
  }
}

}  // namespace

bool clip_polygon(std::span<const ClipVertex> in, std::vector<ClipVertex>& out, std::vector<ClipVertex>& scratch) {
  // Trivial accept and reject first: most polygons of a room lie wholly inside or outside.
  uint32_t any_out = 0, all_out = 0x3F;
  for (const ClipVertex& v : in) {
    uint32_t code = 0;
    for (size_t k = 0; k < clip_planes.size(); ++k) {
      if (clip_planes[k](v.p_clip) < 0.0) code |= 1u << k;
    }
    any_out |= code;
    all_out &= code;
  }
  out.assign(in.begin(), in.end());
  if (all_out != 0) {
    out.clear();
    return false;
  }
  if (any_out == 0) return true;
  for (size_t k = 0; k < clip_planes.size(); ++k) {
    if (!(any_out & (1u << k))) continue;
    clip_against(clip_planes[k], out, scratch);
    std::swap(out, scratch);
    if (out.size() < 3) {
      out.clear();
      return false;
    }
  }
  return true;
}

}  // namespace rr

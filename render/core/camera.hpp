// Camera -> view and projection; clipping in homogeneous clip space. View space looks down -Z with
// +Y up; clip space is OpenGL's (x, y, z in [-w, w]); screen space is pixels with (0, 0) at the
// top-left corner of the top-left pixel and y pointing down, so pixel (x, y) has its centre at
// (x + 0.5, y + 0.5).
#pragma once

#include "render/core/scene.hpp"

#include <span>
#include <vector>

namespace rr {

struct ViewTransform {
  Mat4 view_from_world{1.0};
  Mat4 clip_from_view{1.0};
  Mat4 clip_from_world{1.0};
  Vec3 eye{0.0};
  int width = 1;
  int height = 1;
  double near = 0.1;
  double far = 100.0;
};

ViewTransform make_view(const Camera& camera, int width, int height);

// The framing view direction (eye towards target): from the +Z side, 55 degrees down.
Vec3 frame_direction();

// `base` moved to frame the axis-aligned box [lo, hi] in a width x height image: it looks along
// frame_direction() at the box's centre from the distance at which the box's bounding sphere fits
// the narrower of the two fields of view, with 5 % to spare; far grows to reach past the sphere.
// The web page's frameBounds (clients/web/src/camera.js) computes the same camera.
Camera frame_bounds(const Camera& base, Vec3 lo, Vec3 hi, int width, int height);

// Clip space -> screen space (x right, y down, in pixels). `w` must be > 0.
Vec2 screen_from_clip(const ViewTransform& view, Vec4 p_clip);

// World -> screen in one step; only meaningful for points in front of the camera.
Vec2 project_to_screen(const ViewTransform& view, Vec3 p_world);

// A vertex being clipped: its clip-space position and the attributes that are interpolated linearly
// along clipped edges (exact for world position, which is affine in clip space).
struct ClipVertex {
  Vec4 p_clip{0.0};
  Vec3 p_world{0.0};
  glm::vec3 normal{0.0f};
};

// How far outside the viewport x and y may go before a polygon is clipped there: a guard band, so
// most polygons only meet the near and far planes, while screen coordinates stay small enough for
// the rasterizer's fixed point.
constexpr double clip_guard_band = 2.0;

// Clips a convex polygon against near (z >= -w), far (z <= w) and the guard band
// (|x|, |y| <= clip_guard_band * w), Sutherland-Hodgman in homogeneous space. Writes the clipped
// polygon to `out` (cleared first); returns false when nothing is left. Never divides by w, so
// vertices behind the eye are handled exactly.
bool clip_polygon(std::span<const ClipVertex> in, std::vector<ClipVertex>& out, std::vector<ClipVertex>& scratch);

}  // namespace rr

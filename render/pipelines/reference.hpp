// The exact reference renderer (pipeline "reference", docs/accuracy.md): one double-precision ray
// through each pixel centre over the tessellated polygons, found with a BVH; the nearest hit gives
// the id, depth and a per-pixel Blinn-Phong colour (light_terms, interpolated vertex normals), with
// exact shadow rays to every light and translucent hits composited far to near. Ties follow the
// rasterizer: the pixel-centre test runs on the same projected, clipped polygon with the top-left
// rule, and equal depths keep the lower id. Used as the test oracle and the accuracy yardstick.
// options.antialias = S > 1 casts S more rays per pixel on sample_pattern(S) (S = 256, the 16 x 16
// grid, through the C++ API only: the edge-error ground truth) and averages their colours; the id
// and shadow mask stay the centre ray's.
#pragma once

#include "render/core/bvh.hpp"
#include "render/core/frame.hpp"
#include "render/core/ray_polygon.hpp"

#include <optional>

namespace rr {

void draw_reference(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings);

// The pixel-centre coverage test of the reference: whether screen point (px, py) lies in the convex
// screen polygon `xy` (either winding), with the rasterizer's top-left rule deciding points exactly
// on an edge. False for a polygon of zero area.
bool covers_screen_point(std::span<const Vec2> xy, double px, double py);

// Two depths closer than this (relative) are a tie, which the lower polygon id wins, as the
// z-buffer keeps the first drawn of equal depths.
constexpr double reference_depth_tie = 1e-12;

}  // namespace rr

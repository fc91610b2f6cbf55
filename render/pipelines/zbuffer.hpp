// The zbuffer pipeline: opaque polygons with a depth test (nearest 1/w wins, ties keep the first
// drawn, i.e. the lower id), then translucent polygons back to front with the depth test and no
// depth write, blended over what is there.
#pragma once

#include "render/core/frame.hpp"

namespace rr {

void draw_zbuffer(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings);

}  // namespace rr

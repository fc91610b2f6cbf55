// Shadow maps reused across frames and requests (docs/lighting.md, "Reusing maps"). In: the scene,
// its tessellation, the view and the options of one frame; out: the frame's maps, from the
// RenderContext's ShadowCache when an earlier frame built the same ones, else from one shadow pass.
// The key holds everything the pass reads, so a hit is the map that frame's own pass would draw.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/shadow.hpp"

#include <memory>
#include <string>

namespace rr {

// Scene id + what the pass reads of each light (type, direction or position, whether it is on) +
// the map options (size, pcf, biases, fit) + for fit == view the exact view (clip matrix and eye);
// a light's colour, the shading mode, the pipeline and the image size do not enter it.
std::string shadow_cache_key(const std::string& scene_id, const Scene& scene, const ViewTransform& view,
                             const ShadowOptions& options);

// The frame's maps, with stats.shadow_cache ("hit" or "miss") and stats.shadow_passes (0 or 1).
// Without a cache in `context` it runs the pass and reports "miss".
std::shared_ptr<const ShadowMaps> obtain_shadow_maps(const Scene& scene, const PolygonSoup& soup,
                                                     const ViewTransform& view, const RenderOptions& options,
                                                     const RenderContext& context, RenderStats& stats);

}  // namespace rr

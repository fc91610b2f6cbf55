// The one path from a parsed request to PNG bytes, used by the CLI, the service, bench-render, the
// fuzz harness and the benches. In: the view (camera + options of a RenderRequest) and a
// PreparedScene (parsed scene, its world-space tessellation, static id, placement warnings). Out: the
// frame, the PNG in the requested mode and a typed report; JSON is written only at the boundary
// (scene_io/report_json.hpp). A render is a pure function of its inputs and the context's caches.
#pragma once

#include "render/core/cells.hpp"
#include "render/core/frame.hpp"
#include "render/core/hierarchy.hpp"
#include "render/core/lamp_sight.hpp"
#include "render/core/placement.hpp"
#include "render/core/shadow_rays.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rr {

// What a scene becomes once, before any view of it is drawn; the scene store keeps these.
struct PreparedScene {
  Scene scene;
  PolygonSoup soup;       // world space, metres
  std::string static_id;  // scene_id(scene.geometry): X-Scene-Id and cache key
  std::vector<PlacementWarning> warnings;
  // The pipelines' hierarchy of `soup` (occlusion culling reads it; every view of the scene shares it).
  std::shared_ptr<const SceneHierarchy> hierarchy;
  // Its cells and portals, with `hierarchy`'s node masks (the portal walk reads them; shared likewise).
  std::shared_ptr<const SceneCells> cells;
  // The shadow rays' tree of `soup`'s casters, collapsed from `hierarchy` (shared likewise).
  std::shared_ptr<const ShadowBvh> shadow_bvh;
  // What its lamps see through the cells, and their fixture maps (lamp culling with shadow rays; shared likewise).
  std::shared_ptr<const PreparedLamps> lamps;
  double tessellate_ms =
      0.0;  // the time tessellation took, with the hierarchy's, cells', shadow tree's and lamps' builds
};

// Tessellates `scene`, builds its hierarchy, cells, shadow-ray tree and lamps' sight and computes
// its id and placement warnings. `threads` share the lamps' part (the result does not depend on them);
// a scene prepared for one render that casts no shadow rays leaves that part out (PrepareLamps::no:
// `lamps` stays null, and a frame that needs it makes its own).
enum class PrepareLamps { yes, no };
PreparedScene prepare_scene(Scene scene, unsigned threads = 1, PrepareLamps lamps = PrepareLamps::yes);
// What a scene prepared for one render with `options` needs: the lamps' sight when the render casts
// shadow rays (shadow.method rays, or auto exposure, whose pre-passes draw with rays).
PrepareLamps lamps_for(const RenderOptions& options);

struct RenderReport {
  StageTimings timings;  // queue .. encode and total (stage_table)
  RenderStats stats;
  std::string scene_id;
  PipelineId pipeline;  // a row of pipeline_table()
  int width = 0, height = 0;
  double exposure = 1.0;  // the multiplier drawn with: options.exposure, or the one "auto" chose
};

struct RenderOutcome {
  Frame frame;
  Camera camera;    // the camera drawn: the view's, or the frame it asked for (Camera::frame_all)
  std::string png;  // in view.options.png_compression; empty when context.encode is false
  RenderReport report;
};

// The camera a view is drawn with: `camera` itself, or with frame_all the frame of `soup`'s bounds
// at the view's image size (frame_bounds in render/core/camera.hpp).
Camera view_camera(const Camera& camera, const RenderOptions& options, const PolygonSoup& soup);

// Draws `view` of `scene` and encodes it. Throws RenderCancelled when context.cancel expires.
RenderOutcome render(const RenderRequest& view, const PreparedScene& scene, const RenderContext& context = {});

}  // namespace rr

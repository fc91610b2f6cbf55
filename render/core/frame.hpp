// The structs every pipeline reads and writes for one frame: its inputs (scene, polygons, view,
// options, what outlives the frame), its outputs (image, id buffer, optional shadow mask) and what it
// measured (stage timings, counts). They sit below the pipelines: no header here includes one of them.
#pragma once

#include "render/core/camera.hpp"
#include "render/core/cancel.hpp"
#include "render/core/image.hpp"
#include "render/core/lru_cache.hpp"
#include "render/core/scene.hpp"
#include "render/core/tessellate.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rr {

struct StageTimings {     // wall-clock milliseconds; a stage that did not run stays 0
  double queue_ms = 0.0;  // waiting for a render slot (the service); not part of total
  double parse_ms = 0.0;
  double tessellate_ms = 0.0;
  double build_ms = 0.0;     // BSP tree build (0 on a cache hit), the scene hierarchy when built for one frame
  double cull_ms = 0.0;      // frustum culling of whole objects and the occlusion walk (occlusion.hpp)
  double sort_ms = 0.0;      // painter's depth sort (and Newell tests)
  double traverse_ms = 0.0;  // BSP walk
  double shadow_ms = 0.0;    // shadow-map passes
  double raster_ms = 0.0;
  double shade_ms = 0.0;
  double encode_ms = 0.0;
  double total_ms = 0.0;  // parse -> encode, wall clock, less any queue wait in between
};

// The one list of stages: the name each is reported under (CLI line, JSON answer, Server-Timing,
// /metrics, the web page's bars) and its field, in report order. A stage added here appears in all.
struct StageField {
  const char* name;
  double StageTimings::*ms;
};
inline constexpr std::array<StageField, 12> stage_table = {{
    {"queue", &StageTimings::queue_ms},
    {"parse", &StageTimings::parse_ms},
    {"tessellate", &StageTimings::tessellate_ms},
    {"build", &StageTimings::build_ms},
    {"cull", &StageTimings::cull_ms},
    {"sort", &StageTimings::sort_ms},
    {"traverse", &StageTimings::traverse_ms},
    {"shadow", &StageTimings::shadow_ms},
    {"raster", &StageTimings::raster_ms},
    {"shade", &StageTimings::shade_ms},
    {"encode", &StageTimings::encode_ms},
    {"total", &StageTimings::total_ms},
}};

struct RenderStats {
  size_t polygons = 0;          // in the tessellated scene
  size_t polygons_culled = 0;   // skipped before rasterization (back-facing or outside the view)
  size_t polygons_drawn = 0;    // reached the rasterizer
  size_t triangles = 0;         // rasterized after clipping
  size_t fragments = 0;         // pixels that passed coverage (before the depth test)
  size_t lights_evaluated = 0;  // light-polygon (flat) or light-vertex/pixel evaluations
  bool shadow_skipped = true;   // no shadow lookups or rays (no light, shadows off, or nothing to cast)
  size_t lamps_culled = 0;      // shadow.method rays, culling on: lights that see no cell the view reaches
  size_t lamps_blocked = 0;     // the same: pairs of a shown polygon and a kept lamp that cannot light any of it
  // The same, what the frame made itself rather than took from its prepared scene or from this
  // thread's last frame: lamps' cube-face portal walks and fixture maps. Not in a report's counts
  // (they depend on what the thread drew before).
  size_t lamp_walks_made = 0;
  size_t fixture_maps_made = 0;
  size_t objects_culled = 0;  // solids (and walls, floor) wholly outside the view frustum
  // Occlusion culling (options.culling on, pipelines whose row uses it; the same for any thread count).
  size_t objects_occluded = 0;    // objects in the frustum with a front face, none of it drawn: all hidden
  size_t nodes_tested = 0;        // hierarchy (or BSP) nodes tested against the depth pyramid
  size_t polygons_projected = 0;  // polygons the pipeline clipped and projected (every pipeline counts them)
  // Cells and portals (cells.hpp; with occlusion culling): the scene's cells (1: none derived, 0: not
  // used), those the portal walk reached and the portal crossings it made.
  size_t cells = 0;
  size_t cells_visited = 0;
  size_t portals_walked = 0;
  std::string shadow_cache = "none";  // "hit", "miss" (the pass ran), "none" (no maps wanted)
  size_t shadow_passes = 0;           // shadow passes run by this frame: 1 on a miss, 0 on a hit
  // Painter.
  size_t painter_pairs_tested = 0;  // pairs that needed Newell's extra tests
  size_t painter_splits = 0;
  bool painter_budget_exhausted = false;  // newell hit a work bound: the order is not exact (docs/painter.md)
  // BSP.
  std::string bsp_cache;  // "hit", "miss" or "" when the pipeline has no tree
  size_t bsp_nodes = 0;
  size_t bsp_depth = 0;
  size_t bsp_input_polygons = 0;
  size_t bsp_fragments = 0;  // polygons stored in the tree after splitting
  size_t bsp_splits = 0;
  size_t bsp_subtrees_occluded = 0;  // front-to-back walk: subtrees skipped as already covered
  size_t bsp_polygons_occluded = 0;  // front-to-back walk: projected polygons skipped as covered
  bool bsp_screen_full = false;      // front-to-back walk stopped early: every pixel was written
};

struct Frame {
  Image image;   // RGB8
  IdBuffer ids;  // visible polygon per pixel (the last one drawn there for priority pipelines)
  // Only when RenderContext::shadow_mask asked for it (else empty): per pixel, shadow_mask_bytes
  // bytes (light_mask_bytes of the scene's lights); bit l % 8 of the pixel's byte l / 8 is set when
  // scene light l reaches the visible surface there: the light is on its lit side and, with shadows
  // on, the shadow lookup (visibility >= 0.5) or shadow ray finds it unblocked. With at most 8 lights
  // it is one byte a pixel, bit l for light l.
  std::vector<uint8_t> shadow_mask = {};
  size_t shadow_mask_bytes = 1;
};

// Bytes per pixel of a light mask for `lights` lights: one bit each, at least one byte.
inline size_t light_mask_bytes(size_t lights) { return lights > 8 ? (lights + 7) / 8 : 1; }

struct SceneHierarchy;                           // hierarchy.hpp: the pipelines' BVH of one static soup
struct SceneCells;                               // cells.hpp: cells and portals of one static scene
struct ShadowBvh;                                // shadow_rays.hpp: the shadow rays' tree of one static soup
struct PreparedLamps;                            // lamp_sight.hpp: what a prepared scene's lamps see
struct LampsBlocked;                             // sight_cones.hpp: lamps that cannot light a polygon
class DepthPyramid;                              // occlusion.hpp: one frame's hierarchical depth
struct BspTree;                                  // bsp.hpp: a tree of one static scene for one set of BSP options
using BspCache = SharedLruCache<BspTree>;        // keyed by scene id + BSP options, shared across requests
struct ShadowMaps;                               // shadow.hpp: the shadow pass's depth maps for one frame
using ShadowCache = SharedLruCache<ShadowMaps>;  // keyed by scene id + lights + map options (+ view)
struct SelectedView;                             // view_selection.hpp: a view's selection of a scene's soup
using ViewCache = SharedLruCache<SelectedView>;  // keyed by scene id + selection (+ "|rays")

// What one render is given besides the scene and the view (all optional): what outlives it and is
// shared across requests (caches, cancellation), how to run it, and what its caller measured first.
struct RenderContext {
  BspCache* bsp_cache = nullptr;        // null: the bsp pipeline builds a private tree per frame
  const CancelToken* cancel = nullptr;  // null: never cancelled
  std::string scene_id;                 // scene_id(geometry) when the caller knows it; else computed
  ShadowCache* shadow_cache = nullptr;  // null: every frame with shadows runs its own shadow pass
  // Views that leave levels or ceilings out: the kept polygons and their shadow-ray tree, made once
  // per selection. Null: each such frame copies its selection (and builds its tree) anew.
  ViewCache* view_cache = nullptr;
  bool shadow_mask = false;  // fill Frame::shadow_mask (error measures); off: no cost
  unsigned threads = 1;      // threads drawing the tiles and encoding the PNG (output does not depend on it)
  // The hierarchy of `hierarchy_soup` (the prepared scene's soup; a frame of a selection of it maps
  // its polygons by id). Null: a frame that culls occlusion builds a private one (timed as build).
  const SceneHierarchy* hierarchy = nullptr;
  const PolygonSoup* hierarchy_soup = nullptr;
  // The cells of `hierarchy_soup` with the hierarchy's node masks. Null with a hierarchy: no cells;
  // null without one: the frame derives them with its private hierarchy (timed as build).
  const SceneCells* cells = nullptr;
  // The shadow-ray tree of `shadow_bvh_soup` (the prepared scene's soup). Null: a frame that casts
  // shadow rays over another soup (a view's selection) builds a private one.
  const ShadowBvh* shadow_bvh = nullptr;
  const PolygonSoup* shadow_bvh_soup = nullptr;
  // What the lamps of `lamps_soup` (the prepared scene's soup) see, made with it; lamp culling takes
  // an entry only when it was made from what the frame would make it from. Null: each frame makes its own.
  const PreparedLamps* lamps = nullptr;
  const PolygonSoup* lamps_soup = nullptr;
  bool use_cells = true;               // benches only: false culls occlusion without the portal walk
  int cull_eager = 0;                  // tests only: the occlusion test made that many margins too eager (a mutation)
  uint32_t drop_portal = 0xFFFFFFFFu;  // tests only: the portal walk ignores this portal (a mutation)
  bool encode = true;                  // false: render() leaves the PNG empty (bench-render's frames)
  // What the caller measured for this request before calling render(), carried into its report.
  // render() adds its own time to before_ms, so total = parse start -> encode end, less queue.
  double queue_ms = 0.0;       // waiting for a render slot
  double parse_ms = 0.0;       // request -> RenderRequest
  double tessellate_ms = 0.0;  // the scene prepared for this request (0 for a stored, prepared one)
  double before_ms = 0.0;      // wall clock from parse start to the render() call, queue wait excluded
};

struct FrameInput {
  // Whether polygon `p` may be visible as far as its whole object goes (see objects_in_view).
  bool object_may_show(const Polygon& p) const { return !objects_in_view || (*objects_in_view)[p.object]; }
  // Whether polygon `index` of `soup` may be visible as far as occlusion culling goes.
  bool polygon_may_show(uint32_t index) const { return !polygons_shown || (*polygons_shown)[index]; }
  // The same for a polygon (or a piece of one) by its id.
  bool id_may_show(uint32_t id) const { return !polygons_shown_by_id || (*polygons_shown_by_id)[id]; }

  const Scene& scene;
  const PolygonSoup& soup;
  const ViewTransform& view;
  const RenderOptions& options;
  const RenderContext& context;
  const ShadowMaps* shadows = nullptr;  // null: no shadow lookups (none needed or shadows off)
  // shadow.method rays: the shadow-ray tree of `soup` (null: no shadow rays). Never set with `shadows`.
  const ShadowBvh* shadow_rays = nullptr;
  // Shadow maps with translucent polygons in `soup`: its shadow-ray tree, whose panes' tree tints
  // the light that the maps let through (null: nothing to tint). Never set with `shadow_rays`.
  const ShadowBvh* glass_rays = nullptr;
  // Per scene light, 1 when the light is skipped altogether (rays only: it sees no cell the view
  // reaches, so every ray it would get is blocked); null: none is.
  const std::vector<uint8_t>* lights_skipped = nullptr;
  // Finer, per polygon (rays only): the lamps none of whose rays to any point of the polygon can be
  // unblocked, because no sight line from the lamp into the polygon's cells reaches its bounds.
  // Null: none known.
  const LampsBlocked* lamps_blocked = nullptr;
  // Per soup object, 0 when its bounding box lies outside the view frustum (frustum.hpp); null:
  // not computed (the bsp pipeline culls subtrees of its tree instead).
  const std::vector<uint8_t>* objects_in_view = nullptr;
  // Per soup polygon, 0 when the occlusion walk found it hidden; null: no occlusion culling (off, or
  // the pipeline's row does not use it). The pyramid the walk filled, for pipelines with their own
  // tree (bsp tests its subtrees against it); null as well without occlusion culling.
  const std::vector<uint8_t>* polygons_shown = nullptr;
  const std::vector<uint8_t>* polygons_shown_by_id = nullptr;  // the same, indexed by Polygon::id
  const DepthPyramid* occlusion = nullptr;
  size_t* lights_evaluated = nullptr;  // SurfaceShader adds its light evaluations here
  uint8_t* shadow_mask = nullptr;      // Frame::shadow_mask's pixels when requested, else null
  size_t shadow_mask_bytes = 1;        // Frame::shadow_mask_bytes: bytes per pixel of shadow_mask
};

using PipelineFn = void (*)(const FrameInput& input, Frame& frame, RenderStats& stats, StageTimings& timings);

}  // namespace rr

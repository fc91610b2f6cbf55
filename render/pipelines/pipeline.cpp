// The render entry point below render(): one frame of a tessellated scene through the pipeline its
// table row (pipeline_table.cpp) names.
#include "render/pipelines/pipeline.hpp"

#include "render/core/cells.hpp"
#include "render/core/draw.hpp"
#include "render/core/frustum.hpp"
#include "render/core/hierarchy.hpp"
#include "render/core/lamp_sight.hpp"
#include "render/core/occlusion.hpp"
#include "render/core/parallel.hpp"
#include "render/core/shadow.hpp"
#include "render/core/shadow_rays.hpp"
#include "render/core/sight_cones.hpp"
#include "render/core/timer.hpp"
#include "render/pipelines/shadow_cache.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

namespace rr {

namespace {

// What the cull stage hands the pipeline; it outlives the draw.
struct CullState {
  ObjectsInView objects;
  std::unique_ptr<SceneHierarchy> private_hierarchy;
  std::vector<uint32_t> frame_of;  // hierarchy-soup polygon -> frame polygon (empty: the same soup)
  std::vector<uint8_t> drawn, opaque;
  OcclusionResult occlusion;
  std::vector<uint8_t> shown_by_id;  // when some polygon's id is not its index
  std::unique_ptr<SceneCells> private_cells;
  std::vector<uint8_t> object_present;  // per object: it has polygons in the frame's soup
  CellWalk cell_walk;
  CellFilter cell_filter;
  CellConditions cell_conditions;
  std::vector<uint8_t> lights_skipped;  // per scene light (shadow rays: FrameInput::lights_skipped)
  LampsBlocked lamps_blocked;           // FrameInput::lamps_blocked; its sight per light from cull_lamps
  // Per scene light, the last fixture map this thread made and everything it was made from: a frame
  // whose inputs compare equal takes it as it is (the map is a function of them alone).
  struct FixtureCache {
    std::vector<double> key;
    FixtureMap map;
  };
  std::vector<FixtureCache> fixture_cache;
  // Per scene light, the cube-face portal walks from its position that this thread last made (when
  // the prepared scene's do not serve): a walk is a function of the cells, the conditions and the
  // viewpoint alone, so a frame with the same cells (serial), conditions and light position takes
  // them as they are.
  struct LampWalks {
    bool kept = false;
    Vec3 position{0.0};
    std::vector<LampFaceWalk> faces;
  };
  std::vector<LampWalks> lamp_walks;
  std::vector<std::pair<size_t, size_t>> made;  // per scene light: walks and fixture maps this frame made
  uint64_t lamp_walks_cells = 0;                // the cells' serial and the conditions every kept walk was made with
  CellConditions lamp_walks_conditions;
  double lamp_tolerance = 0.0;   // cull_lamps' tolerance (metres), which block_lamps' tests share
  std::vector<uint8_t> id_seen;  // per polygon id, while filling lamps_blocked
};

// The hierarchy of `soup`: the context's when it was built on this soup or on the soup this one was
// selected from (polygon ids are indices there), else a private one built now (timed as build).
const SceneHierarchy& frame_hierarchy(const PolygonSoup& soup, const RenderContext& context, CullState& state,
                                      StageTimings& timings) {
  if (context.hierarchy && context.hierarchy_soup == &soup) return *context.hierarchy;
  if (context.hierarchy && context.hierarchy_soup) {
    const std::vector<Polygon>& all = context.hierarchy_soup->polygons;
    state.frame_of.assign(all.size(), no_frame_polygon);
    bool mapped = true;
    for (uint32_t j = 0; j < soup.polygons.size() && mapped; ++j) {
      const uint32_t id = soup.polygons[j].id;
      mapped = id < all.size() && all[id].id == id && state.frame_of[id] == no_frame_polygon;
      if (mapped) state.frame_of[id] = j;
    }
    if (mapped) return *context.hierarchy;
    state.frame_of.clear();
  }
  Stopwatch build_clock;
  state.private_hierarchy = std::make_unique<SceneHierarchy>(build_hierarchy(soup, context.cancel));
  timings.build_ms += build_clock.elapsed_ms();
  return *state.private_hierarchy;
}

// The cells of the frame's hierarchy: the context's with its hierarchy, derived now with a private one
// (timed as build), none when the context has a hierarchy without cells or the caller turned them off.
const SceneCells* frame_cells(const FrameInput& input, const SceneHierarchy& hierarchy, CullState& state,
                              StageTimings& timings) {
  state.private_cells.reset();
  if (!input.context.use_cells) return nullptr;
  if (!state.private_hierarchy) return input.context.cells;
  Stopwatch build_clock;
  state.private_cells = std::make_unique<SceneCells>(build_cells(input.scene.geometry, input.soup, hierarchy));
  timings.build_ms += build_clock.elapsed_ms();
  return state.private_cells.get();
}

// The portal walk from the camera: the filter the occlusion walk applies, or null when the frame may
// not skip cells (none derived, or a wall that bounds them is not drawn). Counts what it did.
const CellFilter* walk_portals(const SceneCells& cells, const FrameInput& input, CullState& state, RenderStats& stats) {
  stats.cells = cells.cells.size();
  stats.cells_visited = cells.cells.size();
  if (!cells.derived()) return nullptr;
  state.cell_conditions = cell_conditions(cells, state.object_present);
  CellConditions& conditions = state.cell_conditions;
  conditions.dropped_pair = input.context.drop_portal;
  if (!conditions.valid) return nullptr;
  walk_cells(cells, conditions, cell_viewpoint(input.view), state.cell_walk);
  make_cell_filter(cells, state.cell_walk, input.view.width, input.view.height, state.cell_filter);
  stats.cells_visited = state.cell_walk.cells_visited;
  stats.portals_walked = state.cell_walk.portals_walked;
  return &state.cell_filter;
}

// Lamps culled by what they see (shadow rays only, after the camera's portal walk): a point light
// whose own portal walk, one per cube face from its position over the whole sphere, reaches no cell
// the camera's walk reached, cannot light any point the frame shows. A shown point lies in a cell the
// camera reached, and an unblocked ray from the lamp to it would be a sight line from the lamp into
// that cell; every other straight line crosses a wall, floor, ceiling or door leaf the frame draws,
// and those are shadow casters (a closed wall by the face turned away from the lamp). So each of its
// rays would be blocked and its terms scaled by 0: skipping it keeps the bytes. Finer, per cell both
// walks reach: the shown point lies on the camera's sight line into that cell, so in the cone of the
// camera's regions of it, and on the lamp's sight line into it, so in the cone of that face's regions
// of it, and on a polygon, so in the soup's box. A lamp none of whose faces' cones meets the
// camera's cone of a shared cell within that box lights no shown point either (the outside, one cell
// that every window opens on, is the case this decides). With shadow maps a lamp is never skipped (a
// map's bias may let light through where a ray would not). Directional lights come from outside
// every cell and are never skipped.
void cull_lamps(const SceneCells& cells, FrameInput& input, CullState& state, RenderStats& stats) {
  const auto& lights = input.scene.lights;
  state.lights_skipped.assign(lights.size(), 0);
  state.lamps_blocked.sight.resize(lights.size());
  for (LampSight& sight : state.lamps_blocked.sight) sight.everything = true;
  state.lamps_blocked.fixtures.clear();
  state.lamp_tolerance = 0.0;
  input.lights_skipped = &state.lights_skipped;
  if (state.cell_walk.everything) return;
  const PolygonSoup& soup = input.soup;
  if (soup.positions.empty()) return;
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double tolerance = lamp_tolerance(lo, hi);
  state.lamp_tolerance = tolerance;
  const Mat4 camera_clip_from_world = cell_viewpoint(input.view).clip_from_world;
  const size_t n_cells = cells.cells.size();
  // The prepared scene's walks and fixture maps, where they were made from what this frame would
  // make them from; per light, its position must match too.
  const PreparedLamps* prepared = input.context.lamps_soup == &soup ? input.context.lamps : nullptr;
  const bool prepared_walks = prepared && prepared->cells != 0 && prepared->cells == cells.serial &&
                              prepared->conditions == state.cell_conditions;
  const bool prepared_fixtures = prepared && prepared->tolerance == tolerance;
  auto prepared_lamp = [&](size_t l) -> const PreparedLamps::Lamp* {
    if (!prepared || l >= prepared->lamps.size()) return nullptr;
    const PreparedLamps::Lamp& lamp = prepared->lamps[l];
    return lamp.point && lamp.position == lights[l].position ? &lamp : nullptr;
  };
  bool all_fixtures_prepared = prepared_fixtures;
  for (size_t l = 0; l < lights.size() && all_fixtures_prepared; ++l)
    all_fixtures_prepared = lights[l].type != LightType::point || prepared_lamp(l);
  const std::vector<std::vector<uint32_t>> fixture =
      all_fixtures_prepared ? std::vector<std::vector<uint32_t>>(lights.size()) : lamp_fixtures(soup, lights);
  if (cells.serial == 0 || state.lamp_walks_cells != cells.serial ||
      state.lamp_walks_conditions != state.cell_conditions) {
    for (CullState::LampWalks& walks : state.lamp_walks) walks.kept = false;
    state.lamp_walks_cells = cells.serial;
    state.lamp_walks_conditions = state.cell_conditions;
  }
  state.lamp_walks.resize(lights.size());
  state.lamps_blocked.fixtures.assign(lights.size(), FixtureMap{});
  state.fixture_cache.resize(lights.size());
  state.made.assign(lights.size(), {0, 0});  // per light: walks, fixture maps
  // Per cell and face: the group of the face's cone with the camera's, gathered face by face and
  // then laid out by cell. Lamps are independent: one task each, writing only its own entries.
  struct Group {
    uint32_t cell = 0, first = 0, count = 0;
  };
  parallel_for(input.context.threads, lights.size(), [&](size_t l, unsigned) {
    const Light& light = lights[l];
    LampSight& sight = state.lamps_blocked.sight[l];
    if (light.type != LightType::point) return;
    const PreparedLamps::Lamp* ready = prepared_lamp(l);
    if (prepared_fixtures && ready) {
      state.lamps_blocked.fixtures[l] = ready->fixture;
    } else if (!fixture[l].empty()) {
      thread_local std::vector<double> key;
      key.assign({light.position.x, light.position.y, light.position.z, tolerance, double(lamp_fixture_bins)});
      for (uint32_t k : fixture[l]) {
        const Polygon& q = soup.polygons[k];
        key.insert(key.end(), {double(q.flags), q.normal.x, q.normal.y, q.normal.z, q.offset, double(q.vertex_count)});
        for (const Vec3& v : soup.points(q)) key.insert(key.end(), {v.x, v.y, v.z});
      }
      CullState::FixtureCache& cached = state.fixture_cache[l];
      if (cached.key != key) {
        cached.key = key, cached.map = fixture_map(soup, fixture[l], light, tolerance, lamp_fixture_bins);
        state.made[l].second = 1;
      }
      state.lamps_blocked.fixtures[l] = cached.map;
    }
    const std::vector<LampFaceWalk>* faces = nullptr;
    if (prepared_walks && ready) {
      faces = &ready->faces;
    } else {
      CullState::LampWalks& walks = state.lamp_walks[l];
      if (!(walks.kept && walks.position == light.position)) {
        walks.kept = true, walks.position = light.position;
        walks.faces = walk_from_lamp(cells, state.cell_conditions, light.position);
        state.made[l].first = walks.faces.size();
      }
      faces = &walks.faces;
    }
    thread_local std::vector<Group> found;
    thread_local std::vector<HalfSpace> planes;
    bool sees = false;
    found.clear();
    planes.clear();
    for (size_t f = 0; f < faces->size(); ++f) {
      const LampFaceWalk& walk = (*faces)[f];
      if (walk.everything) {
        sees = true;
        found.clear();
        break;
      }
      const Mat4 lamp_clip_from_world = lamp_face_view(light.position, f).clip_from_world;
      for (size_t c = 0; c < n_cells; ++c) {
        if (!walk.reached[c] || !state.cell_walk.reached[c]) continue;
        const uint32_t first = uint32_t(planes.size());
        add_sight_cone(camera_clip_from_world, bounding_region(state.cell_walk, c), planes);
        add_sight_cone(lamp_clip_from_world, walk.regions[c], planes);
        const std::span<const HalfSpace> cone(planes.data() + first, planes.size() - first);
        if (!half_spaces_meet_in_box(cone, lo, hi, tolerance)) {
          planes.resize(first);
          continue;
        }
        sees = true;
        found.push_back({uint32_t(c), first, uint32_t(planes.size() - first)});
      }
    }
    if (!sees) {
      state.lights_skipped[l] = 1;
      return;
    }
    if (found.empty()) return;  // a walk gave up
    sight.everything = false;
    std::stable_sort(found.begin(), found.end(), [](const Group& a, const Group& b) { return a.cell < b.cell; });
    sight.cell_first.assign(n_cells + 1, 0);
    for (const Group& g : found) ++sight.cell_first[g.cell + 1];
    for (size_t c = 0; c < n_cells; ++c) sight.cell_first[c + 1] += sight.cell_first[c];
    sight.groups.clear();
    for (const Group& g : found) sight.groups.emplace_back(g.first, g.count);
    sight.planes.assign(planes.begin(), planes.end());
  });
  for (uint8_t skipped : state.lights_skipped) stats.lamps_culled += skipped;
  for (const auto& [walks, maps] : state.made) stats.lamp_walks_made += walks, stats.fixture_maps_made += maps;
}

// Lamps blocked per polygon (shadow rays, after the occlusion walk): a shown point x of polygon p
// that a kept lamp lights lies in one of p's cells (its bounds touch every cell it has a point in),
// and, by cull_lamps' argument, in the camera's cone and a face's cone of that cell, and in p's
// bounding box. When, for every cell of p, the box lies wholly outside one half-space of each of
// that cell's groups (each moved out by the tolerance), the lamp lights no point of p: its rays would
// all be blocked, and leaving the lamp out of p's shading keeps the bytes.
void block_lamps(const SceneCells& cells, uint32_t ids, FrameInput& input, CullState& state, RenderStats& stats) {
  const PolygonSoup& soup = input.soup;
  const auto& lights = input.scene.lights;
  LampsBlocked& out = state.lamps_blocked;
  bool any_sight = false, any_fixture = false;
  for (size_t l = 0; l < lights.size(); ++l) {
    if (state.lights_skipped[l]) continue;
    any_sight = any_sight || !out.sight[l].everything;
    any_fixture = any_fixture || (l < out.fixtures.size() && out.fixtures[l].n > 0);
  }
  out.words = (lights.size() + 63) / 64;
  out.bits.clear();  // no polygon blocked unless a lamp's sight says so below
  if (any_fixture) input.lamps_blocked = &out;
  if (!any_sight) return;
  out.bits.assign(size_t(ids) * out.words, 0);
  // An id shared by several frame polygons is left unblocked (one of them may be drawn unshown).
  state.id_seen.assign(ids, 0);
  for (const Polygon& p : soup.polygons) state.id_seen[p.id] = uint8_t(std::min(state.id_seen[p.id] + 1, 2));
  const bool selection = !state.frame_of.empty();
  // Chunks of polygons as tasks: each writes the rows of its own polygons' ids (an id of one polygon
  // only) and its own count.
  constexpr size_t chunk = 512;
  const size_t chunks = (soup.polygons.size() + chunk - 1) / chunk;
  std::vector<size_t> blocked(chunks, 0);
  parallel_for(input.context.threads, chunks, [&](size_t task, unsigned) {
    const size_t end = std::min(soup.polygons.size(), (task + 1) * chunk);
    for (size_t j = task * chunk; j < end; ++j) {
      const Polygon& p = soup.polygons[j];
      if (!state.occlusion.shown[j] || state.id_seen[p.id] != 1) continue;
      Vec3 plo(std::numeric_limits<double>::infinity()), phi(-std::numeric_limits<double>::infinity());
      for (const Vec3& v : soup.points(p)) plo = glm::min(plo, v), phi = glm::max(phi, v);
      const std::span<const uint32_t> own = cells.cells_of_polygon(selection ? p.id : uint32_t(j));
      uint64_t* const row = out.bits.data() + size_t(p.id) * out.words;
      for (uint32_t l = 0; l < lights.size(); ++l) {
        const LampSight& sight = out.sight[l];
        if (state.lights_skipped[l] || sight.everything) continue;
        bool lit = false;
        for (size_t k = 0; k < own.size() && !lit; ++k) {
          for (uint32_t g = sight.cell_first[own[k]]; g < sight.cell_first[own[k] + 1] && !lit; ++g) {
            const auto [first, count] = sight.groups[g];
            lit = !box_outside_half_spaces({sight.planes.data() + first, count}, plo, phi, state.lamp_tolerance);
          }
        }
        if (!lit) row[l / 64] |= uint64_t(1) << (l % 64), ++blocked[task];
      }
    }
  });
  for (size_t b : blocked) stats.lamps_blocked += b;
  input.lamps_blocked = &out;
}

// The cull stage: whole objects outside the frustum (rows that cull objects), then the occlusion
// walk (rows that use it, with options.culling on). Timed as cull.
void cull(const PipelineInfo& pipeline, FrameInput& input, CullState& state, RenderStats& stats,
          StageTimings& timings) {
  Stopwatch clock;
  const PolygonSoup& soup = input.soup;
  if (pipeline.culls_objects) {
    state.objects = objects_in_view(soup, input.view);
    input.objects_in_view = &state.objects.visible;
    stats.objects_culled = state.objects.culled;
  }
  if (!pipeline.occlusion_culling || input.options.culling != CullingMode::on) {
    timings.cull_ms += clock.elapsed_ms();
    return;
  }
  const double before = timings.build_ms;
  const SceneHierarchy& hierarchy = frame_hierarchy(soup, input.context, state, timings);
  const SceneCells* cells = frame_cells(input, hierarchy, state, timings);
  const double built = timings.build_ms - before;
  const size_t n = soup.polygons.size();
  state.drawn.resize(n);
  state.opaque.resize(n);
  const bool selection = !state.frame_of.empty();
  state.object_present.assign(selection ? soup.objects.size() : 0, 0);
  for (size_t i = 0; i < n; ++i) {
    const Polygon& p = soup.polygons[i];
    state.drawn[i] = !is_back_facing(p, input.view.eye) && input.object_may_show(p);
    state.opaque[i] = !(p.flags & polygon_translucent);
    if (selection) state.object_present[p.object] = 1;
  }
  OcclusionCandidates candidates{state.drawn, state.opaque};
  if (cells) candidates.cells = walk_portals(*cells, input, state, stats);
  if (candidates.cells && input.shadow_rays) cull_lamps(*cells, input, state, stats);
  walk_occlusion(hierarchy, soup, state.frame_of, candidates, input.view, input.context.cull_eager, state.occlusion);
  uint32_t ids = 0;
  bool same = true;
  for (size_t i = 0; i < n; ++i) {
    ids = std::max(ids, soup.polygons[i].id + 1);
    same = same && soup.polygons[i].id == i;
  }
  if (candidates.cells && input.shadow_rays) block_lamps(*cells, ids, input, state, stats);
  input.polygons_shown = &state.occlusion.shown;
  input.polygons_shown_by_id = &state.occlusion.shown;
  if (!same) {
    state.shown_by_id.assign(ids, 0);
    for (size_t i = 0; i < n; ++i) state.shown_by_id[soup.polygons[i].id] |= state.occlusion.shown[i];
    input.polygons_shown_by_id = &state.shown_by_id;
  }
  input.occlusion = &state.occlusion.pyramid;
  stats.nodes_tested = state.occlusion.nodes_tested;
  // An object counts as occluded when it has a polygon the pipeline would draw and the walk showed none.
  std::vector<uint8_t> object_state(soup.objects.size(), 0);  // bit 0: drawn; bit 1: shown
  for (size_t i = 0; i < n; ++i) {
    if (state.drawn[i]) object_state[soup.polygons[i].object] |= uint8_t(1 | (state.occlusion.shown[i] << 1));
  }
  for (uint8_t s : object_state) stats.objects_occluded += s == 1;
  timings.cull_ms += clock.elapsed_ms() - built;
}

}  // namespace

RenderResult render_frame(const Scene& scene, const PolygonSoup& soup, const Camera& camera,
                          const RenderOptions& options, const RenderContext& context) {
  Stopwatch clock;
  RenderResult result;
  result.frame.image = Image(options.width, options.height, scene.background);
  result.frame.ids = IdBuffer(options.width, options.height);
  if (context.shadow_mask) {
    result.frame.shadow_mask_bytes = light_mask_bytes(scene.lights.size());
    result.frame.shadow_mask.assign(result.frame.ids.ids.size() * result.frame.shadow_mask_bytes, 0);
  }
  result.stats.polygons = soup.polygons.size();
  ViewTransform view = make_view(camera, options.width, options.height);
  FrameInput input{scene, soup, view, options, context};
  if (context.shadow_mask) {
    input.shadow_mask = result.frame.shadow_mask.data();
    input.shadow_mask_bytes = result.frame.shadow_mask_bytes;
  }
  const PipelineInfo& pipeline = pipeline_info(options.pipeline);
  check_cancel(context.cancel);
  // The shadow pass runs at most once, before any pipeline draws, and not at all when the shadow
  // cache holds this frame's maps; with no light or shadows off it does not run (shadow_ms stays 0).
  // It comes before culling and reads none of it: the maps are the same with culling on or off.
  std::shared_ptr<const ShadowMaps> shadow_maps;
  ShadowBvh private_rays;
  if (options.shadows && !scene.lights.empty() && pipeline.shadow_maps && options.shadow.method == ShadowMethod::rays) {
    // The casters are the frame's soup: a view's selection (levels, ceilings left out) casts what it
    // draws, as the maps and the reference do, so it takes a private tree (timed as shadow).
    if (context.shadow_bvh && context.shadow_bvh_soup == &soup) {
      input.shadow_rays = context.shadow_bvh;
    } else {
      Stopwatch shadow_clock;
      private_rays = build_shadow_bvh(soup, build_hierarchy(soup, context.cancel));
      input.shadow_rays = &private_rays;
      result.timings.shadow_ms = shadow_clock.elapsed_ms();
    }
  } else if (options.shadows && !scene.lights.empty() && pipeline.shadow_maps) {
    Stopwatch shadow_clock;
    shadow_maps = obtain_shadow_maps(scene, soup, view, options, context, result.stats);
    if (!shadow_maps->empty()) {
      input.shadows = shadow_maps.get();
      // The maps hold the opaque casters; light through panes is tinted by exact rays against the
      // panes' tree, the same that shadow.method rays casts.
      // The prepared scene's tree says whether it has panes; only a view's selection of the soup
      // is searched for them, and given a private tree when it has some.
      if (context.shadow_bvh && context.shadow_bvh_soup == &soup) {
        if (!context.shadow_bvh->glass.nodes.empty()) input.glass_rays = context.shadow_bvh;
      } else if (std::any_of(soup.polygons.begin(), soup.polygons.end(),
                             [](const Polygon& p) { return (p.flags & polygon_translucent) != 0; })) {
        private_rays = build_shadow_bvh(soup, build_hierarchy(soup, context.cancel));
        input.glass_rays = &private_rays;
      }
    }
    result.timings.shadow_ms = shadow_clock.elapsed_ms();
  }
  result.stats.shadow_skipped = input.shadows == nullptr && input.shadow_rays == nullptr;
  // Whole objects outside the frustum, and what lies behind what is drawn first, are skipped before
  // any per-polygon work of the pipeline.
  // Kept by this thread for its next frame, so the buffers' memory is not allocated again.
  thread_local CullState kept_cull_state;
  CullState& culled = kept_cull_state;
  culled.private_hierarchy.reset();
  culled.frame_of.clear();
  cull(pipeline, input, culled, result.stats, result.timings);
  check_cancel(context.cancel);
  input.lights_evaluated = &result.stats.lights_evaluated;
  pipeline.draw(input, result.frame, result.stats, result.timings);
  result.timings.total_ms = clock.elapsed_ms();
  return result;
}

}  // namespace rr

// The table of pipelines: one row per pipeline holds every fact about it (name, summary, draw
// function, whether whole objects are culled before it draws, whether it uses shadow maps, whether
// it uses occlusion culling).
// RenderOptions::pipeline is a PipelineId, an index into this table; validation, GET /v1/pipelines,
// the tests, the benchmarks and the fuzz harness iterate the table and never name a pipeline in code.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/names.hpp"

#include <string_view>

namespace rr {

struct PipelineInfo {
  const char* name;
  const char* summary;
  PipelineFn draw;
  // render_frame skips whole objects outside the frustum before the pipeline sees a polygon; off
  // for pipelines that cull on their own (bsp walks its tree; reference casts rays through a BVH).
  bool culls_objects = false;
  bool shadow_maps = true;  // render_frame runs the shadow-map pass for it (when shadows are on)
  // With options.culling on, render_frame walks the scene's hierarchy against a depth pyramid first
  // (occlusion.hpp) and the pipeline skips what it found hidden, with byte-identical output. Off for
  // painter (its keys and Newell's budget depend on which polygons it is given) and the reference
  // (the exhaustive oracle).
  bool occlusion_culling = false;
};

NameTable<PipelineInfo> pipeline_table();  // row 0 is the default pipeline
const PipelineInfo* find_pipeline(std::string_view name);
const PipelineInfo& pipeline_info(PipelineId id);
PipelineId pipeline_id(const PipelineInfo& row);  // row: a row of pipeline_table()
// For code that names a pipeline (tests, benches): throws std::invalid_argument for an unknown name.
PipelineId pipeline_id(std::string_view name);

}  // namespace rr

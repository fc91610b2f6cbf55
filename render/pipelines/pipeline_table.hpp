// The table of pipelines: one row per pipeline holds every fact about it (name, summary, draw
// function) and what it supports, one column per capability (object culling, shadow maps, occlusion
// culling, the A-buffer, exact visibility, being the reference). RenderOptions::pipeline is a
// PipelineId, an index into this table; validation, GET /v1/pipelines, the tests, the benchmarks and
// the fuzz harness iterate the table and pick rows by its columns, so a new row is tested for what it
// says it does.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/names.hpp"

#include <string_view>

namespace rr {

inline void keep_options(RenderOptions&) {}  // an exact_mode: exact as requested

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
  // options.antialias > 1 resolves its sub-samples through the A-buffer (docs/antialiasing.md); off
  // for the reference, which casts a ray per sub-sample and has goldens of its own.
  bool abuffer = true;
  // Sets the options under which its visibility is exact: every pixel off the reference's id edges
  // shows the reference's polygon (the stress suites hold it to that). Null: never exact.
  void (*exact_mode)(RenderOptions& options) = keep_options;
  bool reference = false;  // the exact ray caster every other row is measured against
};

NameTable<PipelineInfo> pipeline_table();  // row 0 is the default pipeline
const PipelineInfo* find_pipeline(std::string_view name);
const PipelineInfo& pipeline_info(PipelineId id);
PipelineId pipeline_id(const PipelineInfo& row);  // row: a row of pipeline_table()
// For code that names a pipeline (tests, benches): throws std::invalid_argument for an unknown name.
PipelineId pipeline_id(std::string_view name);

}  // namespace rr

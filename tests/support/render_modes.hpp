// Every render mode of one request, for tests that hold a property across all of them: each
// pipeline (the reference one optionally), each shading and shadows off and on; and the rows of the
// pipeline table whose visibility is exact, with the options that make them so.
#pragma once

#include "render/core/scene_names.hpp"
#include "render/pipelines/pipeline_table.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rr::testing {

// Calls fn(request, label) with `request`'s options set to each shading, shadows off and on; label
// names the mode (" phong shadows") for a SCOPED_TRACE.
template <class Fn>
void for_each_shading_mode(nlohmann::json request, Fn&& fn) {
  for (const auto& shading : shading_names) {
    for (bool shadows : {false, true}) {
      request["options"]["shading"] = shading.name;
      request["options"]["shadows"] = shadows;
      std::string label = " ";
      label += shading.name;
      if (shadows) label += " shadows";
      fn(const_cast<const nlohmann::json&>(request), label);
    }
  }
}

// The same through each pipeline too (the reference one when `with_reference`); the label starts
// with the pipeline (" zbuffer phong shadows").
template <class Fn>
void for_each_render_mode(nlohmann::json request, bool with_reference, Fn&& fn) {
  for (const PipelineInfo& pipeline : pipeline_table()) {
    if (!with_reference && pipeline.reference) continue;
    request["options"]["pipeline"] = pipeline.name;
    for_each_shading_mode(request, [&](const nlohmann::json& mode, const std::string& label) {
      std::string full = " ";
      full += pipeline.name;
      full += label;
      fn(mode, full);
    });
  }
}

// The pipelines whose visibility is exact (PipelineInfo::exact_mode), in table order: drawn with
// exact_options, each shows the reference's polygon at every pixel off the reference's id edges. The
// reference itself is among them unless `with_reference` is false.
inline std::vector<const PipelineInfo*> exact_pipelines(bool with_reference = true) {
  std::vector<const PipelineInfo*> rows;
  for (const PipelineInfo& p : pipeline_table()) {
    if (p.exact_mode && (with_reference || !p.reference)) rows.push_back(&p);
  }
  return rows;
}

// `options` set to draw with `pipeline` (a row of pipeline_table()) in its exact mode.
inline RenderOptions exact_options(const PipelineInfo& pipeline, RenderOptions options) {
  options.pipeline = pipeline_id(pipeline);
  pipeline.exact_mode(options);
  return options;
}

}  // namespace rr::testing

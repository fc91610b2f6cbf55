// The pipeline table. Adding a pipeline is its own file (a PipelineFn) plus one row here; the schema's
// enum of pipeline names is held to this table by tests/unit/test_schema_tables.cpp.
#include "render/pipelines/pipeline_table.hpp"

#include "render/pipelines/bsp.hpp"
#include "render/pipelines/painter.hpp"
#include "render/pipelines/reference.hpp"
#include "render/pipelines/zbuffer.hpp"

#include <array>
#include <cassert>
#include <limits>
#include <stdexcept>
#include <string>

namespace rr {

namespace {
void newell_order(RenderOptions& options) { options.painter_key = PainterKey::newell; }

constexpr auto pipelines = std::to_array<PipelineInfo>({
    {.name = "zbuffer",
     .summary = "Rasterization with a depth buffer (1/w, float); translucent polygons blended back to front.",
     .draw = draw_zbuffer,
     .culls_objects = true,
     .occlusion_culling = true},
    {.name = "painter",
     .summary = "Painter's algorithm: polygons sorted back to front by view depth (painter.key mean, min or max), "
                "or ordered exactly by the Newell-Newell-Sancha tests with splitting (newell); no depth buffer.",
     .draw = draw_painter,
     .culls_objects = true,
     .exact_mode = newell_order},  // a depth-sorted order is not exact: intersecting polygons need splitting
    {.name = "bsp",
     .summary = "A BSP tree of the static scene (built once, cached by scene id), walked front to back with a "
                "coverage buffer that skips hidden subtrees (bsp.traversal back_to_front: the classic "
                "back-to-front walk), with frustum and back-face culling; no depth buffer.",
     .draw = draw_bsp,
     .occlusion_culling = true},
    {.name = "reference",
     .summary = "Exact reference: one double-precision ray per pixel centre through a BVH, per-pixel lighting "
                "with exact shadow rays; the ground truth the others are measured against (slow).",
     .draw = draw_reference,
     .shadow_maps = false,
     .abuffer = false,
     .reference = true},
});
static_assert(pipelines.size() <= std::numeric_limits<decltype(PipelineId::index)>::max() + 1);
}  // namespace

NameTable<PipelineInfo> pipeline_table() { return pipelines; }

const PipelineInfo* find_pipeline(std::string_view name) { return pipeline_table().find(name); }

const PipelineInfo& pipeline_info(PipelineId id) {
  assert(id.index < pipelines.size() && "a PipelineId comes from the table");
  return pipelines[id.index];
}

PipelineId pipeline_id(const PipelineInfo& row) {
  assert(&row >= pipelines.data() && &row < pipelines.data() + pipelines.size());
  return PipelineId{decltype(PipelineId::index)(&row - pipelines.data())};
}

PipelineId pipeline_id(std::string_view name) {
  const PipelineInfo* row = find_pipeline(name);
  if (!row) throw std::invalid_argument("unknown pipeline \"" + std::string(name) + "\"");
  return pipeline_id(*row);
}

}  // namespace rr

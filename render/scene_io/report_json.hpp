// The render report at the boundary: RenderReport (typed timings and counts) -> the JSON object the
// CLI prints as its line and the service answers with (before adding its own members), and the
// placement warnings as answers list them. The timings
// follow stage_table (render/core/frame.hpp), so every writer names the same stages in one order.
#pragma once

#include "render/pipelines/render.hpp"

#include <nlohmann/json.hpp>

namespace rr {

// {"timings_ms": {stage: ms, ...}, "counts": {...}, "shadow", "shadow_cache", and "painter" / "bsp"
// when those pipelines reported}. Milliseconds are rounded to the microsecond.
nlohmann::ordered_json report_json(const RenderReport& report);

// Only the timings_ms object of report_json.
nlohmann::ordered_json timings_json(const StageTimings& timings);

// Placement warnings as answers list them: [{"pointer", "detail", "depth"[, "other"]}], deepest
// first, pointers into the document that holds the scene (element_pointer.hpp).
nlohmann::json warnings_json(const std::vector<PlacementWarning>& warnings, const Scene& scene,
                             std::string_view scene_pointer);

}  // namespace rr

// The accuracy benchmark's error measures of one frame against the reference pipeline's frame of the
// same scene, camera and options, as one JSON object. A thin adapter over render/core/error_metrics.hpp
// (the measures themselves live there; nothing is computed here). With textured polygons in `soup`,
// also the texture error (texture_pixels, texture_rmse, texture_psnr_db).
#pragma once

#include "render/pipelines/pipeline.hpp"

#include <nlohmann/json.hpp>

namespace rr::bench {

nlohmann::ordered_json measure_errors(const Frame& reference, const Frame& frame, const PolygonSoup& soup);

}  // namespace rr::bench

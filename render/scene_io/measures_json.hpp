// Error measures (render/core/error_metrics.hpp) as the JSON object `roomrender compare` prints and
// the accuracy benchmark records: visibility for id buffers, shading for images, shadow for masks.
#pragma once

#include "render/core/error_metrics.hpp"

#include <nlohmann/json.hpp>

namespace rr {

// One JSON object: {"width", "height", "visibility": {pixels, differing, error, non_edge_pixels,
// non_edge_differing, non_edge_error}, "shading": {rmse, psnr_db (null when infinite)},
// "shadow": {pixels, differing, error}}, each part only when measured.
nlohmann::ordered_json error_measures_json(const ErrorMeasures& measures);

}  // namespace rr

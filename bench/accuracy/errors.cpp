// The error measures of one frame against the reference's (errors.hpp), from render/error_metrics.
#include "bench/accuracy/errors.hpp"

#include "render/core/error_metrics.hpp"

#include <algorithm>
#include <cmath>

namespace rr::bench {

nlohmann::ordered_json measure_errors(const Frame& reference, const Frame& frame, const PolygonSoup& soup) {
  const ErrorMeasures m = compare_frames(reference, frame);
  nlohmann::ordered_json j = {{"visibility_all", nullptr},
                              {"visibility_non_edge", nullptr},
                              {"rmse", nullptr},
                              {"psnr_db", nullptr},
                              {"shadow_disagreement", nullptr},
                              {"shadow_disagreement_band", nullptr},
                              {"shadow_disagreement_away", nullptr}};
  if (m.visibility) {
    j["visibility_all"] = m.visibility->share();
    j["visibility_non_edge"] = m.visibility->non_edge_share();
  }
  if (m.shading) {
    j["rmse"] = m.shading->rmse;
    // JSON has no infinity: identical images (RMSE 0) get a null PSNR, which the report prints "inf".
    if (std::isfinite(m.shading->psnr_db)) j["psnr_db"] = m.shading->psnr_db;
  }
  if (m.shadow) j["shadow_disagreement"] = m.shadow->share();
  if (m.shadow && m.shadow->split) {  // within shadow_edge_band pixels of the reference's shadow edges, and away
    j["shadow_disagreement_band"] = m.shadow->band_share();
    j["shadow_disagreement_away"] = m.shadow->away_share();
    // The pixel counts behind the two shares: a few pixels away from the edges is a share near 0.
    j["shadow_band_pixels"] = m.shadow->band_pixels;
    j["shadow_band_differing"] = m.shadow->band_differing;
    j["shadow_away_pixels"] = m.shadow->away_pixels;
    j["shadow_away_differing"] = m.shadow->away_differing;
  }
  const std::vector<uint8_t> textured = textured_polygons(soup);
  if (std::find(textured.begin(), textured.end(), 1) != textured.end()) {
    const TexturedPixelError t = texture_error(reference.ids, textured, reference.image, frame.image, &frame.ids);
    j["texture_pixels"] = t.pixels;
    j["texture_rmse"] = t.rmse;
    j["texture_psnr_db"] = std::isfinite(t.psnr_db) ? nlohmann::ordered_json(t.psnr_db) : nullptr;
  }
  return j;
}

}  // namespace rr::bench

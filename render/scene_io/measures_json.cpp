// Error measures as JSON (see measures_json.hpp).
#include "render/scene_io/measures_json.hpp"

#include <cmath>

namespace rr {

nlohmann::ordered_json error_measures_json(const ErrorMeasures& m) {
  nlohmann::ordered_json j;
  j["width"] = m.width;
  j["height"] = m.height;
  if (m.visibility) {
    const VisibilityError& v = *m.visibility;
    j["visibility"] = {{"pixels", v.pixels},
                       {"differing", v.differing},
                       {"error", v.share()},
                       {"non_edge_pixels", v.non_edge_pixels},
                       {"non_edge_differing", v.non_edge_differing},
                       {"non_edge_error", v.non_edge_share()}};
  }
  if (m.shading) {
    nlohmann::ordered_json s = {{"rmse", m.shading->rmse}, {"psnr_db", nullptr}};
    if (std::isfinite(m.shading->psnr_db)) s["psnr_db"] = m.shading->psnr_db;
    j["shading"] = s;
  }
  if (m.shadow) {
    const ShadowError& e = *m.shadow;
    nlohmann::ordered_json s = {{"pixels", e.pixels}, {"differing", e.differing}, {"error", e.share()}};
    if (e.split) {
      s["band_pixels"] = e.band_pixels, s["band_differing"] = e.band_differing, s["band_error"] = e.band_share();
      s["away_pixels"] = e.away_pixels, s["away_differing"] = e.away_differing, s["away_error"] = e.away_share();
    }
    j["shadow"] = s;
  }
  return j;
}

}  // namespace rr

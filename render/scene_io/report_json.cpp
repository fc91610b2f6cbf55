// report_json (see report_json.hpp): the one writer of a render's timings and counts as JSON.
#include "render/scene_io/report_json.hpp"

#include "render/scene_io/element_pointer.hpp"

#include <cmath>

namespace rr {

nlohmann::ordered_json timings_json(const StageTimings& t) {
  auto ms = [](double v) { return std::round(v * 1000.0) / 1000.0; };  // microsecond resolution
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const StageField& stage : stage_table) j[stage.name] = ms(t.*stage.ms);
  return j;
}

nlohmann::ordered_json report_json(const RenderReport& report) {
  const RenderStats& s = report.stats;
  nlohmann::ordered_json j;
  j["timings_ms"] = timings_json(report.timings);
  j["counts"] = {{"polygons", s.polygons},
                 {"polygons_culled", s.polygons_culled},
                 {"polygons_drawn", s.polygons_drawn},
                 {"triangles", s.triangles},
                 {"fragments", s.fragments},
                 {"lights_evaluated", s.lights_evaluated},
                 {"shadow_passes", s.shadow_passes},
                 {"objects_culled", s.objects_culled},
                 {"objects_occluded", s.objects_occluded},
                 {"nodes_tested", s.nodes_tested},
                 {"polygons_projected", s.polygons_projected},
                 {"cells", s.cells},
                 {"cells_visited", s.cells_visited},
                 {"portals_walked", s.portals_walked},
                 {"lamps_culled", s.lamps_culled},
                 {"lamps_blocked", s.lamps_blocked}};
  j["shadow"] = s.shadow_skipped ? "skipped" : "rendered";
  j["shadow_cache"] = s.shadow_cache;
  j["exposure"] = report.exposure;
  if (s.painter_pairs_tested || s.painter_splits || s.painter_budget_exhausted) {
    j["painter"] = {{"pairs_tested", s.painter_pairs_tested},
                    {"splits", s.painter_splits},
                    {"budget_exhausted", s.painter_budget_exhausted}};
  }
  if (!s.bsp_cache.empty()) {
    j["bsp"] = {{"cache", s.bsp_cache},
                {"nodes", s.bsp_nodes},
                {"depth", s.bsp_depth},
                {"input_polygons", s.bsp_input_polygons},
                {"fragments", s.bsp_fragments},
                {"splits", s.bsp_splits},
                {"subtrees_occluded", s.bsp_subtrees_occluded},
                {"polygons_occluded", s.bsp_polygons_occluded},
                {"screen_full", s.bsp_screen_full}};
  }
  return j;
}

nlohmann::json warnings_json(const std::vector<PlacementWarning>& warnings, const Scene& scene,
                             std::string_view scene_pointer) {
  nlohmann::json list = nlohmann::json::array();
  for (const WarningText& w : describe(warnings, scene, scene_pointer)) {
    nlohmann::json item = {{"pointer", w.pointer}, {"detail", w.detail}, {"depth", std::round(w.depth_m * 1e6) / 1e6}};
    if (!w.other.empty()) item["other"] = w.other;
    list.push_back(std::move(item));
  }
  return list;
}

}  // namespace rr

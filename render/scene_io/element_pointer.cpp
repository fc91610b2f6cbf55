// Element references and placement warnings as text (see element_pointer.hpp).
#include "render/scene_io/element_pointer.hpp"

#include "render/scene_io/json_reader.hpp"  // format_number

namespace rr {

namespace {

// The element's pointer followed by its id, when it has one: /scene/solids/2 ("sofa").
std::string label(ElementRef element, const Scene& scene, std::string_view scene_pointer) {
  const std::string pointer = element_pointer(element, scene_pointer);
  const StaticGeometry& g = scene.geometry;
  const std::string* id = nullptr;
  if (element.kind == ElementKind::wall && element.index < g.walls.size()) id = &g.walls[element.index].id;
  if (element.kind == ElementKind::solid && element.index < g.solids.size()) id = &g.solids[element.index].id;
  return !id || id->empty() ? pointer : pointer + " (\"" + quote_input(*id) + "\")";
}

// "piece" for a piece of furniture, "solid" for the other solids.
std::string solid_noun(ElementRef element, const Scene& scene) {
  const std::vector<Solid>& solids = scene.geometry.solids;
  const bool piece = element.kind == ElementKind::solid && element.index < solids.size() &&
                     solids[element.index].type == SolidType::piece;
  return piece ? "piece" : "solid";
}

}  // namespace

std::string element_pointer(ElementRef element, std::string_view scene_pointer) {
  std::string out(scene_pointer);
  switch (element.kind) {
    case ElementKind::scene:
      break;
    case ElementKind::floor:
      out += "/floor";
      break;
    case ElementKind::wall:
      out += "/walls/" + std::to_string(element.index);
      break;
    case ElementKind::opening:
      out += "/walls/" + std::to_string(element.index) + "/openings/" + std::to_string(element.opening);
      break;
    case ElementKind::solid:
      out += "/solids/" + std::to_string(element.index);
      break;
    case ElementKind::room:
      out += "/rooms/" + std::to_string(element.index);
      break;
  }
  return out;
}

WarningText describe(const PlacementWarning& w, const Scene& scene, std::string_view scene_pointer) {
  const std::string distance = format_number(w.distance_m) + " m";
  const std::string under = " (less than " + format_number(w.limit_m) + " m)";
  std::string detail;
  switch (w.issue) {
    case PlacementIssue::opening_near_start:
      detail = "opening is " + distance + " from its wall's start" + under;
      break;
    case PlacementIssue::opening_near_end:
      detail = "opening is " + distance + " from its wall's end" + under;
      break;
    case PlacementIssue::openings_too_close:
      detail = "opening is " + distance + " from opening " + element_pointer(w.other, scene_pointer) + under;
      break;
    case PlacementIssue::beyond_floor:
      detail = solid_noun(w.element, scene) + " reaches " + distance + " beyond the floor's edge";
      break;
    case PlacementIssue::intersects:
      detail = solid_noun(w.element, scene) + " intersects " +
               (w.other.kind == ElementKind::wall ? "wall " : solid_noun(w.other, scene) + " ") +
               label(w.other, scene, scene_pointer) + " by " + format_number(w.depth_m) + " m";
      break;
    case PlacementIssue::more_problems:
    case PlacementIssue::stopped_early:
      detail = "placement checks " +
               std::string(w.issue == PlacementIssue::stopped_early ? "stopped early (too many overlapping pairs)"
                                                                    : "found more problems") +
               "; " + std::to_string(w.count) + " further warning(s) not listed";
      break;
  }
  const bool pair = w.issue == PlacementIssue::intersects || w.issue == PlacementIssue::openings_too_close;
  return {element_pointer(w.element, scene_pointer), detail, pair ? element_pointer(w.other, scene_pointer) : "",
          w.depth_m};
}

std::vector<WarningText> describe(const std::vector<PlacementWarning>& warnings, const Scene& scene,
                                  std::string_view scene_pointer) {
  std::vector<WarningText> out;
  out.reserve(warnings.size());
  for (const PlacementWarning& w : warnings) out.push_back(describe(w, scene, scene_pointer));
  return out;
}

}  // namespace rr

// Runtime element references and placement warnings as a client reads them: JSON Pointers into the
// document that holds the scene ("/scene" in a render request, "" in a stored scene document) and
// the warnings' messages. The one place where runtime data turns into pointer text.
#pragma once

#include "render/core/element.hpp"
#include "render/core/placement.hpp"
#include "render/core/scene.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace rr {

// "/scene/walls/3/openings/1" for opening 1 of wall 3 under scene_pointer "/scene".
std::string element_pointer(ElementRef element, std::string_view scene_pointer = "/scene");

struct WarningText {
  std::string pointer;
  std::string detail;
  std::string other;   // the other element of a pair; empty when there is none
  double depth_m = 0;  // PlacementWarning::depth_m, its severity
};

WarningText describe(const PlacementWarning& warning, const Scene& scene, std::string_view scene_pointer = "/scene");
std::vector<WarningText> describe(const std::vector<PlacementWarning>& warnings, const Scene& scene,
                                  std::string_view scene_pointer = "/scene");

}  // namespace rr

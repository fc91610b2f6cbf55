// Which of a scene's polygons one view draws: those on the levels it selects (or the viewable ones)
// and the ceilings its ceiling mode keeps. In: the scene, its soup, the camera and options. Out: a
// keep flag per soup object and, when something is left out, a soup of the kept polygons with their
// ids unchanged and a cache-key suffix naming the selection. Nothing left out: no copy, no suffix.
#pragma once

#include "render/core/scene.hpp"
#include "render/core/tessellate.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rr {

struct SoupSelection {
  bool everything = true;     // no object is left out: draw the soup as it is
  std::vector<uint8_t> keep;  // per soup object (empty when everything)
  std::string key_suffix;     // appended to the scene id of every cache key (empty when everything)
};

SoupSelection select_objects(const StaticGeometry& geometry, const PolygonSoup& soup, const Camera& camera,
                             const RenderOptions& options);

// The polygons of the kept objects, in soup order, keeping their ids, materials and objects.
PolygonSoup selected_soup(const PolygonSoup& soup, const SoupSelection& selection);

}  // namespace rr

// Which of a scene's polygons one view draws: those on the levels it selects (or the viewable ones)
// and the ceilings its ceiling mode keeps. In: the scene, its soup, the camera and options. Out: a
// keep flag per soup object and, when something is left out, a soup of the kept polygons with their
// ids unchanged and a cache-key suffix naming the selection. Nothing left out: no copy, no suffix.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/scene.hpp"
#include "render/core/shadow_rays.hpp"
#include "render/core/tessellate.hpp"

#include <cstdint>
#include <memory>
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

// A selection's soup as a frame draws it, made once and shared by every view making the same
// selection of the same static scene (a ViewCache entry), with its shadow rays' tree when one was
// wanted. A function of the scene and the selection alone, so a frame draws the same bytes from a
// cached view as from one made for it.
struct SelectedView {
  std::shared_ptr<const PolygonSoup> soup;
  std::shared_ptr<const ShadowBvh> shadow_bvh;  // null: made without one
  bool panes = false;                           // the soup holds translucent polygons
  size_t bytes() const;                         // what it costs against a cache budget
};

// Whether a frame wants its view's shadow-ray tree: not at all, always (shadow rays), or when the
// soup holds panes (shadow maps, whose light through panes the panes' tree tints).
enum class ViewTree { none, always, with_panes };

// The view of `soup` that `selection` makes (not everything), from `cache` under `key` (the scene's
// static id with the selection's suffix) when given, else made now; holding the shadow rays' tree
// when `tree` asks for it, whose build time, when it ran, is added to `tree_ms`.
std::shared_ptr<const SelectedView> selected_view(const PolygonSoup& soup, const SoupSelection& selection,
                                                  const std::string& key, ViewTree tree, ViewCache* cache,
                                                  const CancelToken* cancel, double& tree_ms);

}  // namespace rr

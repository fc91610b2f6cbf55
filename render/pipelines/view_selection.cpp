// select_objects and selected_soup (see view_selection.hpp). Objects keep their indices in the
// filtered soup, so per-object data (frustum culling, smooth normals) needs no remapping; polygons
// keep their ids, so id buffers compare across selections.
#include "render/pipelines/view_selection.hpp"

#include "render/core/hash.hpp"
#include "render/core/hierarchy.hpp"
#include "render/core/timer.hpp"

#include <algorithm>

namespace rr {

namespace {

std::vector<uint8_t> drawn_levels(const std::vector<Level>& levels, const RenderOptions& options) {
  std::vector<uint8_t> drawn(levels.size(), 0);
  for (size_t i = 0; i < levels.size(); ++i) {
    if (!options.levels_given) {
      drawn[i] = levels[i].viewable;
      continue;
    }
    for (const std::string& id : options.levels) drawn[i] |= uint8_t(id == levels[i].id);
  }
  return drawn;
}

// auto: a ceiling is drawn for a camera below it; one above it looks into the room (an aerial view).
bool keeps_ceiling(const Room& room, const Camera& camera, CeilingMode mode) {
  switch (mode) {
    case CeilingMode::on:
      return true;
    case CeilingMode::off:
      return false;
    case CeilingMode::automatic:
      break;
  }
  return camera.position.y < room.elevation + room.ceiling_height;
}

}  // namespace

SoupSelection select_objects(const StaticGeometry& geometry, const PolygonSoup& soup, const Camera& camera,
                             const RenderOptions& options) {
  SoupSelection out;
  if (geometry.levels.empty() && geometry.rooms.empty()) return out;
  const std::vector<uint8_t> drawn = drawn_levels(geometry.levels, options);
  out.keep.assign(soup.objects.size(), 1);
  for (size_t i = 0; i < soup.objects.size(); ++i) {
    const SceneObject& o = soup.objects[i];
    bool keep = o.level < 0 || size_t(o.level) >= drawn.size() || drawn[size_t(o.level)];
    if (keep && o.ceiling) keep = keeps_ceiling(geometry.rooms[o.element.index], camera, options.ceilings);
    out.keep[i] = keep;
    out.everything = out.everything && keep;
  }
  if (out.everything) {
    out.keep.clear();
    return out;
  }
  Fnv1a h;
  h.add_bytes({reinterpret_cast<const char*>(out.keep.data()), out.keep.size()});
  out.key_suffix = "|objects " + hex64(h.value());
  return out;
}

PolygonSoup selected_soup(const PolygonSoup& soup, const SoupSelection& selection) {
  if (selection.everything) return soup;
  PolygonSoup out;
  out.materials = soup.materials;
  out.objects = soup.objects;
  out.uv_maps = soup.uv_maps;
  // At most the whole soup: one allocation each instead of repeated growth.
  out.polygons.reserve(soup.polygons.size());
  out.positions.reserve(soup.positions.size());
  out.normals.reserve(soup.normals.size());
  for (const Polygon& p : soup.polygons) {
    if (!selection.keep[p.object]) continue;
    Polygon q = p;
    q.first_vertex = uint32_t(out.positions.size());
    const auto points = soup.points(p);
    const auto normals = soup.vertex_normals(p);
    out.positions.insert(out.positions.end(), points.begin(), points.end());
    out.normals.insert(out.normals.end(), normals.begin(), normals.end());
    out.polygons.push_back(q);
  }
  return out;
}

size_t SelectedView::bytes() const {
  size_t out = sizeof(SelectedView);
  if (soup) out += sizeof(PolygonSoup) + soup_bytes(*soup);
  if (shadow_bvh) out += shadow_bvh->bytes();
  return out;
}

std::shared_ptr<const SelectedView> selected_view(const PolygonSoup& soup, const SoupSelection& selection,
                                                  const std::string& key, ViewTree tree, ViewCache* cache,
                                                  const CancelToken* cancel, double& tree_ms) {
  auto make = [&] {
    auto view = std::make_shared<SelectedView>();
    view->soup = std::make_shared<const PolygonSoup>(selected_soup(soup, selection));
    const auto& polygons = view->soup->polygons;
    view->panes = std::any_of(polygons.begin(), polygons.end(),
                              [](const Polygon& p) { return (p.flags & polygon_translucent) != 0; });
    return ViewCache::Built{view, view->bytes()};
  };
  // The same view with the tree of its soup: the soup is shared with `plain`, and counted again.
  auto with_tree = [&](const std::shared_ptr<const SelectedView>& plain) {
    auto view = std::make_shared<SelectedView>(*plain);
    Stopwatch clock;
    view->shadow_bvh =
        std::make_shared<const ShadowBvh>(build_shadow_bvh(*view->soup, build_hierarchy(*view->soup, cancel)));
    tree_ms += clock.elapsed_ms();
    return ViewCache::Built{view, view->bytes()};
  };
  bool hit = false;
  std::shared_ptr<const SelectedView> plain = cache ? cache->get_or_build(key, make, hit) : make().value;
  if (tree == ViewTree::none || (tree == ViewTree::with_panes && !plain->panes)) return plain;
  if (!cache) return with_tree(plain).value;
  return cache->get_or_build(
      key + "|rays", [&] { return with_tree(plain); }, hit);
}

}  // namespace rr

// The shadow cache's key and lookup (see shadow_cache.hpp).
#include "render/pipelines/shadow_cache.hpp"

#include "render/core/scene_id.hpp"

#include <cstdio>
#include <initializer_list>

namespace rr {

namespace {

// Hexadecimal floats: exact, so two keys are equal only when the pass would read equal numbers.
void append_numbers(std::string& key, std::initializer_list<double> values) {
  char buffer[40];
  for (double v : values) {
    std::snprintf(buffer, sizeof buffer, "|%a", v);
    key += buffer;
  }
}

}  // namespace

std::string shadow_cache_key(const std::string& scene_id, const Scene& scene, const ViewTransform& view,
                             const ShadowOptions& o) {
  std::string key = scene_id + "|shadow|" + (o.fit == ShadowFit::scene ? "scene" : "view");
  append_numbers(key, {double(o.size), double(o.pcf), o.bias, o.slope_bias});
  for (const Light& light : scene.lights) {
    // The pass only asks whether a light adds anything (a dark light gets no map), not how much.
    const bool on = light.intensity > 0.0f && light.color != Color(0.0f);
    const bool directional = light.type == LightType::directional;
    key += directional ? "|dir" : "|point";
    key += on ? "|on" : "|off";
    const Vec3 v = directional ? light.direction : light.position;
    append_numbers(key, {v.x, v.y, v.z});
  }
  if (o.fit == ShadowFit::view) {
    // collect_receivers reads only these of the view: the frustum and the eye.
    for (int c = 0; c < 4; ++c) {
      const Vec4& column = view.clip_from_world[c];
      append_numbers(key, {column.x, column.y, column.z, column.w});
    }
    append_numbers(key, {view.eye.x, view.eye.y, view.eye.z});
  }
  return key;
}

std::shared_ptr<const ShadowMaps> obtain_shadow_maps(const Scene& scene, const PolygonSoup& soup,
                                                     const ViewTransform& view, const RenderOptions& options,
                                                     const RenderContext& context, RenderStats& stats) {
  auto build = [&] {
    ++stats.shadow_passes;
    auto maps = std::make_shared<const ShadowMaps>(
        build_shadow_maps(scene, soup, view, options, context.cancel, context.threads));
    return ShadowCache::Built{maps, maps->bytes()};
  };
  if (!context.shadow_cache) {
    stats.shadow_cache = "miss";  // no cache to ask: this frame's own pass
    return build().value;
  }
  const std::string id = context.scene_id.empty() ? scene_id(scene.geometry) : context.scene_id;
  bool hit = false;
  auto maps = context.shadow_cache->get_or_build(shadow_cache_key(id, scene, view, options.shadow), build, hit);
  // A request that waited for another's build ran no pass itself, but found nothing ready: a miss.
  stats.shadow_cache = hit ? "hit" : "miss";
  return maps;
}

}  // namespace rr

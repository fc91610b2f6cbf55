// The accuracy benchmark's configurations (every pipeline and each relevant option) and the timed
// render of one scene under one of them. Times are wall-clock milliseconds of render_frame (parsing
// and tessellation excluded); the BSP tree is built once (build_ms) and the timed frames reuse it
// from a cache, as the service does for a stored scene.
#pragma once

#include "bench/accuracy/suite.hpp"
#include "render/pipelines/pipeline.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rr::bench {

struct BenchConfig {
  std::string label;      // e.g. "painter-newell", "bsp w=1/4/-1 eps=1e-7", "phong shadows 2048 pcf3"
  std::string group;      // "visibility" (flat, no shadows), "shading" (zbuffer, lights and shadows) or "texture"
  RenderOptions options;  // width and height are the scene's
  nlohmann::ordered_json options_json;  // the same options as the request's "options" would say them
};

// Every configuration. To keep the suite within its time budget on a shared 2-core machine, a scene
// of more than large_scene_polygons polygons gets two BSP settings instead of five (its trees take
// seconds to minutes to build), and a scene with more than many_lights lights (the Sweet Home 3D
// homes: 7-17 point lights, six shadow-map faces each) or a large one gets three shadow settings
// instead of eight. Every scene also gets Phong with exact shadow rays (`shadow.method` rays).
constexpr size_t large_scene_polygons = 100'000;
constexpr size_t many_lights = 4;
inline bool is_large(const BenchScene& s) { return s.prepared.soup.polygons.size() > large_scene_polygons; }
inline bool has_few_shadow_settings(const BenchScene& s) {
  return is_large(s) || s.prepared.scene.lights.size() > many_lights;
}
// A scene of the "textures" class gets one configuration per texture filter instead (zbuffer, Phong,
// no shadows: group "texture"): its visibility and lighting are measured on its untextured twin.
std::vector<BenchConfig> make_configs(const BenchScene& scene);

struct TimedRender {
  std::string status = "ok";  // "ok" or "timeout" (the config's deadline passed: no frame)
  int frames = 0;             // timed frames (after one untimed warm-up frame)
  double frame_ms_median = 0.0;
  double build_ms = 0.0;                   // BSP tree build, measured on the warm-up frame (a cache miss)
  nlohmann::ordered_json stage_ms_median;  // sort / traverse / shadow / raster / shade / total
  RenderResult last;                       // the warm-up frame, with its shadow mask (for the error measures)
};

// Renders `scene` with `options` (size from the scene): one warm-up frame, then up to `max_frames`
// timed frames (fewer for slow frames: 3 above 250 ms, 1 above 1 s). Stops at `timeout_s` seconds.
TimedRender time_render(const BenchScene& scene, const std::string& scene_id, const RenderOptions& options,
                        int max_frames, double timeout_s);

}  // namespace rr::bench

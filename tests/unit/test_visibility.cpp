// The tiled visibility buffer (zbuffer pipeline) against the reference it replaced: every polygon
// drawn fragment by fragment through draw_projected with a frame-wide depth test (opaque in index
// order, then translucent far to near), shading every fragment that passes. On every example x
// shading x shadows off/on the ids must agree, and the colours wherever the ids agree, bit for bit.
// The one allowed difference: pass 1 steps 1/w along a span instead of recomputing it per pixel,
// so where two surfaces are within a float rounding of each other the other one may win; that is
// bounded by 1 pixel in 10,000.
#include "render/core/draw.hpp"
#include "render/core/hierarchy.hpp"
#include "render/core/scene_names.hpp"
#include "render/core/shading.hpp"
#include "render/core/shadow.hpp"
#include "render/core/shadow_rays.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace rr {
namespace {

Frame draw_reference(const RenderRequest& req, const PolygonSoup& soup) {
  const int w = req.options.width, h = req.options.height;
  const ViewTransform view = make_view(req.camera, w, h);
  ShadowMaps maps;
  if (req.options.shadows && !req.scene.lights.empty()) maps = build_shadow_maps(req.scene, soup, view, req.options);
  RenderContext context;
  FrameInput input{req.scene, soup, view, req.options, context, maps.empty() ? nullptr : &maps};
  // As render_frame: with maps, the panes' tree tints the light they let through.
  ShadowBvh panes;
  if (!maps.empty()) {
    panes = build_shadow_bvh(soup, build_hierarchy(soup));
    input.glass_rays = &panes;
  }
  Frame frame{Image(w, h, req.scene.background), IdBuffer(w, h)};
  std::vector<float> depth(size_t(w) * size_t(h), 0.0f);
  FrameTarget target{frame.image, frame.ids, &depth, {0, 0, w, h}};
  SurfaceShader shader(input, soup);
  std::vector<uint32_t> opaque;
  std::vector<std::pair<double, uint32_t>> translucent;
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
    const Polygon& poly = soup.polygons[i];
    if (is_back_facing(poly, view.eye)) continue;
    shader.prepare(i);
    if (!(poly.flags & polygon_translucent)) {
      opaque.push_back(i);
      continue;
    }
    double d = 0.0;
    for (const Vec3& p : soup.points(poly)) d += -(view.view_from_world * Vec4(p, 1.0)).z;
    translucent.push_back({d / double(poly.vertex_count), i});
  }
  std::sort(translucent.begin(), translucent.end(), std::greater<>());
  DrawScratch scratch;
  auto draw = [&](uint32_t i, DepthMode mode) {
    const Polygon& poly = soup.polygons[i];
    if (!project_polygon(view, soup, poly, scratch)) return;
    shader.bind(i, scratch);
    const float alpha = mode == DepthMode::test_only ? soup.materials[poly.material].opacity : 1.0f;
    draw_projected(target, scratch, poly.id, alpha, mode,
                   [&](const Fragment& f, size_t k) { return shader.fragment(f, k); });
  };
  for (uint32_t i : opaque) draw(i, DepthMode::test_and_write);
  for (const auto& [d, i] : translucent) draw(i, DepthMode::test_only);
  return frame;
}

TEST(Visibility, MatchesPerFragmentZBufferingOnEveryExampleAndMode) {
  size_t compared = 0;
  for (const auto& file : testing::example_files()) {
    nlohmann::json j = nlohmann::json::parse(testing::read_file(file));
    j["options"]["width"] = 300;
    j["options"]["height"] = 200;
    j["options"]["pipeline"] = "zbuffer";
    for (const auto& shading : shading_names) {
      for (bool shadows : {false, true}) {
        j["options"]["shading"] = shading.name;
        j["options"]["shadows"] = shadows;
        SCOPED_TRACE(file.filename().string() + " " + shading.name + (shadows ? " shadows" : ""));
        const RenderRequest req = request_from_json(j);
        const PolygonSoup soup = tessellate(req.scene.geometry);
        const Frame reference = draw_reference(req, soup);
        RenderContext context;
        context.threads = 2;
        const RenderResult tiled = render_frame(req.scene, soup, req.camera, req.options, context);
        size_t id_differs = 0, colour_differs = 0;
        for (size_t i = 0; i < reference.ids.ids.size(); ++i) {
          if (reference.ids.ids[i] != tiled.frame.ids.ids[i]) {
            ++id_differs;
            continue;
          }
          for (size_t c = 0; c < 3; ++c)
            colour_differs += reference.image.rgb[i * 3 + c] != tiled.frame.image.rgb[i * 3 + c];
        }
        EXPECT_LE(id_differs, reference.ids.ids.size() / 10000);
        EXPECT_EQ(colour_differs, 0u);
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 0u);
}

}  // namespace
}  // namespace rr

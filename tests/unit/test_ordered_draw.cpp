// The tiled in-order drawer of the painter and bsp pipelines (render/pipelines/ordered_draw.hpp)
// against the single-threaded whole-frame draw it replaces, kept here as the reference: each
// polygon of the same order projected and drawn over the whole frame with draw_projected
// (DepthMode::none, last writer wins). Image, ids, shadow mask, fragment and light-evaluation counts
// must be identical for 1, 2 and 5 threads, on every example and on seeded random scenes with
// translucent panes, every shading, shadows off and on, at sizes that leave partial tiles. The bsp
// front-to-back walk (first writer wins) must leave the same image, ids and mask.
#include "render/core/frustum.hpp"
#include "render/core/shading.hpp"
#include "render/pipelines/bsp.hpp"
#include "render/pipelines/painter.hpp"
#include "render/pipelines/shadow_cache.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/render_modes.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <random>

namespace rr {
namespace {

using json = nlohmann::json;

struct Drawn {
  Frame frame;
  RenderStats stats;
};

// One frame's inputs, set up as render_frame sets them up.
struct Setup {
  RenderRequest request;
  PolygonSoup soup;
  ViewTransform view;
  std::shared_ptr<const ShadowMaps> shadows;
  ObjectsInView objects;

  explicit Setup(const json& j) : request(request_from_json(j)), soup(tessellate(request.scene.geometry)) {
    view = make_view(request.camera, request.options.width, request.options.height);
    RenderContext context;
    RenderStats stats;
    if (request.options.shadows && !request.scene.lights.empty()) {
      shadows = obtain_shadow_maps(request.scene, soup, view, request.options, context, stats);
    }
    objects = objects_in_view(soup, view);
  }

  // Draws with `fn(input, frame, stats)` on `threads` threads, the shadow mask on.
  template <class Fn>
  Drawn draw(unsigned threads, bool cull_objects, Fn&& fn) const {
    RenderContext context;
    context.threads = threads;
    Drawn d;
    d.frame.image = Image(view.width, view.height, request.scene.background);
    d.frame.ids = IdBuffer(view.width, view.height);
    d.frame.shadow_mask.assign(d.frame.ids.ids.size(), 0);
    FrameInput input{request.scene, soup, view, request.options, context};
    if (shadows && !shadows->empty()) input.shadows = shadows.get();
    if (cull_objects) input.objects_in_view = &objects.visible;
    input.lights_evaluated = &d.stats.lights_evaluated;
    input.shadow_mask = d.frame.shadow_mask.data();
    fn(input, d.frame, d.stats);
    return d;
  }
};

// The reference: polygon items[k] of sources[k] drawn in order over the whole frame.
void draw_whole_frame(const FrameInput& input, const std::vector<const PolygonSoup*>& soups,
                      const std::vector<std::pair<uint32_t, size_t>>& items, Frame& frame, RenderStats& stats) {
  std::vector<std::unique_ptr<SurfaceShader>> shaders;
  for (const PolygonSoup* soup : soups) shaders.push_back(std::make_unique<SurfaceShader>(input, *soup));
  for (const auto& [index, source] : items) shaders[source]->prepare(index);
  FrameTarget target{frame.image, frame.ids, nullptr, {0, 0, frame.image.width, frame.image.height}};
  DrawScratch scratch;
  for (const auto& [index, source] : items) {
    const PolygonSoup& soup = *soups[source];
    const Polygon& poly = soup.polygons[index];
    if (!project_polygon(input.view, soup, poly, scratch)) continue;
    SurfaceShader& shader = *shaders[source];
    shader.bind(index, scratch);
    const float alpha = poly.flags & polygon_translucent ? soup.materials[poly.material].opacity : 1.0f;
    stats.fragments += draw_projected(target, scratch, poly.id, alpha, DepthMode::none,
                                      [&](const Fragment& f, size_t k) { return shader.fragment(f, k); });
  }
}

// `counts`: the same fragments and light evaluations too (not for the front-to-back walk, which
// skips hidden polygons and so draws fewer). Phong evaluates its lights per shaded pixel, and the
// tiles shade a pixel only for the writes that last, so there it may evaluate fewer.
void expect_same(const Drawn& tiled, const Drawn& reference, unsigned threads, bool phong, bool counts = true) {
  SCOPED_TRACE(std::to_string(threads) + " threads");
  EXPECT_TRUE(tiled.frame.image.rgb == reference.frame.image.rgb) << "the image differs";
  EXPECT_TRUE(tiled.frame.ids.ids == reference.frame.ids.ids) << "the ids differ";
  EXPECT_TRUE(tiled.frame.shadow_mask == reference.frame.shadow_mask) << "the shadow mask differs";
  if (!counts) return;
  EXPECT_EQ(tiled.stats.fragments, reference.stats.fragments);
  if (phong) {
    EXPECT_LE(tiled.stats.lights_evaluated, reference.stats.lights_evaluated);
  } else {
    EXPECT_EQ(tiled.stats.lights_evaluated, reference.stats.lights_evaluated);
  }
}

void check_painter(const json& request) {
  const Setup setup(request);
  const bool phong = setup.request.options.shading == ShadingMode::phong;
  const Drawn reference = setup.draw(1, true, [&](const FrameInput& input, Frame& frame, RenderStats& stats) {
    const PainterOrder order = painter_order(input, input.options.painter_key);
    std::vector<std::pair<uint32_t, size_t>> items;
    for (const PainterItem& it : order.items) items.push_back({it.index, it.fragment ? 1 : 0});
    draw_whole_frame(input, {&input.soup, &order.fragments}, items, frame, stats);
  });
  for (unsigned threads : {1u, 2u, 5u}) {
    expect_same(setup.draw(threads, true,
                           [](const FrameInput& input, Frame& frame, RenderStats& stats) {
                             StageTimings timings;
                             draw_painter(input, frame, stats, timings);
                           }),
                reference, threads, phong);
  }
}

// Both walks of the bsp pipeline against the back-to-front order drawn over the whole frame.
void check_bsp(json request) {
  request["options"]["bsp"]["traversal"] = "back_to_front";
  Setup setup(request);
  const bool phong = setup.request.options.shading == ShadingMode::phong;
  const BspTree tree = build_bsp(setup.soup, setup.request.options.bsp);
  const Drawn reference = setup.draw(1, false, [&](const FrameInput& input, Frame& frame, RenderStats& stats) {
    size_t culled = 0;
    std::vector<std::pair<uint32_t, size_t>> items;
    for (uint32_t index : bsp_back_to_front(tree, input.view, culled)) items.push_back({index, 0});
    draw_whole_frame(input, {&tree.fragments}, items, frame, stats);
  });
  auto draw = [](const FrameInput& input, Frame& frame, RenderStats& stats) {
    StageTimings timings;
    draw_bsp(input, frame, stats, timings);
  };
  for (unsigned threads : {1u, 2u, 5u}) expect_same(setup.draw(threads, false, draw), reference, threads, phong);
  setup.request.options.bsp.traversal = BspTraversal::front_to_back;
  for (unsigned threads : {1u, 2u, 5u}) expect_same(setup.draw(threads, false, draw), reference, threads, phong, false);
}

// Random triangles through each other, a box, and a wall with a translucent window among them.
json random_scene(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), opacity(0.2, 0.8);
  json vertices = json::array(), faces = json::array();
  for (int t = 0; t < 30; ++t) {
    for (int k = 0; k < 3; ++k) vertices.push_back({1.5 * u(rng), u(rng) + 1.0, 2.0 * u(rng) + 0.5});
    faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  json solids = json::array({{{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}}});
  solids.push_back({{"type", "box"}, {"center", {u(rng), u(rng)}}, {"size", {0.5, 0.8, 0.4}}});
  json window = {{"type", "window"}, {"offset", 0.5 + 0.5 * u(rng)}, {"width", 2.0}, {"sill", 0.3},
                 {"height", 1.5},    {"opacity", opacity(rng)}};
  const double wall_y = 0.3 + 0.3 * u(rng);  // triangles reach through the wall and its window
  json walls =
      json::array({{{"start", {-2.0, wall_y}}, {"end", {2.0, wall_y}}, {"height", 2.5}, {"openings", {window}}}});
  json light = {{"type", "directional"}, {"direction", {u(rng), -1.0, u(rng)}}};
  return {{"scene", {{"floor", {{"cells", {3, 3}}}}, {"walls", walls}, {"solids", solids}, {"lights", {light}}}},
          {"camera", {{"position", {2.0 * u(rng), 1.2 + 0.5 * u(rng), 4.0}}, {"target", {0.0, 1.0, 0.0}}}},
          {"options", {{"width", 150}, {"height", 97}}}};
}

TEST(OrderedDraw, PainterEqualsTheWholeFrameDrawOnEveryExample) {
  for (const auto& file : testing::example_files()) {
    const std::string name = file.stem().string();
    const json example = testing::example_request(name, 250, 170);
    testing::for_each_shading_mode(example, [&](const json& request, const std::string& label) {
      SCOPED_TRACE(name + label);
      check_painter(request);
    });
  }
}

TEST(OrderedDraw, BspEqualsTheWholeFrameBackToFrontDrawOnEveryExample) {
  for (const auto& file : testing::example_files()) {
    const std::string name = file.stem().string();
    const json example = testing::example_request(name, 250, 170);
    testing::for_each_shading_mode(example, [&](const json& request, const std::string& label) {
      SCOPED_TRACE(name + label);
      check_bsp(request);
    });
  }
}

TEST(OrderedDraw, SeededRandomScenesEqualTheWholeFrameDraw) {
  const char* keys[] = {"mean", "min", "max", "newell"};
  const char* shadings[] = {"flat", "gouraud", "phong"};
  for (uint32_t seed = 1; seed <= 24; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    json request = random_scene(seed);
    request["options"]["painter"]["key"] = keys[seed % 4];
    request["options"]["shading"] = shadings[seed % 3];
    request["options"]["shadows"] = seed % 2 == 0;
    check_painter(request);
    check_bsp(request);
  }
}

}  // namespace
}  // namespace rr

// The tiled rasterizer's thread count does not change a render: every example x every pipeline x
// every shading x shadows off/on, drawn with 1, 2 and 8 threads, gives byte-identical PNG and id
// buffers. The size is not a multiple of the 64-pixel tile, so partial tiles and tile seams are in
// every image, and 8 threads exceed this machine's cores, so tiles really interleave. The same holds
// with anti-aliasing on.
#include "render/core/scene_names.hpp"
#include "render/core/shading.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/render_modes.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <random>

namespace rr {
namespace {

struct Drawn {
  std::string png;
  std::vector<uint32_t> ids;
  size_t fragments = 0, lights_evaluated = 0;
};

Drawn draw(const RenderRequest& request, const PolygonSoup& soup, unsigned threads) {
  RenderContext context;
  context.threads = threads;
  RenderResult r = render_frame(request.scene, soup, request.camera, request.options, context);
  return {encode_png(r.frame.image), r.frame.ids.ids, r.stats.fragments, r.stats.lights_evaluated};
}

// The frame drawn with 2 and with 8 threads is the one drawn with 1, and so are its counts.
void expect_same_for_two_and_eight_threads(const RenderRequest& request, const PolygonSoup& soup) {
  const Drawn one = draw(request, soup, 1);
  for (unsigned threads : {2u, 8u}) {
    const Drawn many = draw(request, soup, threads);
    EXPECT_TRUE(many.png == one.png) << threads << " threads: the PNG differs";
    EXPECT_TRUE(many.ids == one.ids) << threads << " threads: the id buffer differs";
    EXPECT_EQ(many.fragments, one.fragments) << threads << " threads";
    EXPECT_EQ(many.lights_evaluated, one.lights_evaluated) << threads << " threads";
  }
}

TEST(Threads, EveryExampleAndModeIsByteIdenticalForOneTwoAndEightThreads) {
  size_t renders = 0;
  for (const auto& file : testing::example_files()) {
    nlohmann::json j = nlohmann::json::parse(testing::read_file(file));
    j["options"]["width"] = 250;  // 4 x 3 tiles, the last column and row partial
    j["options"]["height"] = 170;
    testing::for_each_render_mode(j, true, [&](const nlohmann::json& mode, const std::string& label) {
      SCOPED_TRACE(file.filename().string() + label);
      const RenderRequest request = request_from_json(mode);
      const PolygonSoup soup = tessellate(request.scene.geometry);
      expect_same_for_two_and_eight_threads(request, soup);
      renders += 2;
    });
  }
  EXPECT_GT(renders, 0u) << "no examples found";
}

// Shadow rays (options.shadow.method rays) decide each point alone, so the thread count cannot change
// them either: every example x raster pipeline x shading, plain and through the A-buffer. And the
// method is used: some example's frame differs from its shadow-map frame.
TEST(Threads, ShadowRaysAreByteIdenticalForOneTwoAndEightThreads) {
  size_t renders = 0, differ_from_maps = 0;
  for (const auto& file : testing::example_files()) {
    nlohmann::json j = nlohmann::json::parse(testing::read_file(file));
    j["options"]["width"] = 250;
    j["options"]["height"] = 170;
    for (int antialias : {1, 8}) {
      j["options"]["antialias"] = antialias;
      testing::for_each_render_mode(j, false, [&](nlohmann::json mode, const std::string& label) {
        if (!mode["options"]["shadows"].get<bool>()) return;
        SCOPED_TRACE(file.filename().string() + label + " rays, antialias " + std::to_string(antialias));
        const RenderRequest maps = request_from_json(mode);
        mode["options"]["shadow"]["method"] = "rays";
        const RenderRequest request = request_from_json(mode);
        const PolygonSoup soup = tessellate(request.scene.geometry);
        expect_same_for_two_and_eight_threads(request, soup);
        differ_from_maps += draw(request, soup, 2).png != draw(maps, soup, 2).png;
        renders += 2;
      });
    }
  }
  EXPECT_GT(renders, 0u) << "no examples found";
  EXPECT_GT(differ_from_maps, 0u);
}

// A scene of 2,000 seeded random triangles: the front end cuts its draw order into several chunks
// (the examples fit in one), and tiles hold long bins.
nlohmann::json many_triangles() {
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> at(-2.0, 2.0), offset(-0.4, 0.4);
  nlohmann::json vertices = nlohmann::json::array(), faces = nlohmann::json::array();
  for (int t = 0; t < 2000; ++t) {
    const double cx = at(rng), cy = at(rng) + 2.0, cz = at(rng);
    for (int v = 0; v < 3; ++v) vertices.push_back({cx + offset(rng), cy + offset(rng), cz + offset(rng)});
    faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  nlohmann::json scene = {
      {"floor", {{"origin", {-2, -2}}, {"cells", {4, 4}}, {"cell_size", 1.0}}},
      {"solids", {{{"type", "mesh"}, {"id", "cloud"}, {"color", "#b08040"}, {"vertices", vertices}, {"faces", faces}}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, -1.0, 0.2}}, {"intensity", 0.8}}}}};
  return {{"scene", scene},
          {"camera", {{"position", {0.5, 2.5, 6.0}}, {"target", {0.0, 2.0, 0.0}}}},
          {"options", {{"width", 250}, {"height", 170}}}};
}

TEST(Threads, ThousandsOfPolygonsAreByteIdenticalForOneTwoAndEightThreads) {
  testing::for_each_render_mode(many_triangles(), false, [&](const nlohmann::json& mode, const std::string& label) {
    SCOPED_TRACE(label);
    const RenderRequest request = request_from_json(mode);
    const PolygonSoup soup = tessellate(request.scene.geometry);
    ASSERT_GT(soup.polygons.size(), 2000u);
    expect_same_for_two_and_eight_threads(request, soup);
  });
}

// The same through the A-buffer (options.antialias): every example and the random triangles, at
// 8 sub-samples, in every raster pipeline and shading; the bsp walk both ways.
TEST(Threads, AntialiasedFramesAreByteIdenticalForOneTwoAndEightThreads) {
  std::vector<nlohmann::json> requests;
  for (const auto& file : testing::example_files()) {
    nlohmann::json j = nlohmann::json::parse(testing::read_file(file));
    j["options"]["width"] = 250;
    j["options"]["height"] = 170;
    requests.push_back(j);
  }
  requests.push_back(many_triangles());
  for (nlohmann::json& j : requests) {
    j["options"]["antialias"] = 8;
    for (const char* traversal : {"front_to_back", "back_to_front"}) {
      j["options"]["bsp"]["traversal"] = traversal;
      testing::for_each_render_mode(j, false, [&](const nlohmann::json& mode, const std::string& label) {
        if (mode["options"]["pipeline"] != "bsp" && std::string(traversal) == "back_to_front") return;
        SCOPED_TRACE(label + " " + traversal);
        const RenderRequest request = request_from_json(mode);
        const PolygonSoup soup = tessellate(request.scene.geometry);
        expect_same_for_two_and_eight_threads(request, soup);
      });
    }
  }
}

}  // namespace
}  // namespace rr

// options.antialias through the raster pipelines: the id buffer stays the surface under the pixel
// centre whatever S (equal to S = 1's), every pipeline's image changes on edges only, and the
// memory budget refuses a frame whose A-buffer does not fit, naming /options/antialias.
#include "render/core/abuffer.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

namespace rr {
namespace {

// The pipelines that resolve through the A-buffer, and the other drawing orders of painter and bsp,
// as options.
std::vector<nlohmann::json> raster_modes() {
  std::vector<nlohmann::json> modes;
  for (const PipelineInfo& p : pipeline_table()) {
    if (p.abuffer) modes.push_back({{"pipeline", p.name}});
  }
  modes.push_back({{"pipeline", "painter"}, {"painter", {{"key", "newell"}}}});
  modes.push_back({{"pipeline", "bsp"}, {"bsp", {{"traversal", "back_to_front"}}}});
  return modes;
}

RenderResult draw(nlohmann::json j, const nlohmann::json& mode, int samples, const std::string& shading,
                  std::set<uint32_t>* translucent_ids = nullptr) {
  for (const auto& [key, value] : mode.items()) j["options"][key] = value;
  j["options"]["antialias"] = samples;
  j["options"]["shading"] = shading;
  j["options"]["shadows"] = shading != "flat";  // flat: one colour per polygon, no shadow edges inside it
  j["options"]["width"] = 160;
  j["options"]["height"] = 120;
  const RenderRequest request = request_from_json(j);
  const PolygonSoup soup = tessellate(request.scene.geometry);
  if (translucent_ids) {
    for (const Polygon& p : soup.polygons) {
      if (p.flags & polygon_translucent) translucent_ids->insert(p.id);
    }
  }
  return render_frame(request.scene, soup, request.camera, request.options, RenderContext{});
}

TEST(Antialias, IdsAreTheCentresSurfaceAndOnlyEdgePixelsChange) {
  size_t renders = 0, changed_images = 0;
  for (const auto& file : testing::example_files()) {
    const nlohmann::json j = nlohmann::json::parse(testing::read_file(file));
    for (const nlohmann::json& mode : raster_modes()) {
      for (const std::string shading : {"flat", "phong"}) {  // phong with shadows
        SCOPED_TRACE(file.filename().string() + " " + mode.dump() + " " + shading);
        std::set<uint32_t> translucent;
        const RenderResult one = draw(j, mode, 1, shading, &translucent);
        for (int samples : {4, 8, 16}) {
          SCOPED_TRACE(samples);
          const RenderResult many = draw(j, mode, samples, shading);
          EXPECT_TRUE(many.frame.ids.ids == one.frame.ids.ids) << "the id buffer differs from S = 1's";
          // A pixel whose 3x3 neighbourhood shows one opaque surface has no edge near it: with flat
          // shading its colour is S = 1's (its samples all see that surface).
          const int w = one.frame.image.width, h = one.frame.image.height;
          size_t differing = 0;
          for (int y = 1; y + 1 < h; ++y) {
            for (int x = 1; x + 1 < w; ++x) {
              const size_t i = size_t(y) * size_t(w) + size_t(x);
              // Through a translucent pane the surfaces behind it may change within the pixel.
              bool interior = !translucent.count(one.frame.ids.ids[i]);
              for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx)
                  interior &= one.frame.ids.ids[size_t(y + dy) * size_t(w) + size_t(x + dx)] == one.frame.ids.ids[i];
              }
              int off = 0;
              for (int c = 0; c < 3; ++c)
                off = std::max(off, std::abs(int(many.frame.image.rgb[i * 3 + size_t(c)]) -
                                             int(one.frame.image.rgb[i * 3 + size_t(c)])));
              differing += off > 0;
              // One byte: S = 1 rounds to bytes after each translucent blend, the resolve once.
              if (shading == "flat" && interior) {
                EXPECT_LE(off, 1) << "interior pixel " << x << "," << y;
              }
            }
          }
          changed_images += differing > 0;
          ++renders;
        }
      }
    }
  }
  EXPECT_GT(renders, 0u) << "no examples found";
  EXPECT_GT(changed_images, renders / 2) << "anti-aliasing left most images as they were";
}

InputError::Kind failure(const std::string& text, const ParseLimits& limits, std::string& pointer) {
  try {
    parse_request(text, limits);
  } catch (const InputError& e) {
    pointer = e.pointer();
    return e.kind();
  }
  pointer.clear();
  return InputError::Kind::malformed;
}

TEST(Antialias, TheMemoryBudgetCountsTheABuffer) {
  EXPECT_LT(render_bytes(640, 480, 1), render_bytes(640, 480, 4));
  EXPECT_LT(render_bytes(640, 480, 4), render_bytes(640, 480, 16));
  ParseLimits limits;
  limits.max_render_bytes = render_bytes(640, 480, 4);
  EXPECT_NO_THROW(parse_request(R"({"options":{"width":640,"height":480,"antialias":4}})", limits));
  std::string pointer;
  EXPECT_EQ(failure(R"({"options":{"width":640,"height":480,"antialias":8}})", limits, pointer),
            InputError::Kind::too_large);
  EXPECT_EQ(pointer, "/options/antialias");
  limits.max_render_bytes = render_bytes(640, 480, 1) - 1;
  EXPECT_EQ(failure(R"({"options":{"width":640,"height":480}})", limits, pointer), InputError::Kind::too_large);
  EXPECT_EQ(pointer, "/options/width");
  // The defaults: the largest frame fits at 8 samples, not at 16.
  EXPECT_NO_THROW(parse_request(R"({"options":{"width":4096,"height":4096,"antialias":8}})"));
  EXPECT_EQ(failure(R"({"options":{"width":4096,"height":4096,"antialias":16}})", ParseLimits{}, pointer),
            InputError::Kind::too_large);
  EXPECT_EQ(pointer, "/options/antialias");
}

}  // namespace
}  // namespace rr

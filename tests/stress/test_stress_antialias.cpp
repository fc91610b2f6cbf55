// Anti-aliasing against the reference on seeded random rooms and intersecting soups: with
// options.antialias = 16, zbuffer, bsp and painter-newell resolve every pixel to the colour of the
// reference's 16 rays on the same sample pattern, within one sub-sample's share of the colour range.
// The scenes are lit by ambient light alone, so each polygon has one exact colour in every pipeline
// and the comparison measures coverage and its resolve, not shading.
#include "stress/stress_support.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace rr::stress {
namespace {

// Per channel: one of the 16 sub-samples may see another polygon (255 / 16, rounded up), plus one
// step of rounding. Why one may: the rasterizer tests sub-samples against its edges with vertices
// snapped to the sub-pixel grid, the reference against the exact projection, so a sub-sample within
// half a grid unit of an edge can land on either side; two such sub-samples in one pixel need two
// edges that close to two of its sub-samples at once.
constexpr int tolerance = 17;

struct Worst {
  int diff = 0;
  int x = 0, y = 0;
  size_t over_one = 0;  // pixels off by more than rounding: sub-samples that saw another polygon
};

Worst compare_colours(const Image& truth, const Image& test) {
  Worst w;
  for (int y = 0; y < truth.height; ++y) {
    for (int x = 0; x < truth.width; ++x) {
      int pixel = 0;
      for (int ch = 0; ch < 3; ++ch) {
        const size_t i = (size_t(y) * size_t(truth.width) + size_t(x)) * 3 + size_t(ch);
        pixel = std::max(pixel, std::abs(int(truth.rgb[i]) - int(test.rgb[i])));
      }
      w.over_one += pixel > 1;
      if (pixel > w.diff) w = {pixel, x, y, w.over_one};
    }
  }
  return w;
}

json ambient_only(json request) {
  request["scene"]["lights"] = json::array();
  request["scene"]["ambient"] = {{"intensity", 1.0}};
  request["options"]["antialias"] = 16;
  return request;
}

void check_resolved_scenes(const char* what, unsigned first_seed, unsigned count, json (*make)(std::mt19937&)) {
  const auto seeds = testing::test_seeds(first_seed, count);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    const StressScene scene(ambient_only(make(rng)));
    const Frame truth = scene.render("reference");
    for (const PipelineInfo* p : testing::exact_pipelines(false)) {
      const Worst w = compare_colours(truth.image, scene.render_exact(*p).image);
      std::printf("[stress] %s %s %s: largest difference %d at %d,%d; %zu pixels off by more than 1\n", what,
                  seed_note(seed).c_str(), p->name, w.diff, w.x, w.y, w.over_one);
      EXPECT_LE(w.diff, tolerance) << what << " " << seed_note(seed) << ": " << p->name << " at pixel " << w.x << ","
                                   << w.y;
    }
  }
}

TEST(StressAntialias, RandomRoomsResolveAsTheReferenceAt16Samples) {
  check_resolved_scenes("rooms", 1800, 12, random_room);
}

TEST(StressAntialias, RandomIntersectingSoupsResolveAsTheReferenceAt16Samples) {
  check_resolved_scenes("soups", 2800, 8, [](std::mt19937& rng) { return random_soup(rng, 40); });
}

}  // namespace
}  // namespace rr::stress

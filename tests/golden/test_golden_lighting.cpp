// Lighting golden images: every room example (an example with a floor and walls) x every pipeline
// x every shading mode x shadows off/on, rendered at 320x240 and compared with
// tests/golden/images/lighting/<example>.<pipeline>.<shading>.<shadows|no-shadows>.png with the
// tolerance of support/golden.hpp. Iterating pipeline_table() and shading_names means a new
// pipeline or mode shows up here (and needs its goldens generated) without touching this file.
#include "render/core/scene_names.hpp"
#include "render/core/shading.hpp"
#include "render/pipelines/pipeline.hpp"
#include "support/golden.hpp"
#include "support/render_helpers.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace rr {
namespace {

struct LightingCase {
  std::string example;  // file stem in examples/
  std::string pipeline;
  std::string shading;
  bool shadows = false;
  std::string name() const {
    return example + "." + pipeline + "." + shading + "." + (shadows ? "shadows" : "no-shadows");
  }
};

void PrintTo(const LightingCase& c, std::ostream* os) { *os << c.name(); }

bool is_room(const nlohmann::json& request) {
  const auto scene = request.find("scene");
  if (scene == request.end()) return false;
  const auto walls = scene->find("walls");
  return scene->contains("floor") && walls != scene->end() && !walls->empty();
}

std::vector<LightingCase> lighting_cases() {
  std::vector<LightingCase> cases;
  for (const auto& file : testing::example_files()) {
    if (!is_room(nlohmann::json::parse(testing::read_file(file)))) continue;
    for (const PipelineInfo& p : pipeline_table()) {
      for (const auto& s : shading_names) {
        for (bool shadows : {false, true}) cases.push_back({file.stem().string(), p.name, s.name, shadows});
      }
    }
  }
  return cases;
}

std::string lighting_case_name(const ::testing::TestParamInfo<LightingCase>& info) {
  std::string name = info.param.name();
  for (char& ch : name) {
    if (ch == '.' || ch == '-') ch = '_';
  }
  return name;
}

class GoldenLighting : public ::testing::TestWithParam<LightingCase> {};

TEST_P(GoldenLighting, MatchesCommittedImage) {
  const LightingCase& c = GetParam();
  nlohmann::json request = nlohmann::json::parse(testing::read_file(testing::examples_dir() / (c.example + ".json")));
  request["options"]["pipeline"] = c.pipeline;
  request["options"]["shading"] = c.shading;
  request["options"]["shadows"] = c.shadows;
  request["options"]["width"] = 320;
  request["options"]["height"] = 240;
  rr::testing::TextRender render = rr::testing::render_text(request.dump());
  EXPECT_EQ(render.result.stats.shadow_skipped, !c.shadows);  // every room casts something
  testing::expect_matches_golden("lighting/" + c.name(), render.png, render.result.frame.image);
}

INSTANTIATE_TEST_SUITE_P(Rooms, GoldenLighting, ::testing::ValuesIn(lighting_cases()), lighting_case_name);

}  // namespace
}  // namespace rr

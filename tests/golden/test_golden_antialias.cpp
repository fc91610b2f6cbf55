// Golden images with options.antialias = 8: every example x every pipeline that resolves through the
// A-buffer (PipelineInfo::abuffer), compared with tests/golden/images/antialias/<example>.<pipeline>.png
// (support/golden.hpp's tolerance). The reference pipeline's supersampled goldens live with its own suite. Regenerate
// only on purpose: ROOMRENDER_UPDATE_GOLDENS=1 ctest -R golden (then look at every changed image).
#include "render/pipelines/pipeline.hpp"
#include "support/golden.hpp"
#include "support/render_helpers.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace rr {
namespace {

struct AntialiasCase {
  std::string example;  // file stem in examples/
  std::string pipeline;
};

void PrintTo(const AntialiasCase& c, std::ostream* os) {
  *os << c.example << " with " << c.pipeline << " at 8 samples";
}

std::vector<AntialiasCase> antialias_cases() {
  std::vector<AntialiasCase> cases;
  for (const auto& file : testing::example_files()) {
    for (const PipelineInfo& p : pipeline_table()) {
      if (p.abuffer) cases.push_back({file.stem().string(), p.name});
    }
  }
  return cases;
}

std::string antialias_case_name(const ::testing::TestParamInfo<AntialiasCase>& info) {
  return info.param.example + "_" + info.param.pipeline;
}

class GoldenAntialias : public ::testing::TestWithParam<AntialiasCase> {};

TEST_P(GoldenAntialias, MatchesCommittedImage) {
  const AntialiasCase& c = GetParam();
  nlohmann::json request = nlohmann::json::parse(testing::read_file(testing::examples_dir() / (c.example + ".json")));
  request["options"]["pipeline"] = c.pipeline;
  request["options"]["antialias"] = 8;
  rr::testing::TextRender render = rr::testing::render_text(request.dump());
  testing::expect_matches_golden("antialias/" + c.example + "." + c.pipeline, render.png, render.result.frame.image);
}

INSTANTIATE_TEST_SUITE_P(Examples, GoldenAntialias, ::testing::ValuesIn(antialias_cases()), antialias_case_name);

}  // namespace
}  // namespace rr

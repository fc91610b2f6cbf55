// Golden images: every example request x every pipeline -> PNG, compared with the image committed
// in tests/golden/images/ with the tolerance of support/golden.hpp (which also writes the actual
// and diff images on failure). Regenerate the goldens only on purpose:
// ROOMRENDER_UPDATE_GOLDENS=1 ctest -R golden (then look at every changed image).
#include "render/pipelines/pipeline.hpp"
#include "support/golden.hpp"
#include "support/render_helpers.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace rr {
namespace {

struct GoldenCase {
  std::string example;  // file stem in examples/
  std::string pipeline;
};

void PrintTo(const GoldenCase& c, std::ostream* os) { *os << c.example << " with " << c.pipeline; }

std::vector<GoldenCase> golden_cases() {
  std::vector<GoldenCase> cases;
  for (const auto& file : testing::example_files()) {
    for (const PipelineInfo& p : pipeline_table()) cases.push_back({file.stem().string(), p.name});
  }
  return cases;
}

std::string golden_case_name(const ::testing::TestParamInfo<GoldenCase>& info) {
  return info.param.example + "_" + info.param.pipeline;
}

class Golden : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(Golden, MatchesCommittedImage) {
  const GoldenCase& c = GetParam();
  nlohmann::json request = nlohmann::json::parse(testing::read_file(testing::examples_dir() / (c.example + ".json")));
  request["options"]["pipeline"] = c.pipeline;
  rr::testing::TextRender render = rr::testing::render_text(request.dump());
  testing::expect_matches_golden(c.example + "." + c.pipeline, render.png, render.result.frame.image);
}

INSTANTIATE_TEST_SUITE_P(Examples, Golden, ::testing::ValuesIn(golden_cases()), golden_case_name);

}  // namespace
}  // namespace rr

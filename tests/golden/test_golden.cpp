// Golden images: every example request x every pipeline -> PNG, compared with the image committed
// in tests/golden/images/. Tolerance has two parts (as filament's): a pixel "differs" when any
// channel is off by more than kChannelTolerance, and at most kMaxDifferingShare of the pixels may
// differ. Renders are deterministic, so on one machine the difference is zero; the tolerance absorbs
// another compiler's floating-point contraction flipping a few edge pixels. On failure the actual
// image and a diff image are written to build/test-output/golden/. Regenerate the goldens only on
// purpose: ROOMRENDER_UPDATE_GOLDENS=1 ctest -R golden (then look at every changed image).
#include "render/pipeline.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <string>

namespace rr {
namespace {

constexpr int kChannelTolerance = 8;           // of 255
constexpr double kMaxDifferingShare = 0.002;   // 0.2 % of the pixels

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

std::string case_name(const ::testing::TestParamInfo<GoldenCase>& info) {
  return info.param.example + "_" + info.param.pipeline;
}

bool update_mode() {
  const char* v = std::getenv("ROOMRENDER_UPDATE_GOLDENS");
  return v && std::string(v) == "1";
}

class Golden : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(Golden, MatchesCommittedImage) {
  const GoldenCase& c = GetParam();
  nlohmann::json request = nlohmann::json::parse(testing::read_file(testing::examples_dir() / (c.example + ".json")));
  request["options"]["pipeline"] = c.pipeline;
  EncodedRender render = render_request_text(request.dump());
  const std::string name = c.example + "." + c.pipeline + ".png";
  const auto golden_path = testing::source_dir() / "tests" / "golden" / "images" / name;
  if (update_mode()) {
    testing::write_file(golden_path, render.png);
    GTEST_SKIP() << "updated " << golden_path;
  }
  ASSERT_TRUE(std::filesystem::exists(golden_path))
      << "no golden image " << golden_path << "; run with ROOMRENDER_UPDATE_GOLDENS=1 to create it";
  Image expected = decode_png(testing::read_file(golden_path));
  const Image& actual = render.result.frame.image;
  ASSERT_EQ(actual.width, expected.width);
  ASSERT_EQ(actual.height, expected.height);
  Image diff(actual.width, actual.height, Color(0.0f));
  size_t differing = 0;
  for (size_t i = 0; i < actual.rgb.size(); i += 3) {
    int worst = 0;
    for (size_t k = 0; k < 3; ++k) worst = std::max(worst, std::abs(int(actual.rgb[i + k]) - int(expected.rgb[i + k])));
    if (worst > kChannelTolerance) {
      ++differing;
      diff.rgb[i] = 255;  // differing pixels in red
    } else if (worst > 0) {
      diff.rgb[i + 1] = 255;  // within tolerance in green
    }
  }
  size_t pixels = size_t(actual.width) * size_t(actual.height);
  double share = double(differing) / double(pixels);
  if (share > kMaxDifferingShare) {
    auto out = testing::output_dir("golden");
    testing::write_file(out / (c.example + "." + c.pipeline + ".actual.png"), render.png);
    testing::write_file(out / (c.example + "." + c.pipeline + ".diff.png"), encode_png(diff));
    FAIL() << differing << " of " << pixels << " pixels differ by more than " << kChannelTolerance
           << "; actual and diff images written to " << out;
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, Golden, ::testing::ValuesIn(golden_cases()), case_name);

}  // namespace
}  // namespace rr

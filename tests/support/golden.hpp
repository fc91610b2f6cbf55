// Golden-image comparison shared by the golden suites. Tolerance has two parts (as filament's): a
// pixel "differs" when any channel is off by more than golden_channel_tolerance, and at most
// golden_max_differing_share of the pixels may differ. Renders are deterministic, so on one machine
// the difference is zero; the tolerance absorbs another compiler's floating-point contraction
// flipping a few edge pixels. On failure the actual image and a diff image (red: differs, green:
// within tolerance) are written to build/test-output/golden/. Regenerate only on purpose:
// ROOMRENDER_UPDATE_GOLDENS=1 ctest -R golden (then look at every changed image).
#pragma once

#include "render/core/image.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace rr::testing {

constexpr int golden_channel_tolerance = 8;           // of 255
constexpr double golden_max_differing_share = 0.002;  // 0.2 % of the pixels

inline bool golden_update_mode() {
  const char* v = std::getenv("ROOMRENDER_UPDATE_GOLDENS");
  return v && std::string(v) == "1";
}

// Compares an encoded render (`png`, decoded as `actual`) with tests/golden/images/<name>.png, where
// `name` may hold a sub-directory ("lighting/studio.zbuffer.phong.shadows"). In update mode it
// writes the golden instead and skips the test.
inline void expect_matches_golden(const std::string& name, const std::string& png, const Image& actual) {
  const auto golden_path = source_dir() / "tests" / "golden" / "images" / (name + ".png");
  if (golden_update_mode()) {
    std::filesystem::create_directories(golden_path.parent_path());
    write_file(golden_path, png);
    GTEST_SKIP() << "updated " << golden_path;
  }
  ASSERT_TRUE(std::filesystem::exists(golden_path))
      << "no golden image " << golden_path << "; run with ROOMRENDER_UPDATE_GOLDENS=1 to create it";
  const Image expected = decode_png(read_file(golden_path));
  ASSERT_EQ(actual.width, expected.width);
  ASSERT_EQ(actual.height, expected.height);
  Image diff(actual.width, actual.height, Color(0.0f));
  size_t differing = 0;
  for (size_t i = 0; i < actual.rgb.size(); i += 3) {
    int worst = 0;
    for (size_t k = 0; k < 3; ++k) worst = std::max(worst, std::abs(int(actual.rgb[i + k]) - int(expected.rgb[i + k])));
    if (worst > golden_channel_tolerance) {
      ++differing;
      diff.rgb[i] = 255;  // differing pixels in red
    } else if (worst > 0) {
      diff.rgb[i + 1] = 255;  // within tolerance in green
    }
  }
  const size_t pixels = size_t(actual.width) * size_t(actual.height);
  if (double(differing) / double(pixels) > golden_max_differing_share) {
    const auto out = output_dir("golden") / name;
    std::filesystem::create_directories(out.parent_path());
    write_file(out.string() + ".actual.png", png);
    write_file(out.string() + ".diff.png", encode_png(diff));
    FAIL() << differing << " of " << pixels << " pixels differ by more than " << golden_channel_tolerance
           << "; actual and diff images written beside " << out;
  }
}

}  // namespace rr::testing

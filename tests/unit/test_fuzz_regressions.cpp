// Replays every input the fuzzer found (fuzz/regressions/) and the hand-written hostile seeds
// (fuzz/seeds/) through the fuzz harness's ordinary, non-libFuzzer path under every
// pipeline/shading/painter-key/shadow variant: each must give a decodable PNG of the shrunk size or
// a clean InputError, never a crash or another exception. Also checks that the harness renders every
// example (the other seeds), so fuzzing reaches the renderer rather than stopping at validation.
#include "fuzz/fuzz_harness.hpp"
#include "render/core/image.hpp"
#include "render/core/scene_names.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace rr {
namespace {

namespace fs = std::filesystem;

// Every file of fuzz/regressions and fuzz/seeds but dotfiles (.gitkeep), sorted.
std::vector<fs::path> replay_files() {
  std::vector<fs::path> files;
  for (const char* dir : {"regressions", "seeds"}) {
    for (const auto& entry : fs::directory_iterator(testing::source_dir() / "fuzz" / dir)) {
      if (entry.is_regular_file() && entry.path().filename().string()[0] != '.') {
        files.push_back(entry.path());
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Every variant the fuzz target can pick: all pipelines x shading modes x shadows, and for the
// painter every sort key too. PNG modes rotate with the index (they all decode alike).
std::vector<fuzz::Variant> all_variants() {
  std::vector<fuzz::Variant> variants;
  for (const PipelineInfo& pipeline : pipeline_table()) {
    for (const auto& shading : shading_names) {
      for (int shadows = 0; shadows < 2; ++shadows) {
        size_t keys = std::string_view(pipeline.name) == "painter" ? painter_key_names.size() : 1;
        for (size_t k = 0; k < keys; ++k) {
          fuzz::Variant v{pipeline_id(pipeline), shading.value, painter_key_names[k].value, shadows == 1,
                          png_compression_names[variants.size() % png_compression_names.size()].value};
          variants.push_back(v);
        }
      }
    }
  }
  return variants;
}

// Runs one input under one variant; returns whether it rendered, failing the test on any exception
// that is not an InputError (those the harness turns into a refusal) or a wrong-sized image.
bool replay(const std::string& bytes, const fuzz::Variant& v) {
  fuzz::Outcome out;
  try {
    out = fuzz::run_request_bytes(bytes, v);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "escaped exception: " << e.what();
    return false;
  }
  if (!out.rendered) return false;
  Image image = decode_png(out.png);
  EXPECT_GE(image.width, 1);
  EXPECT_GE(image.height, 1);
  EXPECT_LE(std::max(image.width, image.height), fuzz::max_fuzz_side);
  return true;
}

TEST(FuzzRegressions, EveryFoundInputRendersOrIsRefusedUnderEveryVariant) {
  std::vector<fs::path> files = replay_files();
  ASSERT_FALSE(files.empty()) << "fuzz/seeds/ and fuzz/regressions/ hold the inputs to replay";
  std::vector<fuzz::Variant> variants = all_variants();
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    std::string bytes = testing::read_file(file);
    replay(bytes, fuzz::variant_of(bytes));  // exactly what the fuzz target ran
    for (size_t i = 0; i < variants.size(); ++i) {
      SCOPED_TRACE("variant " + std::to_string(i));
      replay(bytes, variants[i]);
    }
  }
}

TEST(FuzzRegressions, HarnessRendersEveryExampleSeed) {
  for (const fs::path& file : testing::example_files()) {
    SCOPED_TRACE(file.filename().string());
    std::string bytes = testing::read_file(file);
    EXPECT_TRUE(replay(bytes, fuzz::variant_of(bytes))) << "the fuzz limits refuse a seed";
  }
}

}  // namespace
}  // namespace rr

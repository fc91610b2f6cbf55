// Helpers for the importer tests: the third-party files in ../shared/data (tests skip without them)
// and a small render of an imported request that reports how much of the frame shows geometry.
#pragma once

#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace rr::testing {

// The files named `prefix`*`extension` in ../shared/data/<sub>, sorted; empty when the data is absent.
inline std::vector<std::filesystem::path> shared_files(const std::string& sub, const std::string& extension,
                                                       const std::string& prefix = "") {
  std::vector<std::filesystem::path> files;
  auto dir = shared_data_dir();
  if (!dir || !std::filesystem::is_directory(*dir / sub)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(*dir / sub)) {
    if (entry.path().extension() == extension && entry.path().filename().string().starts_with(prefix)) {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Test names from file names: letters and digits only.
inline std::string test_name_of(const std::filesystem::path& file) {
  std::string name = file.stem().string();
  std::replace_if(
      name.begin(), name.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
  return name;
}

// Renders `request` (as an importer produced it, so through request_from_json like any request) at
// 160 x 120 with `pipeline`; returns the share of pixels that show a polygon.
inline double covered_share(const nlohmann::json& request, const std::string& pipeline) {
  nlohmann::json small = request;
  small["options"]["width"] = 160;
  small["options"]["height"] = 120;
  small["options"]["pipeline"] = pipeline;
  RenderRequest parsed = request_from_json(small);
  PreparedScene scene = prepare_scene(parsed.scene);
  RenderContext context;
  context.encode = false;
  RenderOutcome result = render(parsed, scene, context);  // through render(): the view's levels and ceilings
  const auto& ids = result.frame.ids.ids;
  size_t covered = size_t(std::count_if(ids.begin(), ids.end(), [](uint32_t id) { return id != background_id; }));
  return double(covered) / double(ids.size());
}

inline std::vector<std::string> pipeline_names() {
  std::vector<std::string> names;
  for (const PipelineInfo& info : pipeline_table()) names.push_back(info.name);
  return names;
}

}  // namespace rr::testing

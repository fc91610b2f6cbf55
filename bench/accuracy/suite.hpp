// The accuracy benchmark's scene suite (bench/accuracy.cpp): every scene as a validated request plus
// its tessellation, tagged with its class (classic test scenes, rooms, Sweet Home 3D homes, R2V
// plans, real interiors, textured surfaces). Sources: examples/, bench_gen_scenes' manifest, and ../shared/data
// (skipped with a message when absent). Parsing, importing and tessellating happen here, outside any timing.
#pragma once

#include "render/core/scene.hpp"
#include "render/pipelines/render.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace rr::bench {

struct SuiteOptions {
  std::filesystem::path source_dir;    // the repository (examples/)
  std::filesystem::path gen_manifest;  // bench_gen_scenes --out; empty: no generated scenes
  std::filesystem::path shared_dir;    // ../shared/data; missing: those scenes are skipped
  std::vector<std::string> only;       // keep scenes whose name contains one of these; empty: all
  int width = 640;
  int height = 360;
  int r2v_plans = 3;  // the first N plans of shared/data/floorplans/r2v, by name
  std::vector<std::string> interiors = {"conference", "fireplace_room", "breakfast_room"};
};

struct BenchScene {
  std::string name;
  std::string scene_class;   // "classic", "rooms", "sh3d", "r2v", "interiors", "textures"
  std::string source;        // file it came from (and camera name), for the report
  RenderRequest request;     // camera and options (width/height set; otherwise defaults); scene moved out
  PreparedScene prepared;    // the scene, tessellated, with its id
  bool light_added = false;  // the source had no light: one default directional light was added
  std::string camera_note;   // how the camera was chosen
  std::string request_json;  // the request as built, before parsing: for tools that hand it on
};

// Loads every scene of the suite that exists; prints one line per skipped source to stderr.
std::vector<BenchScene> load_suite(const SuiteOptions& options);

}  // namespace rr::bench

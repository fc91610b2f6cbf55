// Helpers shared by the test suites: repository paths, file I/O, example requests, and the optional
// third-party data in ../shared (tests that need it skip when it is absent, as in a fresh clone).
#pragma once

#include "render/core/error_metrics.hpp"
#include "render/core/image.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace rr::testing {

std::filesystem::path source_dir();  // the repository root
std::filesystem::path examples_dir();
// ../shared/data beside the repository, or nullopt when absent (with ROOMRENDER_REQUIRE_SHARED set:
// throws, so the test fails instead of skipping).
std::optional<std::filesystem::path> shared_data_dir();
std::filesystem::path output_dir(const std::string& suite);  // build/test-output/<suite>, created
// An empty scratch directory of the running test: output_dir(suite)/<TestSuite>.<TestName> (a '/' of a
// parameterized name becomes '_'), removed and created anew.
std::filesystem::path fresh_output_dir(const std::string& suite = "integration");

// CPU milliseconds used so far by the calling thread / by the whole process. Tests that bound how
// long work takes count CPU, not wall time: on a shared machine a process can wait for a core longer
// than any work it does.
double thread_cpu_ms();
double process_cpu_ms();

std::string read_file(const std::filesystem::path& path);
void write_file(const std::filesystem::path& path, const std::string& bytes);

// examples/<stem>.json as a request, drawn at width x height.
nlohmann::json example_request(const std::string& stem, int width = 320, int height = 240);

// The unit cube [-0.5, 0.5]^3 as a mesh ("vertices", "faces"), each quad counter-clockwise seen from
// outside.
nlohmann::json unit_cube_mesh();

// Every examples/*.json, sorted by name.
std::vector<std::filesystem::path> example_files();

// An id buffer as ASCII art, one row per line: '.' for background, otherwise the id's last digit
// ('0'..'9'), so small exact fixtures read like pictures.
std::string ids_as_ascii(const IdBuffer& ids);

// "Edge pixel" (render/core/error_metrics.hpp): a pixel of `ids` with a 4-neighbour whose id differs;
// there two exact pipelines may legitimately disagree (a split's cut lands within a rounding of
// the true line).
using rr::is_edge_pixel;

struct IdDiff {
  size_t interior = 0;  // differing pixels that are not edge pixels of `truth`
  size_t edge = 0;      // differing edge pixels
};

// Pixel-by-pixel comparison of two id buffers of one size. `edges_of_both`: also count as edge
// pixels those on an id edge of `test` (split pieces snap to the sub-pixel grid on their own).
IdDiff compare_ids(const IdBuffer& truth, const IdBuffer& test, bool edges_of_both = false);

// What `roomrender <args>` did: its exit status and its two streams, as raw bytes.
struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
// Runs the built `roomrender <args>` in `dir` (args go to the shell as written), with `stdin_file`
// as its standard input when given; its streams are kept in dir/stdout.bin and dir/stderr.txt.
RunResult run_roomrender(const std::string& args, const std::filesystem::path& dir, const std::string& stdin_file = "");

}  // namespace rr::testing

// The request flags of `roomrender render` (and `bench-render`, which shares their table), run as a
// user would: each flag gives the same PNG bytes as its value written into the request file and wins
// over the file's own value; `-o -` puts the PNG on stdout and the timings line on stderr; a
// malformed value exits 2 naming the flag, a value the request refuses exits 1 at its pointer.
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace {

using nlohmann::json;
using rr::testing::run_roomrender;
using rr::testing::RunResult;
namespace fs = std::filesystem;

// The studio example, small, with every member a flag sets written out, so each flag below
// replaces a value the file holds (precedence) rather than filling a default.
json base_request() {
  json request = json::parse(rr::testing::read_file(rr::testing::examples_dir() / "studio.json"));
  request["options"] = {{"width", 96},       {"height", 72},     {"pipeline", "zbuffer"},
                        {"shading", "flat"}, {"shadows", false}, {"png", {{"compression", "fast"}}}};
  return request;
}

std::string render_png(const std::string& args, const fs::path& dir) {
  RunResult run = run_roomrender("render request.json -o out.png " + args, dir);
  EXPECT_EQ(run.exit_code, 0) << args << ": " << run.err;
  return rr::testing::read_file(dir / "out.png");
}

std::string render_json_png(const json& request, const fs::path& dir) {
  rr::testing::write_file(dir / "written.json", request.dump());
  RunResult run = run_roomrender("render written.json -o written.png", dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return rr::testing::read_file(dir / "written.png");
}

struct FlagCase {
  std::string args;
  std::function<void(json&)> write;  // the same value written into the request
};

std::vector<FlagCase> flag_cases() {
  auto set = [](const char* object, const char* key, json value) { return [=](json& r) { r[object][key] = value; }; };
  return {
      {"--shading phong", set("options", "shading", "phong")},
      {"--shading=gouraud", set("options", "shading", "gouraud")},
      {"--shadows true", set("options", "shadows", true)},
      {"--pipeline painter", set("options", "pipeline", "painter")},
      {"--png small", [](json& r) { r["options"]["png"]["compression"] = "small"; }},
      {"--png none", [](json& r) { r["options"]["png"]["compression"] = "none"; }},
      {"--width 80", set("options", "width", 80)},
      {"--height 60", set("options", "height", 60)},
      {"--size 64x48", [](json& r) { r["options"]["width"] = 64, r["options"]["height"] = 48; }},
      {"--eye 4,2.5,5", set("camera", "position", {4, 2.5, 5})},
      {"--target 1,0.5,1.5", set("camera", "target", {1, 0.5, 1.5})},
      {"--up 0.3,1,0", set("camera", "up", {0.3, 1, 0})},
      {"--fovy 40", set("camera", "fov_y", 40)},
      {"--near 3", set("camera", "near", 3)},
      {"--far 4", set("camera", "far", 4)},
      // Toward the light on the command line; the direction it travels in the file.
      {"--light-dir 1,2,-0.5",
       [](json& r) {
         r["scene"]["lights"] = {{{"type", "directional"}, {"direction", {-1, -2, 0.5}}}};
       }},
  };
}

TEST(CliParity, EachRequestFlagGivesTheBytesOfItsValueInTheFile) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "request.json", base_request().dump());
  const std::string base = render_png("", dir);
  ASSERT_FALSE(base.empty());
  for (const FlagCase& c : flag_cases()) {
    SCOPED_TRACE(c.args);
    const std::string flagged = render_png(c.args, dir);
    json written = base_request();
    c.write(written);
    const std::string from_file = render_json_png(written, dir);
    ASSERT_FALSE(flagged.empty());
    EXPECT_TRUE(flagged == from_file) << "the flag and the same value in the file give different PNGs";
    EXPECT_FALSE(flagged == base) << "the flag changed nothing: it did not win over the file's value";
  }
}

TEST(CliParity, AllFlagsTogetherEqualAllValuesInTheFile) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "request.json", base_request().dump());
  std::string args;
  json written = base_request();
  for (const FlagCase& c : flag_cases()) {
    if (c.args.starts_with("--size") || c.args.starts_with("--shading=") || c.args == "--png none") continue;
    args += " " + c.args;
    c.write(written);
  }
  EXPECT_TRUE(render_png(args, dir) == render_json_png(written, dir)) << args;
}

TEST(CliParity, DashOutputWritesThePngToStdoutAndTheLineToStderr) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "request.json", base_request().dump());
  RunResult to_file = run_roomrender("render request.json -o out.png --shading phong", dir);
  ASSERT_EQ(to_file.exit_code, 0) << to_file.err;
  RunResult to_stdout = run_roomrender("render request.json -o - --shading phong", dir);
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_FALSE(fs::exists(dir / "-")) << "-o - must not write a file named -";
  EXPECT_TRUE(to_stdout.out == rr::testing::read_file(dir / "out.png")) << "stdout is not the PNG -o file writes";
  ASSERT_EQ(std::count(to_stdout.err.begin(), to_stdout.err.end(), '\n'), 1) << to_stdout.err;
  json line = json::parse(to_stdout.err);
  EXPECT_EQ(json::parse(to_file.out).at("timings_ms").size(), line.at("timings_ms").size()) << line;
  EXPECT_EQ(line.at("width"), 96);

  // The id buffer may take stdout instead; the two cannot share it.
  RunResult ids = run_roomrender("render request.json -o out2.png --ids -", dir);
  ASSERT_EQ(ids.exit_code, 0) << ids.err;
  EXPECT_EQ(ids.out.size(), 8u + 4u * 96u * 72u);
  EXPECT_TRUE(json::parse(ids.err).at("timings_ms").is_object()) << ids.err;
  RunResult both = run_roomrender("render request.json -o - --ids -", dir);
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_TRUE(both.out.empty());
}

// The one error line of a usage error: the flag named, no pointer, the synopsis.
void expect_usage_error_naming(const RunResult& run, const std::string& flag_name) {
  EXPECT_EQ(run.exit_code, 2) << run.err;
  ASSERT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  json line = json::parse(run.err);
  EXPECT_EQ(line.at("error").get<std::string>().rfind(flag_name, 0), 0u) << line;
  EXPECT_TRUE(line.at("pointer").is_null()) << line;
  EXPECT_TRUE(line.at("usage").is_string()) << line;
}

TEST(CliParity, MalformedFlagValuesExitTwoNamingTheFlag) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "request.json", base_request().dump());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--eye 1,2", "--eye"},         {"--target 1,2,x", "--target"},    {"--up '0;1;0'", "--up"},
      {"--fovy wide", "--fovy"},      {"--near 0.1m", "--near"},         {"--far=", "--far"},
      {"--width 1.5", "--width"},     {"--height tall", "--height"},     {"--size 64", "--size"},
      {"--shadows yes", "--shadows"}, {"--light-dir up", "--light-dir"}, {"--size 64x48 --width 64", "--size"}};
  for (const auto& [args, flag_name] : cases) {
    SCOPED_TRACE(args);
    for (const char* command : {"render request.json -o out.png ", "bench-render --request request.json --frames 1 "}) {
      expect_usage_error_naming(run_roomrender(command + args, dir), flag_name);
    }
    EXPECT_FALSE(fs::exists(dir / "out.png"));
  }
  expect_usage_error_naming(run_roomrender("render request.json -o out.png --shading", dir), "--shading");
}

TEST(CliParity, ValuesTheRequestRefusesExitOneAtTheirPointerNamingTheFlag) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "request.json", base_request().dump());
  const std::vector<std::array<std::string, 3>> cases = {
      {"--fovy 500", "/camera/fov_y", "--fovy"},
      {"--shading glossy", "/options/shading", "--shading"},
      {"--png tiny", "/options/png/compression", "--png"},
      {"--pipeline raytrace", "/options/pipeline", "--pipeline"},
      {"--size 0x10", "/options/width", "--size"},
      {"--up 0,0,0", "/camera/up", "--up"},
      {"--far 0.01", "/camera/far", "--far"},  // nearer than the file's near
  };
  for (const auto& [args, pointer, flag_name] : cases) {
    SCOPED_TRACE(args);
    RunResult run = run_roomrender("render request.json -o out.png " + args, dir);
    EXPECT_EQ(run.exit_code, 1) << run.err;
    json line = json::parse(run.err);
    EXPECT_EQ(line.at("pointer"), pointer) << line;
    EXPECT_EQ(line.value("flag", ""), flag_name) << line;
    EXPECT_FALSE(fs::exists(dir / "out.png"));
  }
}

// bench-render reads the same table: the same flags give the frame render draws.
TEST(CliParity, BenchRenderTakesTheSameFlagsAsRender) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "request.json", base_request().dump());
  const std::string args = "--shading phong --shadows true --eye 4,2.5,5 --fovy 50 --width 80 --height 60 --png small";
  const std::string rendered = render_png(args, dir);
  RunResult bench = run_roomrender("bench-render --request request.json --frames 1 --out bench.png " + args, dir);
  ASSERT_EQ(bench.exit_code, 0) << bench.err;
  EXPECT_TRUE(rendered == rr::testing::read_file(dir / "bench.png"));
  json line = json::parse(bench.out);
  EXPECT_EQ(line.at("shading"), "phong");
  EXPECT_EQ(line.at("width"), 80);

  RunResult render_help = run_roomrender("render --help", dir), bench_help = run_roomrender("bench-render --help", dir);
  for (const char* name : {"--eye", "--target", "--up", "--fovy", "--near", "--far", "--width", "--height", "--size",
                           "--pipeline", "--shading", "--shadows", "--png", "--light-dir"}) {
    EXPECT_NE(render_help.out.find(std::string(name) + " "), std::string::npos) << name;
    EXPECT_NE(bench_help.out.find(std::string(name) + " "), std::string::npos) << name;
  }
}

}  // namespace

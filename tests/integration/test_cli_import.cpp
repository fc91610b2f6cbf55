// `roomrender import` and `roomrender render --obj` run as a user would: the printed request renders
// as is, an OBJ's .mtl is found beside it, warnings and errors are JSON lines on stderr (errors
// locate the problem in the source file), and usage mistakes exit 2. Real files from ../shared/data
// where present (the tests that need them skip otherwise); small fixtures written here otherwise.
#include "render/core/image.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct CommandRun {
  int exit_code = -1;
  std::string out, err;
};

// roomrender with `args` (each single-quoted for the shell) in `dir`; stdout and stderr kept apart.
CommandRun roomrender(const std::vector<std::string>& args, const fs::path& dir) {
  std::string command = "cd '" + dir.string() + "' && '" ROOMRENDER_BINARY_DIR "/roomrender'";
  for (const std::string& a : args) command += " '" + a + "'";
  command += " >out.txt 2>err.txt";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, rr::testing::read_file(dir / "out.txt"),
          rr::testing::read_file(dir / "err.txt")};
}

// The JSON lines of a stream.
std::vector<json> json_lines(const std::string& text) {
  std::vector<json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(json::parse(line));
  return lines;
}

std::optional<fs::path> shared(const std::string& relative) {
  auto dir = rr::testing::shared_data_dir();
  if (!dir || !fs::exists(*dir / relative)) return std::nullopt;
  return *dir / relative;
}

TEST(CliImport, HomeXmlImportsAndTheRequestRendersAsIs) {
  auto home = shared("floorplans/sweethome3d/Studio.xml");
  if (!home) GTEST_SKIP() << "../shared/data is absent";
  fs::path dir = rr::testing::fresh_output_dir();
  CommandRun imported = roomrender({"import", home->string()}, dir);
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  EXPECT_EQ(imported.err, "");  // Studio imports without a warning
  rr::testing::write_file(dir / "req.json", imported.out);
  json request = json::parse(imported.out);
  EXPECT_EQ(request["scene"]["walls"].size(), 16u);  // SOURCES.md: 16 walls, none of them arcs
  CommandRun rendered = roomrender({"render", "req.json", "-o", "out.png", "--width", "160", "--height", "120"}, dir);
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  rr::Image image = rr::decode_png(rr::testing::read_file(dir / "out.png"));
  EXPECT_EQ(image.width, 160);
  EXPECT_GT(json::parse(rendered.out)["counts"]["polygons_drawn"].get<int>(), 0);
}

TEST(CliImport, R2vPlanIsRecognisedAndScaled) {
  auto plan = shared("floorplans/r2v/r2v_01_0403_4f22be9b24bf02dc516c579d14aa_0001.txt");
  if (!plan) GTEST_SKIP() << "../shared/data is absent";
  fs::path dir = rr::testing::fresh_output_dir();
  CommandRun imported = roomrender({"import", plan->string(), "--scale", "0.02"}, dir);
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  json request = json::parse(imported.out);
  // The file's line 13 is the wall "44 9 44 196": pixels times 0.02 m.
  EXPECT_EQ(request["scene"]["walls"][0]["start"], json::array({0.88, 0.18}));
  rr::testing::write_file(dir / "req.json", imported.out);
  EXPECT_EQ(roomrender({"render", "req.json", "-o", "out.png"}, dir).exit_code, 0);
}

TEST(CliImport, RenderObjFindsItsMaterialLibraryBesideIt) {
  fs::path dir = rr::testing::fresh_output_dir();
  fs::create_directories(dir / "models");
  rr::testing::write_file(dir / "models/tile.mtl", "newmtl green\nKd 0 1 0\n");
  rr::testing::write_file(dir / "models/tile.obj",
                          "mtllib tile.mtl\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nusemtl green\nf 1 2 3 4\n");
  CommandRun imported = roomrender({"import", "models/tile.obj"}, dir);
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  EXPECT_EQ(json::parse(imported.out)["scene"]["solids"][0]["color"], json::array({0.0, 1.0, 0.0}));
  CommandRun rendered =
      roomrender({"render", "--obj", "models/tile.obj", "-o", "tile.png", "--width", "64", "--height", "48"}, dir);
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  rr::Image image = rr::decode_png(rr::testing::read_file(dir / "tile.png"));
  ASSERT_EQ(image.width, 64);
  // The quad faces the camera above it and fills the centre: the centre pixel is pure green
  // (flat colour times ambient and sun light: no red or blue can appear).
  const size_t centre = (size_t(24) * 64 + 32) * 3;
  EXPECT_EQ(image.rgb[centre], 0);
  EXPECT_GT(image.rgb[centre + 1], 0);
  EXPECT_EQ(image.rgb[centre + 2], 0);
}

TEST(CliImport, ErrorsLocateTheProblemInTheSourceFile) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  CommandRun run = roomrender({"import", "bad.obj"}, dir);
  EXPECT_EQ(run.exit_code, 1);
  std::vector<json> lines = json_lines(run.err);
  ASSERT_EQ(lines.size(), 1u) << run.err;
  EXPECT_EQ(lines[0]["pointer"], "/line/4");
  EXPECT_NE(lines[0]["error"].get<std::string>().find("vertex index 9 is out of range"), std::string::npos);
  rr::testing::write_file(dir / "home.xml", "<home>\n<wall xStart='0'\n</home>\n");
  run = roomrender({"import", "home.xml"}, dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(json_lines(run.err).at(0)["pointer"], "/line/3");
  rr::testing::write_file(dir / "notes.dat", "hello");
  run = roomrender({"import", "notes.dat"}, dir);
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("pass --format"), std::string::npos) << run.err;
}

TEST(CliImport, WarningsAreJsonLinesOnStderr) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "bent.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\nf 1 2 3 4\n");
  CommandRun run = roomrender({"import", "bent.obj"}, dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<json> lines = json_lines(run.err);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0]["warning"], "1 non-planar faces were split into triangles");
}

TEST(CliImport, UsageMistakesExitTwo) {
  fs::path dir = rr::testing::fresh_output_dir();
  EXPECT_EQ(roomrender({"import", "x.obj", "--format", "dxf"}, dir).exit_code, 2);
  EXPECT_EQ(roomrender({"import"}, dir).exit_code, 2);
  EXPECT_EQ(roomrender({"import", "x.obj", "--scale", "-3"}, dir).exit_code, 2);
  EXPECT_EQ(roomrender({"render", "req.json", "--obj", "x.obj", "-o", "o.png"}, dir).exit_code, 2);
  EXPECT_EQ(roomrender({"render", "req.json", "--scale", "2", "-o", "o.png"}, dir).exit_code, 2);
}

}  // namespace

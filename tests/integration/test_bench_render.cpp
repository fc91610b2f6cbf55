// `roomrender bench-render` run as the benchmark script runs it (the built executable, files in a
// scratch directory): one JSON line whose frame times and stage medians are consistent, --out and
// --ids that equal a normal `render` of the same request, camera/light/size flags that mean exactly
// what the same values written into the request mean, and --list naming the build's own tables.
#include "render/core/scene_names.hpp"
#include "render/core/shading.hpp"
#include "render/pipelines/pipeline.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct BenchOutcome {
  int status = -1;
  json line;        // stdout parsed when it is one JSON line; null otherwise
  std::string err;  // stderr
};

// Runs `roomrender <args>` with `dir` as the working directory.
BenchOutcome roomrender(const fs::path& dir, const std::string& args) {
  const std::string out = (dir / "out.txt").string(), err = (dir / "err.txt").string();
  const std::string command =
      "cd '" + dir.string() + "' && '" ROOMRENDER_BINARY_DIR "/roomrender' " + args + " >'" + out + "' 2>'" + err + "'";
  const int raw = std::system(command.c_str());
  BenchOutcome o;
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  o.line = json::parse(rr::testing::read_file(out), nullptr, /*allow_exceptions=*/false);
  if (o.line.is_discarded()) o.line = nullptr;
  o.err = rr::testing::read_file(err);
  return o;
}

// A lit box, an open floor quad and a translucent pane: opaque, open and blended paths all draw.
json small_scene() {
  return {
      {"solids",
       {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"rotation_y", 30}, {"color", "#c04040"}},
        {{"type", "mesh"}, {"vertices", {{-3, 0, -3}, {3, 0, -3}, {3, 0, 3}, {-3, 0, 3}}}, {"faces", {{0, 3, 2, 1}}}}}},
      {"walls",
       {{{"start", {-2, -1.5}},
         {"end", {2, -1.5}},
         {"height", 2},
         {"openings", {{{"type", "window"}, {"offset", 1}, {"width", 2}, {"sill", 0.3}}}}}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.2, -1, 0.7}}}}}};
}

bool same_file(const fs::path& a, const fs::path& b) { return rr::testing::read_file(a) == rr::testing::read_file(b); }

TEST(BenchRender, PrintsOneLineOfConsistentTimings) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "scene.json", json{{"scene", small_scene()}}.dump());
  BenchOutcome run = roomrender(dir, "bench-render --request scene.json --size 64x48 --frames 5 --warmup 2");
  ASSERT_EQ(run.status, 0) << run.err;
  ASSERT_TRUE(run.line.is_object()) << "stdout must be exactly one JSON line";
  const json& j = run.line;
  EXPECT_EQ(j["source"], "request");
  EXPECT_EQ(j["pipeline"], "zbuffer");
  EXPECT_EQ(j["shading"], "flat");
  EXPECT_EQ(j["shadows"], false);
  EXPECT_EQ(j["width"], 64);
  EXPECT_EQ(j["height"], 48);
  EXPECT_EQ(j["frames"], 5);
  EXPECT_EQ(j["warmup"], 2);
  // The box's 6 quads, the floor quad, and the wall's faces: every polygon is a fan of (n - 2).
  EXPECT_GT(j["polygons"].get<int>(), 7);
  EXPECT_GE(j["triangles"].get<int>(), 2 * j["polygons"].get<int>());
  EXPECT_EQ(j["counts"]["polygons"], j["polygons"]);
  EXPECT_GE(j["setup_ms"].get<double>(), 0.0);
  const double lo = j["frame_ms_min"], mid = j["frame_ms_median"], hi = j["frame_ms_max"];
  EXPECT_GT(lo, 0.0);
  EXPECT_LE(lo, mid);
  EXPECT_LE(mid, hi);
  // Each frame's stage total is measured inside the frame's wall clock, so its median cannot exceed
  // the frame median (1 µs: both are rounded to microseconds); stages sum to at most the total.
  const json& st = j["stage_ms_median"];
  // "other" is a difference of clock readings rounded to 1 µs, hence the tolerance.
  for (const char* stage : {"shadow", "build", "cull", "sort", "traverse", "raster", "shade", "other", "total"}) {
    ASSERT_TRUE(st[stage].is_number()) << stage << " in " << j;
    EXPECT_GE(st[stage].get<double>(), -0.001) << stage;
  }
  EXPECT_LE(st["total"].get<double>(), mid + 0.001);
  EXPECT_GT(st["raster"].get<double>(), 0.0);
  EXPECT_LE(st["raster"].get<double>() + st["shade"].get<double>(), st["total"].get<double>() + 0.002);
  EXPECT_GT(j["counts"]["fragments"].get<int>(), 0) << "the camera should see the scene";
}

TEST(BenchRender, OutAndIdsEqualANormalRender) {
  fs::path dir = rr::testing::fresh_output_dir();
  fs::path studio = rr::testing::examples_dir() / "studio.json";  // walls, openings, translucent panes
  BenchOutcome render =
      roomrender(dir, "render '" + studio.string() + "' -o render.png --ids render.ids --width 160 --height 120");
  ASSERT_EQ(render.status, 0) << render.err;
  BenchOutcome bench = roomrender(dir, "bench-render --request '" + studio.string() +
                                           "' --size 160x120 --frames 2 --out bench.png --ids bench.ids");
  ASSERT_EQ(bench.status, 0) << bench.err;
  EXPECT_TRUE(same_file(dir / "render.ids", dir / "bench.ids"));
  rr::Image a = rr::decode_png(rr::testing::read_file(dir / "render.png"));
  rr::Image b = rr::decode_png(rr::testing::read_file(dir / "bench.png"));
  EXPECT_EQ(a.width, 160);
  EXPECT_EQ(b.width, a.width);
  EXPECT_EQ(b.height, a.height);
  EXPECT_TRUE(a.rgb == b.rgb) << "bench-render's last frame must be the frame render draws";
}

// --obj: polygon id k is the OBJ's k-th `f` line (one group, no repairs), and the frame is the one
// `render --obj` draws from the same file.
TEST(BenchRender, ObjIdsAreTheFaceLinesInOrder) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "two.obj",
                          "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv -0.5 0.5 0\nv 0.5 0.5 0\nv 0 1.2 0\n"
                          "f 1 4 3 2\nf 5 6 7\n");
  const std::string camera = " --eye 0,3,4 --target 0,0.3,0 --up 0,1,0 --fovy 50 --near 0.1 --far 20 --size 80x60";
  BenchOutcome bench = roomrender(dir, "bench-render --obj two.obj" + camera + " --frames 2 --ids bench.ids");
  ASSERT_EQ(bench.status, 0) << bench.err;
  EXPECT_EQ(bench.line["source"], "obj");
  EXPECT_EQ(bench.line["polygons"], 2);
  rr::IdBuffer ids = rr::decode_id_buffer(rr::testing::read_file(dir / "bench.ids"));
  size_t floor = 0, triangle = 0;
  for (uint32_t id : ids.ids) {
    floor += id == 0;
    triangle += id == 1;
  }
  EXPECT_GT(floor, 100u);    // the first f line, the quad
  EXPECT_GT(triangle, 50u);  // the second, the triangle in front of it
  BenchOutcome bad = roomrender(dir, "bench-render --obj missing.obj --frames 1");
  EXPECT_EQ(bad.status, 1);
}

// The peer's flags (OpenGL look-at, fovy, near/far, WxH, a direction toward the light) written into a
// request by hand must give the same picture as bench-render given them as flags.
TEST(BenchRender, CameraAndLightFlagsMeanTheRequestsValues) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "plain.json", json{{"scene", small_scene()}}.dump());
  json by_hand = {{"scene", small_scene()},
                  {"camera",
                   {{"position", {2.5, 3, 4}},
                    {"target", {0, 0.25, 0}},
                    {"up", {0, 1, 0.1}},
                    {"fov_y", 45},
                    {"near", 0.5},
                    {"far", 20}}},
                  {"options", {{"width", 96}, {"height", 64}}}};
  by_hand["scene"]["lights"] = {
      {{"type", "directional"}, {"direction", {-1, -2, 0.5}}}};  // travels away from the flag's
  rr::testing::write_file(dir / "by_hand.json", by_hand.dump());
  BenchOutcome render = roomrender(dir, "render by_hand.json -o render.png --ids render.ids");
  ASSERT_EQ(render.status, 0) << render.err;
  BenchOutcome bench = roomrender(dir,
                                  "bench-render --request plain.json --eye 2.5,3,4 --target 0,0.25,0 --up 0,1,0.1 "
                                  "--fovy 45 --near 0.5 --far 20 --size 96x64 --light-dir 1,2,-0.5 --frames 1 "
                                  "--out bench.png --ids bench.ids");
  ASSERT_EQ(bench.status, 0) << bench.err;
  EXPECT_TRUE(same_file(dir / "render.ids", dir / "bench.ids"));
  EXPECT_TRUE(rr::decode_png(rr::testing::read_file(dir / "render.png")).rgb ==
              rr::decode_png(rr::testing::read_file(dir / "bench.png")).rgb);
  // And the light flag matters: the opposite direction lights other faces.
  BenchOutcome flipped =
      roomrender(dir, "bench-render --request by_hand.json --light-dir -1,-2,0.5 --frames 1 --out flipped.png");
  ASSERT_EQ(flipped.status, 0) << flipped.err;
  EXPECT_FALSE(rr::decode_png(rr::testing::read_file(dir / "flipped.png")).rgb ==
               rr::decode_png(rr::testing::read_file(dir / "render.png")).rgb);
}

TEST(BenchRender, ListNamesTheBuildsTables) {
  fs::path dir = rr::testing::fresh_output_dir();
  BenchOutcome list = roomrender(dir, "bench-render --list");
  ASSERT_EQ(list.status, 0) << list.err;
  std::vector<std::string> pipelines, shadings;
  for (const rr::PipelineInfo& p : rr::pipeline_table()) pipelines.push_back(p.name);
  for (const auto& s : rr::shading_names) shadings.push_back(s.name);
  EXPECT_EQ(list.line["pipelines"].get<std::vector<std::string>>(), pipelines);
  EXPECT_EQ(list.line["shadings"].get<std::vector<std::string>>(), shadings);
}

TEST(BenchRender, BadCommandLinesAndBadValues) {
  fs::path dir = rr::testing::fresh_output_dir();
  rr::testing::write_file(dir / "scene.json", json{{"scene", small_scene()}}.dump());
  // Usage errors (exit 2): no input, two inputs, malformed numbers.
  for (const char* args :
       {"bench-render", "bench-render --request scene.json --obj scene.obj",
        "bench-render --request scene.json --frames 0", "bench-render --request scene.json --eye 1,2",
        "bench-render --request scene.json --size 64", "bench-render --request scene.json --shadows yes",
        "bench-render --request scene.json --fovy wide"}) {
    EXPECT_EQ(roomrender(dir, args).status, 2) << args;
  }
  // Values the request validator refuses are reported by JSON Pointer (exit 1).
  BenchOutcome fov = roomrender(dir, "bench-render --request scene.json --fovy 500");
  EXPECT_EQ(fov.status, 1);
  EXPECT_EQ(json::parse(fov.err)["pointer"], "/camera/fov_y") << fov.err;
  BenchOutcome pipeline = roomrender(dir, "bench-render --request scene.json --pipeline raytrace");
  EXPECT_EQ(pipeline.status, 1);
  EXPECT_EQ(json::parse(pipeline.err)["pointer"], "/options/pipeline") << pipeline.err;
}

}  // namespace

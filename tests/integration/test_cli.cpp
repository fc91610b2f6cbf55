// The built `roomrender` executable, run as a user would (a shell, files in a scratch directory):
// render writes the PNG and the raw id buffer and prints one JSON line of timings and counts; export
// writes one OBJ `f` line per polygon in id order with exactly round-tripping coordinates; errors are
// one JSON line on stderr with exit 1, usage errors exit 2; serve announces its port and stops on SIGTERM.
#include "cli/cli.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace {

using nlohmann::json;
using rr::testing::run_roomrender;
using rr::testing::RunResult;
namespace fs = std::filesystem;

// One closed mesh (a box) whose coordinates need all 17 digits, so OBJ round-tripping is tested;
// identity placement, so world coordinates are the mesh's own. Faces wind outward.
const std::array<std::array<double, 3>, 8> box_vertices = {{
    {0.1, -2.75, -0.7},
    {1.2345678901234567, -2.75, -0.7},
    {1.2345678901234567, 0.3, -0.7},
    {0.1, 0.3, -0.7},
    {0.1, -2.75, 0.45},
    {1.2345678901234567, -2.75, 0.45},
    {1.2345678901234567, 0.3, 0.45},
    {0.1, 0.3, 0.45},
}};
const std::vector<std::vector<int>> box_faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 4, 7, 3},
                                                 {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}};

json mesh_request() {
  return {{"scene",
           {{"solids", {{{"type", "mesh"}, {"vertices", box_vertices}, {"faces", box_faces}, {"closed", true}}}},
            {"lights", {{{"type", "directional"}, {"direction", {-0.3, -1, -0.5}}}}}}},
          {"camera", {{"position", {3.5, 1.5, 4}}, {"target", {0.6, -1.2, 0}}}},
          {"options", {{"width", 40}, {"height", 30}}}};
}

fs::path write_request(const fs::path& dir, const json& request) {
  rr::testing::write_file(dir / "request.json", request.dump(2));
  return dir / "request.json";
}

uint32_t le32(const std::string& bytes, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | uint8_t(bytes[at + size_t(i)]);
  return v;
}

// Checks the id file against render/core/image.hpp's format by hand: header, size, and every id either
// background or a polygon. Returns how many pixels show a polygon.
size_t check_id_file(const std::string& bytes, uint32_t width, uint32_t height, size_t polygons) {
  EXPECT_GE(bytes.size(), 8u);
  if (bytes.size() < 8) return 0;
  EXPECT_EQ(le32(bytes, 0), width);
  EXPECT_EQ(le32(bytes, 4), height);
  EXPECT_EQ(bytes.size(), 8 + 4 * size_t(width) * size_t(height));
  size_t covered = 0;
  for (size_t at = 8; at + 4 <= bytes.size(); at += 4) {
    uint32_t id = le32(bytes, at);
    if (id == rr::background_id) continue;
    EXPECT_LT(id, polygons) << "pixel " << (at - 8) / 4;
    ++covered;
  }
  return covered;
}

TEST(Cli, RenderWritesPngIdsAndOneTimingsLine) {
  fs::path dir = rr::testing::fresh_output_dir();
  write_request(dir, mesh_request());
  RunResult run = run_roomrender("render request.json -o out.png --ids out.ids", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1) << run.out;
  json line = json::parse(run.out);
  for (const char* stage : {"parse", "tessellate", "raster", "shade", "encode", "total"}) {
    EXPECT_TRUE(line["timings_ms"][stage].is_number()) << stage << " in " << line;
  }
  EXPECT_EQ(line["counts"]["polygons"], box_faces.size()) << line;
  rr::Image image = rr::decode_png(rr::testing::read_file(dir / "out.png"));
  EXPECT_EQ(image.width, 40);
  EXPECT_EQ(image.height, 30);
  size_t covered = check_id_file(rr::testing::read_file(dir / "out.ids"), 40, 30, box_faces.size());
  EXPECT_GT(covered, 0u) << "the camera should see the box";
}

TEST(Cli, RenderOverridesAndStdin) {
  fs::path dir = rr::testing::fresh_output_dir();
  fs::path request = write_request(dir, mesh_request());
  RunResult run = run_roomrender("render - -o out.png --ids out.ids --width 24 --height=18 --pipeline zbuffer", dir,
                                 request.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  check_id_file(rr::testing::read_file(dir / "out.ids"), 24, 18, box_faces.size());
}

TEST(Cli, RenderErrorsAreOneJsonLineWithPointer) {
  fs::path dir = rr::testing::fresh_output_dir();
  json bad_wall = {{"scene", {{"walls", {{{"start", {0, 0}}, {"end", {2, 0}}, {"thickness", -1}}}}}}};
  write_request(dir, bad_wall);
  RunResult invalid = run_roomrender("render request.json -o out.png", dir);
  EXPECT_EQ(invalid.exit_code, 1);
  EXPECT_EQ(json::parse(invalid.err)["pointer"], "/scene/walls/0/thickness") << invalid.err;
  EXPECT_FALSE(fs::exists(dir / "out.png"));

  write_request(dir, mesh_request());
  RunResult too_large = run_roomrender("render request.json -o out.png --width 100000", dir);
  EXPECT_EQ(too_large.exit_code, 1);
  EXPECT_EQ(json::parse(too_large.err)["pointer"], "/options/width") << too_large.err;
}

TEST(Cli, UsageErrorsExitTwo) {
  fs::path dir = rr::testing::fresh_output_dir();
  EXPECT_EQ(run_roomrender("no-such-command", dir).exit_code, 2);
  EXPECT_EQ(run_roomrender("", dir).exit_code, 2);
  EXPECT_EQ(run_roomrender("render request.json", dir).exit_code, 2);  // no -o
  EXPECT_EQ(run_roomrender("render request.json -o x.png --width wide", dir).exit_code, 2);
  EXPECT_EQ(run_roomrender("export request.json --obj", dir).exit_code, 2);
  EXPECT_EQ(run_roomrender("serve --port 70000", dir).exit_code, 2);
  RunResult version = run_roomrender("--version", dir);
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind("roomrender ", 0), 0u) << version.out;
  EXPECT_EQ(run_roomrender("help", dir).exit_code, 0);
}

struct ObjFile {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::vector<size_t>> faces;  // 0-based indices into vertices
};

ObjFile read_obj(const std::string& text) {
  ObjFile obj;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "v") {
      std::array<std::string, 3> xyz;
      words >> xyz[0] >> xyz[1] >> xyz[2];
      // strtod is correctly rounded, so a shortest round-trip decimal reads back exactly.
      obj.vertices.push_back({std::strtod(xyz[0].c_str(), nullptr), std::strtod(xyz[1].c_str(), nullptr),
                              std::strtod(xyz[2].c_str(), nullptr)});
    } else if (tag == "f") {
      std::vector<size_t> face;
      for (size_t index; words >> index;) face.push_back(index - 1);
      obj.faces.push_back(face);
    }
  }
  return obj;
}

// The polygon's vertices equal the face's, allowing a different starting vertex (the format promises
// the face, not where its loop starts).
bool same_loop(const std::vector<std::array<double, 3>>& a, const std::vector<std::array<double, 3>>& b) {
  if (a.size() != b.size()) return false;
  for (size_t shift = 0; shift < a.size(); ++shift) {
    bool equal = true;
    for (size_t i = 0; i < a.size() && equal; ++i) equal = a[(i + shift) % a.size()] == b[i];
    if (equal) return true;
  }
  return false;
}

TEST(Cli, ExportWritesOneFaceLinePerPolygonWithExactVertices) {
  fs::path dir = rr::testing::fresh_output_dir();
  write_request(dir, mesh_request());
  RunResult run = run_roomrender("export request.json --obj out.obj", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(json::parse(run.out)["polygons"], box_faces.size()) << run.out;
  ObjFile obj = read_obj(rr::testing::read_file(dir / "out.obj"));
  ASSERT_EQ(obj.faces.size(), box_faces.size());
  for (size_t k = 0; k < box_faces.size(); ++k) {
    std::vector<std::array<double, 3>> exported, expected;
    for (size_t index : obj.faces[k]) {
      ASSERT_LT(index, obj.vertices.size());
      exported.push_back(obj.vertices[index]);
    }
    for (int index : box_faces[k]) expected.push_back(box_vertices[size_t(index)]);
    EXPECT_TRUE(same_loop(exported, expected)) << "face " << k;
  }
}

TEST(Cli, ExportAndRenderAgreeOnPolygonCountForStudio) {
  fs::path dir = rr::testing::fresh_output_dir();
  std::string studio = (rr::testing::examples_dir() / "studio.json").string();
  RunResult exported = run_roomrender("export '" + studio + "' --obj studio.obj", dir);
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  RunResult rendered = run_roomrender("render '" + studio + "' -o studio.png --width 64 --height 48", dir);
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  size_t polygons = json::parse(rendered.out)["counts"]["polygons"];
  EXPECT_EQ(json::parse(exported.out)["polygons"], polygons);
  EXPECT_EQ(read_obj(rr::testing::read_file(dir / "studio.obj")).faces.size(), polygons);
}

// `serve --port 0` announces the port it got in its first stdout line, serves, and stops cleanly on
// SIGTERM. ROOMRENDER_PORT is set to garbage to show that the flag wins (the variable is not read).
TEST(Cli, ServeAnnouncesItsPortAndStopsOnSigterm) {
  int out_pipe[2];
  ASSERT_EQ(::pipe(out_pipe), 0);
  pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::close(out_pipe[0]);
    ::setenv("ROOMRENDER_PORT", "not-a-port", 1);
    ::execl(ROOMRENDER_BINARY_DIR "/roomrender", "roomrender", "serve", "--port", "0", "--log-requests", "0",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(out_pipe[1]);
  std::FILE* out = ::fdopen(out_pipe[0], "r");
  char line[4096] = {};
  bool got_line = std::fgets(line, sizeof line, out) != nullptr;
  json listening = got_line ? json::parse(line, nullptr, false) : json();
  int port = listening.is_object() ? listening.value("port", 0) : 0;
  EXPECT_EQ(listening.value("event", ""), "listening") << line;
  EXPECT_GT(port, 0) << line;
  if (port > 0) {
    httplib::Client client("127.0.0.1", port);
    auto res = client.Get("/healthz");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200);
  }
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  bool stopped = std::fgets(line, sizeof line, out) != nullptr;
  EXPECT_TRUE(stopped && json::parse(line, nullptr, false).value("event", "") == "stopped") << line;
  std::fclose(out);
}

TEST(Cli, ServeConfigReadsVariablesButFlagsWin) {
  auto env = [](const char* name) -> std::optional<std::string> {
    if (std::string(name) == "ROOMRENDER_PORT") return "9001";
    if (std::string(name) == "ROOMRENDER_BIND") return "0.0.0.0";
    if (std::string(name) == "ROOMRENDER_THREADS") return "3";
    return std::nullopt;
  };
  std::vector<std::string> args = {"--bind", "127.0.0.2", "--examples-dir=/tmp/ex"};
  rr::server::ServerConfig config = rr::server::serve_config_from(args, env);
  EXPECT_EQ(config.port, 9001);
  EXPECT_EQ(config.bind, "127.0.0.2");
  EXPECT_EQ(config.threads, 3);
  EXPECT_EQ(config.examples_dir, "/tmp/ex");
  EXPECT_TRUE(config.log_requests);
  std::vector<std::string> bad = {"--threads", "many"};
  EXPECT_THROW(rr::server::serve_config_from(bad, env), rr::server::UsageError);
  auto bad_env = [](const char* name) -> std::optional<std::string> {
    return std::string(name) == "ROOMRENDER_PORT" ? std::optional<std::string>("99999") : std::nullopt;
  };
  EXPECT_THROW(rr::server::serve_config_from({}, bad_env), rr::server::UsageError);
}

}  // namespace

// compare: the reference render against the zbuffer render of the same request, as files. The
// box is seen whole with no polygon crossing another, so the two differ only on id edges (the
// non-edge visibility error is exactly 0); a file compared with itself has zero error and an
// infinite PSNR (null in JSON).
TEST(Cli, CompareIdsAndPngsPrintsErrorMeasures) {
  fs::path dir = rr::testing::fresh_output_dir();
  json request = mesh_request();
  // A point light: its lighting varies across each face, so flat shading differs from the
  // reference's per-pixel lighting (with the directional light alone both are exact).
  request["scene"]["lights"].push_back({{"type", "point"}, {"position", {1.5, 1.0, 1.5}}});
  write_request(dir, request);
  ASSERT_EQ(run_roomrender("render request.json -o z.png --ids z.ids", dir).exit_code, 0);
  ASSERT_EQ(run_roomrender("render request.json -o r.png --ids r.ids --pipeline reference", dir).exit_code, 0);
  RunResult ids = run_roomrender("compare r.ids z.ids", dir);
  ASSERT_EQ(ids.exit_code, 0) << ids.err;
  ASSERT_EQ(std::count(ids.out.begin(), ids.out.end(), '\n'), 1) << ids.out;
  json v = json::parse(ids.out);
  EXPECT_EQ(v["width"], 40);
  EXPECT_EQ(v["visibility"]["pixels"], 40 * 30);
  EXPECT_EQ(v["visibility"]["non_edge_differing"], 0) << v;
  EXPECT_GT(v["visibility"]["non_edge_pixels"].get<int>(), 0) << v;
  EXPECT_FALSE(v.contains("shading"));
  RunResult png = run_roomrender("compare r.png z.png", dir);
  ASSERT_EQ(png.exit_code, 0) << png.err;
  json s = json::parse(png.out);
  ASSERT_GT(s["shading"]["rmse"].get<double>(), 0.0) << s;  // flat against per-pixel lighting
  EXPECT_NEAR(s["shading"]["psnr_db"].get<double>(), 20.0 * std::log10(255.0 / s["shading"]["rmse"].get<double>()),
              1e-9);
  json same = json::parse(run_roomrender("compare z.png z.png", dir).out);
  EXPECT_EQ(same["shading"]["rmse"], 0.0);
  EXPECT_TRUE(same["shading"]["psnr_db"].is_null()) << same;
}

// compare --request: the texture error over the textured pixels of the papered studio away from the
// reference's edges. Nearest filtering against the reference's box filter differs there; a file
// against itself does not; the untextured studio has no textured pixel; the test's ids keep only the
// pixels where it drew the reference's polygon; ids of another scene are refused.
TEST(Cli, CompareReportsTheTextureErrorOfTheRequestsTexturedPixels) {
  fs::path dir = rr::testing::fresh_output_dir();
  json request = rr::testing::example_request("studio_textured", 96, 72);
  request["options"]["shadows"] = false;
  write_request(dir, request);
  json plain = rr::testing::example_request("studio", 96, 72);
  rr::testing::write_file(dir / "plain.json", plain.dump());
  ASSERT_EQ(run_roomrender("render request.json -o r.png --ids r.ids --pipeline reference", dir).exit_code, 0);
  ASSERT_EQ(run_roomrender("render request.json -o n.png --ids n.ids --texture-filter nearest", dir).exit_code, 0);
  ASSERT_EQ(
      run_roomrender("render request.json -o m.png --ids m.ids --texture-filter nearest --fovy 62", dir).exit_code, 0);
  RunResult run = run_roomrender("compare r.png n.png --edges r.ids --request request.json", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json t = json::parse(run.out)["texture"];
  const int pixels = t["pixels"].get<int>();
  EXPECT_GT(pixels, 96 * 72 / 4) << t;  // walls and floor fill most of the view
  ASSERT_GT(t["rmse"].get<double>(), 0.0) << t;
  EXPECT_NEAR(t["psnr_db"].get<double>(), 20.0 * std::log10(255.0 / t["rmse"].get<double>()), 1e-9);

  const json same = json::parse(run_roomrender("compare r.png r.png --edges r.ids --request request.json", dir).out);
  EXPECT_EQ(same["texture"]["pixels"], pixels);
  EXPECT_EQ(same["texture"]["rmse"], 0.0);
  EXPECT_TRUE(same["texture"]["psnr_db"].is_null()) << same;
  // The same polygon ids, so the test's ids change nothing for the same view.
  EXPECT_EQ(json::parse(run_roomrender("compare r.png n.png --edges r.ids --request request.json --test-ids n.ids", dir)
                            .out)["texture"],
            t);
  // A wider view moves every polygon: far fewer pixels show the reference's polygon.
  const json moved = json::parse(
      run_roomrender("compare r.png m.png --edges r.ids --request request.json --test-ids m.ids", dir).out)["texture"];
  EXPECT_LT(moved["pixels"].get<int>(), pixels) << moved;

  ASSERT_EQ(run_roomrender("render plain.json -o p.png --ids p.ids --pipeline reference", dir).exit_code, 0);
  const json none = json::parse(run_roomrender("compare p.png p.png --edges p.ids --request plain.json", dir).out);
  EXPECT_EQ(none["texture"]["pixels"], 0) << none;

  rr::testing::write_file(dir / "one.json", mesh_request().dump());  // six polygons: ids past them are refused
  RunResult other = run_roomrender("compare r.png n.png --edges r.ids --request one.json", dir);
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("is not among the 6 polygons"), std::string::npos) << other.err;
  RunResult usage = run_roomrender("compare r.png n.png --request request.json", dir);
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_NE(usage.err.find("--edges REFERENCE.ids"), std::string::npos) << usage.err;
}

TEST(Cli, CompareRejectsMismatchedSizesKindsAndUnreadableFiles) {
  fs::path dir = rr::testing::fresh_output_dir();
  write_request(dir, mesh_request());
  ASSERT_EQ(run_roomrender("render request.json -o a.png --ids a.ids", dir).exit_code, 0);
  ASSERT_EQ(run_roomrender("render request.json -o b.png --ids b.ids --width 20", dir).exit_code, 0);
  rr::testing::write_file(dir / "bad.ids", "not an id buffer");
  struct Case {
    std::string args, message;
    int exit_code;
  };
  for (const Case& c : {Case{"compare a.ids b.ids", "sizes differ: 40x30 and 20x30", 1},
                        Case{"compare a.png b.png", "sizes differ: 40x30 and 20x30", 1},
                        Case{"compare a.png a.ids", "a.png is a PNG but a.ids is not", 1},
                        Case{"compare a.ids missing.ids", "cannot read missing.ids", 1},
                        Case{"compare a.ids bad.ids", "bad.ids", 1}, Case{"compare a.ids", "expected two files", 2}}) {
    SCOPED_TRACE(c.args);
    RunResult run = run_roomrender(c.args, dir);
    EXPECT_EQ(run.exit_code, c.exit_code);
    EXPECT_TRUE(run.out.empty()) << run.out;
    json err = json::parse(run.err);
    EXPECT_NE(err["error"].get<std::string>().find(c.message), std::string::npos) << err;
  }
}

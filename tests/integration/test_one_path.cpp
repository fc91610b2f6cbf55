// Every way to render is one path: each example (and a furnished room of pieces, the catalogue's
// placed by ref and one inline, mirrored, with a transformed part) x pipeline x {flat, phong +
// shadow maps, phong + shadow rays} at 96x72 is drawn over HTTP (inline POST /v1/render, stored POST
// /v1/scenes/{id}/render, GET .../render.png with the view as query parameters) and by the built `roomrender render`,
// and the four PNGs must be byte-identical. The stage names must agree too: the JSON answer's timings_ms keys,
// Server-Timing's names and the CLI line's timings_ms keys are all stage_table, in its order.
#include "integration/server_fixture.hpp"
#include "render/core/frame.hpp"
#include "render/pipelines/pipeline.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

namespace {

using nlohmann::json;
using rr::testing::TestServer;
namespace fs = std::filesystem;

constexpr int frame_width = 96, frame_height = 72;  // small: the reference pipeline casts one ray per pixel

std::vector<std::string> stage_names() {
  std::vector<std::string> names;
  for (const rr::StageField& stage : rr::stage_table) names.emplace_back(stage.name);
  return names;
}

std::vector<std::string> server_timing_names(const std::string& header) {
  std::vector<std::string> names;
  size_t start = 0;
  while (start < header.size()) {
    size_t end = header.find(',', start);
    if (end == std::string::npos) end = header.size();
    std::string entry = header.substr(start, end - start);
    entry.erase(0, entry.find_first_not_of(' '));
    names.push_back(entry.substr(0, entry.find(';')));
    start = end + 1;
  }
  return names;
}

// The keys in the order the text has them (nlohmann::json would sort them).
std::vector<std::string> keys_of(const nlohmann::ordered_json& object) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : object.items()) keys.push_back(key);
  return keys;
}

// A JSON number or vector as a query value (shortest round-trip text, as nlohmann writes it).
std::string query_value(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (!value.is_array()) return value.dump();
  std::string text;
  for (const json& v : value) {
    if (!text.empty()) text.push_back(',');
    text.append(v.dump());
  }
  return text;
}

json camera_of(const json& request) { return request.contains("camera") ? request.at("camera") : json::object(); }

// The query string of GET .../render.png carrying the same view as `request`'s camera and options
// (docs/api.md names each parameter after its member).
std::string view_query(const json& request) {
  std::string query;
  auto add = [&](const std::string& name, const json& value) {
    query.push_back(query.empty() ? '?' : '&');
    query.append(name);
    query.push_back('=');
    query.append(query_value(value));  // digits, letters, '.', '-', ',': nothing to escape
  };
  const json camera = camera_of(request);
  for (auto it = camera.begin(); it != camera.end(); ++it) add(it.key(), it.value());
  for (const auto& [key, value] : request.at("options").items()) {
    if (key == "painter") {
      for (const auto& [k, v] : value.items()) add(std::string("painter_").append(k), v);
    } else if (key == "bsp" || key == "shadow") {
      for (const auto& [k, v] : value.items()) add(std::string(key).append("_").append(k), v);
    } else if (key == "png") {
      add("png", value.at("compression"));
    } else {
      add(key, value);
    }
  }
  return query;
}

// How a case is lit: flat without shadows, or phong with shadows of each options.shadow.method.
enum class Lit { flat, map, rays };

struct RenderCase {
  std::string example;
  std::string pipeline;
  Lit lit;
};

std::vector<RenderCase> render_cases() {
  std::vector<RenderCase> cases;
  std::vector<fs::path> examples;
  for (const auto& entry : fs::directory_iterator(fs::path(ROOMRENDER_SOURCE_DIR) / "examples")) {
    if (entry.path().extension() == ".json") examples.push_back(entry.path());
  }
  std::sort(examples.begin(), examples.end());
  std::vector<std::string> names;
  for (const fs::path& example : examples) names.push_back(example.stem().string());
  names.push_back("furnished_room");
  for (const std::string& name : names) {
    for (const rr::PipelineInfo& p : rr::pipeline_table()) {
      for (Lit lit : {Lit::flat, Lit::map, Lit::rays}) cases.push_back({name, p.name, lit});
    }
  }
  return cases;
}

// A room furnished with pieces: three of the server's catalogue (their parts placing its read-only
// meshes by ref, which the CLI resolves from the same files), one mirrored, and one inline piece
// whose second part has a transform.
json furnished_room(const json& catalogue) {
  json solids = json::array();
  const std::vector<std::tuple<std::string, double, double, double, bool>> placed = {
      {"table", 0.0, 0.0, 0.0, false}, {"chair", -0.55, 0.1, 90.0, false}, {"sofa", 0.2, -1.3, 0.0, true}};
  for (const auto& [id, x, z, turn, mirrored] : placed) {
    for (const json& item : catalogue.at("items")) {
      if (item.at("id") != id) continue;
      json piece = item.at("piece");
      piece["center"] = {x, z};
      piece["rotation_y"] = turn;
      if (mirrored) piece["mirrored"] = true;
      solids.push_back(piece);
    }
  }
  const json cube = rr::testing::unit_cube_mesh();
  json lid = cube;
  lid["color"] = "#c04040";
  lid["transform"] = {{1, 0, 0.2, 0}, {0, 0.2, 0, 0.4}, {0, 0, 0.8, 0.1}};
  solids.push_back({{"type", "piece"},
                    {"id", "chest"},
                    {"center", {1.2, 0.8}},
                    {"size", {0.6, 0.5, 0.4}},
                    {"rotation_y", 30},
                    {"mirrored", true},
                    {"parts", {cube, lid}}});
  return {{"scene",
           {{"floor", {{"cells", {4, 4}}, {"origin", {-2, -2}}}},
            {"walls", {{{"start", {-2, -2}}, {"end", {2, -2}}}}},
            {"solids", solids},
            {"lights", {{{"type", "directional"}, {"direction", {-0.3, -1, -0.4}}}}}}},
          {"camera", {{"position", {2.5, 2.2, 3}}, {"target", {0, 0.4, -0.3}}}},
          {"options", json::object()}};
}

json case_request(const RenderCase& c, const json& furnished) {
  json request =
      c.example == "furnished_room"
          ? furnished
          : json::parse(rr::testing::read_file(fs::path(ROOMRENDER_SOURCE_DIR) / "examples" / (c.example + ".json")));
  json& options = request["options"];
  if (options.is_null()) options = json::object();
  options["width"] = frame_width;
  options["height"] = frame_height;
  options["pipeline"] = c.pipeline;
  options["shading"] = c.lit != Lit::flat ? "phong" : "flat";
  options["shadows"] = c.lit != Lit::flat;
  if (c.lit == Lit::rays) options["shadow"]["method"] = "rays";
  return request;
}

struct CliRender {
  std::string png;
  nlohmann::ordered_json line;
};

CliRender render_with_cli(const json& request, const fs::path& dir) {
  rr::testing::write_file(dir / "request.json", request.dump());
  std::string command = "cd '" + dir.string() +
                        "' && '" ROOMRENDER_BINARY_DIR
                        "/roomrender' render request.json -o out.png >line.json 2>err.txt";
  int status = std::system(command.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << rr::testing::read_file(dir / "err.txt");
  return {rr::testing::read_file(dir / "out.png"),
          nlohmann::ordered_json::parse(rr::testing::read_file(dir / "line.json"))};
}

TEST(OnePath, EveryExamplePipelineAndShadingGivesTheSameBytesEverywhere) {
  TestServer server;
  httplib::Client client = server.client(120);
  const fs::path dir = rr::testing::output_dir("integration") / "one_path";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::vector<std::string> stages = stage_names();
  auto catalogue = client.Get("/v1/catalogue");
  ASSERT_TRUE(catalogue);
  const json furnished = furnished_room(json::parse(catalogue->body));
  ASSERT_EQ(furnished["scene"]["solids"].size(), 4u) << "the catalogue has a table, a chair and a sofa";
  size_t compared = 0;
  for (const RenderCase& c : render_cases()) {
    SCOPED_TRACE(c.example + " " + c.pipeline +
                 (c.lit == Lit::rays  ? " phong+shadow rays"
                  : c.lit == Lit::map ? " phong+shadow maps"
                                      : " flat"));
    const json request = case_request(c, furnished);
    const json view = {{"camera", camera_of(request)}, {"options", request.at("options")}};

    auto inline_png = client.Post("/v1/render", request.dump(), "application/json");
    ASSERT_TRUE(inline_png);
    ASSERT_EQ(inline_png->status, 200) << inline_png->body;
    EXPECT_EQ(server_timing_names(inline_png->get_header_value("Server-Timing")), stages);

    httplib::Headers want_json = {{"Accept", "application/json"}};
    auto inline_json = client.Post("/v1/render", want_json, request.dump(), "application/json");
    ASSERT_TRUE(inline_json);
    ASSERT_EQ(inline_json->status, 200) << inline_json->body;
    const auto answer = nlohmann::ordered_json::parse(inline_json->body);
    EXPECT_EQ(keys_of(answer.at("timings_ms")), stages);
    EXPECT_EQ(rr::testing::base64_decode(answer.at("png_base64").get<std::string>()), inline_png->body);

    auto stored = client.Post("/v1/scenes", request.at("scene").dump(), "application/json");
    ASSERT_TRUE(stored);
    ASSERT_TRUE(stored->status == 200 || stored->status == 201) << stored->body;
    const std::string location = json::parse(stored->body).at("location");
    auto stored_png = client.Post(location + "/render", view.dump(), "application/json");
    ASSERT_TRUE(stored_png);
    ASSERT_EQ(stored_png->status, 200) << stored_png->body;
    EXPECT_EQ(server_timing_names(stored_png->get_header_value("Server-Timing")), stages);

    auto got_png = client.Get(location + "/render.png" + view_query(request));
    ASSERT_TRUE(got_png);
    ASSERT_EQ(got_png->status, 200) << got_png->body;
    EXPECT_EQ(server_timing_names(got_png->get_header_value("Server-Timing")), stages);

    const CliRender cli = render_with_cli(request, dir);
    EXPECT_EQ(keys_of(cli.line.at("timings_ms")), stages);

    EXPECT_EQ(inline_png->body.size(), cli.png.size());
    EXPECT_TRUE(inline_png->body == cli.png) << "inline POST and CLI differ";
    EXPECT_TRUE(stored_png->body == cli.png) << "stored POST and CLI differ";
    EXPECT_TRUE(got_png->body == cli.png) << "GET render.png and CLI differ";
    ++compared;
  }
  EXPECT_GE(compared, 13u * 4u * 3u);
}

// The png query parameter selects the encoder as options.png.compression does in a body.
TEST(OnePath, PngQueryParameterSelectsTheEncoder) {
  TestServer server;
  httplib::Client client = server.client();
  json request = case_request({"studio", "zbuffer", Lit::flat}, json());
  auto stored = client.Post("/v1/scenes", request.at("scene").dump(), "application/json");
  ASSERT_TRUE(stored);
  const std::string location = json::parse(stored->body).at("location");
  std::vector<size_t> sizes;
  for (const char* mode : {"fast", "small", "none"}) {
    request["options"]["png"] = {{"compression", mode}};
    auto got = client.Get(location + "/render.png" + view_query(request));
    ASSERT_TRUE(got);
    ASSERT_EQ(got->status, 200) << got->body;
    auto posted =
        client.Post(location + "/render", json{{"camera", request["camera"]}, {"options", request["options"]}}.dump(),
                    "application/json");
    ASSERT_TRUE(posted);
    EXPECT_TRUE(got->body == posted->body) << mode;
    sizes.push_back(got->body.size());
  }
  EXPECT_LT(sizes[1], sizes[0]) << "small is smaller than fast";
  EXPECT_GT(sizes[2], sizes[0]) << "none stores the rows uncompressed";
  auto bad = client.Get(location + "/render.png?png=tiny");
  rr::testing::expect_problem(bad, 422);
}

}  // namespace

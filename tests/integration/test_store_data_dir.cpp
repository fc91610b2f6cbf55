// A data directory written by an earlier server (tests/fixtures/data-dir-v1, see its README) loads
// unchanged: every stored id still resolves to the same canonical text and renders, storing the same
// content again answers the same id, and start-up neither skips nor rewrites a file. Stored ids are
// public and persisted (file names, URLs, ETags), so this must hold across every release.
#include "server_fixture.hpp"

#include <filesystem>
#include <map>

namespace {

using nlohmann::json;
using namespace rr::testing;
namespace fs = std::filesystem;

// id -> file content, for every scenes/{id}.json of `dir`.
std::map<std::string, std::string> scene_files(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::directory_iterator(dir / "scenes")) {
    files[entry.path().stem().string()] = read_file(entry.path());
  }
  return files;
}

TEST(StoreDataDir, DataDirWrittenBeforeLoadsAndEveryIdResolves) {
  const fs::path fixture = source_dir() / "tests" / "fixtures" / "data-dir-v1";
  const std::map<std::string, std::string> stored = scene_files(fixture);
  ASSERT_EQ(stored.size(), 4u) << "the fixture holds four scenes";
  fs::path dir = fresh_output_dir();
  fs::copy(fixture, dir, fs::copy_options::recursive);

  rr::server::ServerConfig config = test_server_config();
  config.data_dir = dir;
  LogCapture log;
  config.log_level = "warn";
  config.log_sink = log.sink();
  TestServer server(config);
  for (const json& line : log.lines()) {
    EXPECT_FALSE(line.value("event", "").starts_with("scene_")) << "start-up warned: " << line.dump();
  }

  for (const auto& [id, text] : stored) {
    SCOPED_TRACE(id);
    auto got = server.client().Get(("/v1/scenes/" + id).c_str());
    ASSERT_TRUE(got);
    ASSERT_EQ(got->status, 200) << got->body;
    EXPECT_EQ(got->body, text);
    EXPECT_EQ(got->get_header_value("ETag"), "\"" + id + "\"");

    auto png = server.client().Get(("/v1/scenes/" + id + "/render.png?width=64&height=48").c_str());
    ASSERT_TRUE(png);
    ASSERT_EQ(png->status, 200) << png->body;
    EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
    EXPECT_EQ(png_size(png->body).width, 64u);
    EXPECT_EQ(png_size(png->body).height, 48u);

    // The same content, spelt with whitespace: already stored under the same id.
    auto again = server.client().Post("/v1/scenes", json::parse(text).dump(2), "application/json");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200) << again->body;
    EXPECT_EQ(json::parse(again->body).value("id", ""), id);
  }
  EXPECT_EQ(scene_files(dir), stored) << "loading and re-storing must leave the files as they were";
}

}  // namespace

// A user's homes are kept: furnished Sweet Home 3D homes (support/sweet_homes.hpp, the nine homes
// and copies moved apart) stored over HTTP on a server with a data directory and otherwise default
// budgets all answer 201, draw, and draw the same bytes after a restart; and the prepared cache's
// evictions are invisible: with room for two homes, ten drawn in turn twice over draw what they drew
// when each was prepared at store time, while /metrics counts the rebuilds and evictions. Not in the
// sanitizer run (test-sanitizers.sh selects other suites): tens of tessellations of 200k-polygon
// homes take minutes under ASan.
#include "integration/server_fixture.hpp"
#include "integration/stored_homes.hpp"
#include "support/sweet_homes.hpp"

#include <algorithm>
#include <cstdio>
#include <set>

namespace {

using namespace rr::testing;
namespace fs = std::filesystem;

rr::server::ServerConfig data_dir_config(const fs::path& dir) {
  rr::server::ServerConfig config = test_server_config();
  config.data_dir = dir;
  // A rebuild of the largest home (218k polygons) on a machine loaded by parallel tests; the
  // deadline is not what this test is about.
  config.render_timeout_ms = 60'000;
  return config;
}

TEST(StoredHomes, ThirtyFurnishedHomesAreKeptAcrossARestart) {
  if (sweet_home_files().empty()) GTEST_SKIP() << "../shared/data is absent";
  expect_homes_kept_across_restart(data_dir_config(fresh_output_dir("store")), 30);
}

TEST(StoredHomes, EvictionIsInvisible) {
  if (sweet_home_files().empty()) GTEST_SKIP() << "../shared/data is absent";
  constexpr size_t count = 10;
  const fs::path dir = fresh_output_dir("store");
  rr::server::ServerConfig config = data_dir_config(dir);
  std::vector<StoredHome> homes;
  std::vector<std::string> first;  // drawn from the scene prepared when it was stored
  double largest = 0.0;            // bytes of the largest prepared home
  {
    TestServer server(config);
    auto client = server.client(120);
    for (size_t i = 0; i < count; ++i) {
      const double before = server.metric("roomrender_cache_bytes", {"cache=\"scenes\""});
      homes.push_back(store_home(client, i));
      ASSERT_EQ(homes.back().status, 201);
      largest = std::max(largest, server.metric("roomrender_cache_bytes", {"cache=\"scenes\""}) - before);
      first.push_back(draw_home(client, homes.back()));
    }
    EXPECT_EQ(server.metric("roomrender_cache_evictions_total", {"cache=\"all\""}), 0.0);
  }
  ASSERT_GT(largest, 0.0);
  config.cache_bytes = size_t(2 * largest);
  TestServer server(config);
  auto client = server.client(120);
  for (int round = 0; round < 2; ++round) {
    for (size_t i = 0; i < count; ++i) {
      EXPECT_EQ(draw_home(client, homes[i]), first[i]) << homes[i].name << " in round " << round + 1;
    }
  }
  // Ten homes in turn through room for two: each draw rebuilt its home, and made room by evicting.
  const double builds = server.metric("roomrender_cache_builds_total", {"cache=\"scenes\""});
  const double evictions = server.metric("roomrender_cache_evictions_total", {"cache=\"scenes\""});
  EXPECT_EQ(builds, 2.0 * count);
  EXPECT_GE(evictions, double(count));
  EXPECT_LE(server.metric("roomrender_cache_bytes", {"cache=\"all\""}), double(config.cache_bytes));
  std::printf(
      "[ evict ] cache of %zu B (two of the largest home): %.0f rebuilds, %.0f scenes and %.0f meshes evicted\n",
      config.cache_bytes, builds, evictions, server.metric("roomrender_cache_evictions_total", {"cache=\"meshes\""}));
}

}  // namespace

// Stored homes over HTTP (stored_homes.hpp).
#include "stored_homes.hpp"

#include "server_fixture.hpp"
#include "support/sweet_homes.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <set>
#include <thread>

namespace rr::testing {

using nlohmann::json;

StoredHome store_home(httplib::Client& client, size_t i) {
  DistinctHome home = distinct_sweet_home(i);
  StoredHome out;
  out.name = home.name;
  auto res = client.Post("/v1/import/sh3d?store=1&width=96&height=72", home.zip, "application/zip");
  if (!res) {
    ADD_FAILURE() << home.name << ": " << httplib::to_string(res.error());
    return out;
  }
  out.status = res->status;
  if (res->status != 201) {
    ADD_FAILURE() << home.name << ": " << res->status << " " << res->body.substr(0, 400);
    return out;
  }
  const json receipt = json::parse(res->body);
  out.location = receipt["location"];
  out.camera = receipt["camera"];
  return out;
}

std::string draw_home(httplib::Client& client, const StoredHome& home, int width, int height) {
  const json view = {{"camera", home.camera}, {"options", {{"width", width}, {"height", height}}}};
  auto res = client.Post((home.location + "/render").c_str(), view.dump(), "application/json");
  if (!res || res->status != 200) {
    ADD_FAILURE() << home.name << " " << home.location << ": "
                  << (res ? std::to_string(res->status) + " " + res->body.substr(0, 300)
                          : httplib::to_string(res.error()));
    return "";
  }
  const PngSize size = png_size(res->body);
  if (size.width != uint32_t(width) || size.height != uint32_t(height)) {
    ADD_FAILURE() << home.name << ": a " << size.width << "x" << size.height << " PNG";
    return "";
  }
  return res->body;
}

std::vector<StoredHome> store_homes(std::vector<httplib::Client*> clients, size_t count) {
  std::vector<StoredHome> homes(count);
  std::vector<std::thread> threads;
  for (size_t c = 0; c < clients.size(); ++c) {
    threads.emplace_back([&, c] {
      for (size_t i = c; i < count; i += clients.size()) homes[i] = store_home(*clients[c], i);
    });
  }
  for (std::thread& t : threads) t.join();
  return homes;
}

void expect_homes_kept_across_restart(const rr::server::ServerConfig& config, size_t count) {
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  std::vector<StoredHome> homes;
  std::vector<std::string> drawn(count);
  {
    TestServer server(config);
    httplib::Client a = server.client(120), b = server.client(120);
    homes = store_homes({&a, &b}, count);
    std::printf("[ homes ] %zu stored in %.1f s\n", count, seconds());
    std::set<std::string> locations;
    for (const StoredHome& home : homes) {
      ASSERT_EQ(home.status, 201) << home.name;
      locations.insert(home.location);
    }
    EXPECT_EQ(locations.size(), count);
    for (size_t i = 0; i < count; ++i) drawn[i] = draw_home(a, homes[i]);
    EXPECT_EQ(server.metric("roomrender_store_entries", {"store=\"scenes\""}), double(count));
    std::printf("[ homes ] documents: %.0f B of scenes, %.0f B of meshes; prepared cache %.0f B; %.1f s\n",
                server.metric("roomrender_store_bytes", {"store=\"scenes\""}),
                server.metric("roomrender_store_bytes", {"store=\"meshes\""}),
                server.metric("roomrender_cache_bytes", {"cache=\"all\""}), seconds());
  }
  TestServer restarted(config);
  auto client = restarted.client(120);
  for (size_t i = 0; i < count; ++i) {
    auto document = client.Get(homes[i].location.c_str());
    ASSERT_TRUE(document);
    EXPECT_EQ(document->status, 200) << homes[i].name;
    EXPECT_EQ(draw_home(client, homes[i]), drawn[i]) << homes[i].name << " draws otherwise after the restart";
  }
  EXPECT_EQ(restarted.metric("roomrender_cache_builds_total", {"cache=\"scenes\""}), double(count));
  std::printf("[ homes ] %zu kept and drawn again after a restart; %.1f s in all\n", count, seconds());
}

}  // namespace rr::testing

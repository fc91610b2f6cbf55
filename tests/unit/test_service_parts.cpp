// The service's pure parts on exact fixtures: Accept negotiation and If-None-Match matching
// (RFC 9110), base64 against RFC 4648's test vectors, the render gate's admission order, bounds and
// deadlines, the Prometheus text of a histogram, the LRU cache's eviction listener, and the
// placement checks on hand-placed boxes.
#include "render/core/lru_cache.hpp"
#include "render/core/placement.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/http_util.hpp"
#include "server/metrics.hpp"
#include "server/render_gate.hpp"
#include "server/scene_store.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>

namespace {

using namespace rr::server;
using namespace std::chrono_literals;

TEST(Negotiate, PicksTheBestOfferedTypeByQValueThenServerOrder) {
  const std::vector<std::string> offered = {"image/png", "application/json"};
  EXPECT_EQ(negotiate("", offered), "image/png");
  EXPECT_EQ(negotiate("*/*", offered), "image/png");
  EXPECT_EQ(negotiate("application/json", offered), "application/json");
  EXPECT_EQ(negotiate("application/*", offered), "application/json");
  EXPECT_EQ(negotiate("image/png;q=0.4, application/json;q=0.5", offered), "application/json");
  EXPECT_EQ(negotiate("*/*;q=0.1, image/png;q=0", offered), "application/json") << "the specific range wins";
  EXPECT_EQ(negotiate("APPLICATION/JSON", offered), "application/json");
  EXPECT_EQ(negotiate("text/html", offered), std::nullopt);
  EXPECT_EQ(negotiate("image/png;q=0", offered), std::nullopt);
  EXPECT_EQ(negotiate("image/png;q=abc", offered), "image/png") << "an unreadable q counts as 1";
}

TEST(IfNoneMatch, WeakComparisonOverAList) {
  EXPECT_TRUE(if_none_match_matches("\"abc\"", "\"abc\""));
  EXPECT_TRUE(if_none_match_matches("W/\"abc\"", "\"abc\""));
  EXPECT_TRUE(if_none_match_matches("\"x\", \"abc\"", "\"abc\""));
  EXPECT_TRUE(if_none_match_matches("*", "\"abc\""));
  EXPECT_FALSE(if_none_match_matches("\"abd\"", "\"abc\""));
  EXPECT_FALSE(if_none_match_matches("abc", "\"abc\"")) << "quotes are part of the tag";
  EXPECT_FALSE(if_none_match_matches("", "\"abc\""));
}

TEST(Base64, Rfc4648TestVectors) {
  EXPECT_EQ(base64_encode(""), "");
  EXPECT_EQ(base64_encode("f"), "Zg==");
  EXPECT_EQ(base64_encode("fo"), "Zm8=");
  EXPECT_EQ(base64_encode("foo"), "Zm9v");
  EXPECT_EQ(base64_encode("foob"), "Zm9vYg==");
  EXPECT_EQ(base64_encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64_encode(std::string("\xff\xfe\x00", 3)), "//4A");
}

TEST(HashHex, IsFnv1a64) {
  EXPECT_EQ(hash_hex(""), "cbf29ce484222325");   // the offset basis
  EXPECT_EQ(hash_hex("a"), "af63dc4c8601ec8c");  // published FNV-1a test vector
}

// A token whose deadline is `budget` from now (tokens hold an atomic, so they are built in place).
struct Token : rr::CancelToken {
  explicit Token(std::chrono::milliseconds budget) { deadline = std::chrono::steady_clock::now() + budget; }
};

TEST(RenderGate, AdmitsUpToConcurrencyQueuesUpToTheLimitAndRefusesBeyond) {
  RenderGate gate(1, 1);
  Token first(5s);
  ASSERT_EQ(gate.enter(first), RenderGate::Admission::admitted);
  Token second(5s);
  auto waiting = std::async(std::launch::async, [&] { return gate.enter(second); });
  while (gate.load().queued == 0) std::this_thread::sleep_for(1ms);
  Token third(5s);
  EXPECT_EQ(gate.enter(third), RenderGate::Admission::saturated);
  EXPECT_TRUE(gate.load().saturated());
  gate.leave(first);
  EXPECT_EQ(waiting.get(), RenderGate::Admission::admitted);
  EXPECT_EQ(gate.load().running, 1u);
  gate.leave(second);
  EXPECT_EQ(gate.load().running, 0u);
}

TEST(RenderGate, AdmitsInArrivalOrder) {
  RenderGate gate(1, 8);
  Token holder(5s);
  ASSERT_EQ(gate.enter(holder), RenderGate::Admission::admitted);
  std::vector<rr::CancelToken> tokens(4);
  std::vector<int> order;
  std::mutex order_mutex;
  std::vector<std::thread> waiters;
  for (int i = 0; i < 4; ++i) {
    tokens[size_t(i)].deadline = std::chrono::steady_clock::now() + 5s;
    waiters.emplace_back([&, i] {
      EXPECT_EQ(gate.enter(tokens[size_t(i)]), RenderGate::Admission::admitted);
      {
        std::lock_guard lock(order_mutex);
        order.push_back(i);
      }
      gate.leave(tokens[size_t(i)]);
    });
    while (gate.load().queued != size_t(i) + 1) std::this_thread::sleep_for(1ms);  // arrive one by one
  }
  gate.leave(holder);
  for (std::thread& t : waiters) t.join();
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3}));
}

TEST(RenderGate, QueuedWorkExpiresAtItsDeadlineAndAbortCancelsRunningWork) {
  RenderGate gate(1, 1);
  Token running(5s);
  ASSERT_EQ(gate.enter(running), RenderGate::Admission::admitted);
  Token late(30ms);
  EXPECT_EQ(gate.enter(late), RenderGate::Admission::expired);
  EXPECT_EQ(gate.load().queued, 0u);
  gate.close();
  Token after_close(5s);
  EXPECT_EQ(gate.enter(after_close), RenderGate::Admission::closed);
  EXPECT_FALSE(gate.wait_idle(std::chrono::steady_clock::now() + 10ms));
  gate.abort();
  EXPECT_TRUE(running.expired()) << "abort cancels what runs";
  gate.leave(running);
  EXPECT_TRUE(gate.wait_idle(std::chrono::steady_clock::now() + 10ms));
}

TEST(Metrics, HistogramIsCumulativeWithSumAndCount) {
  Metrics metrics;
  // Binary fractions, so the sum prints exactly.
  metrics.record_request("/v1/render", "POST", 200, 0.00390625);
  metrics.record_request("/v1/render", "POST", 200, 0.25);
  metrics.record_request("/v1/render", "POST", 422, 20.0);
  std::string text = metrics.prometheus_text({});
  EXPECT_NE(text.find("roomrender_http_requests_total{route=\"/v1/render\",method=\"POST\",status=\"200\"} 2\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"0.0025\"} 0\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"0.005\"} 1\n"),
            std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"10\"} 2\n"),
            std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"+Inf\"} 3\n"),
            std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_count{route=\"/v1/render\"} 3\n"), std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_sum{route=\"/v1/render\"} 20.25390625\n"),
            std::string::npos);
}

TEST(LruCacheEvictionListener, HearsEvictionsButNotErasesOrReplacements) {
  rr::SharedLruCache<int> cache(20);
  std::vector<std::string> evicted;
  cache.set_eviction_listener([&](const std::string& key) { evicted.push_back(key); });
  cache.put("a", std::make_shared<const int>(1), 10);
  cache.put("b", std::make_shared<const int>(2), 10);
  cache.put("b", std::make_shared<const int>(3), 10);  // replacement
  cache.erase("b");
  EXPECT_TRUE(evicted.empty());
  cache.put("c", std::make_shared<const int>(4), 10);
  cache.put("d", std::make_shared<const int>(5), 10);  // evicts a
  bool hit = false;
  cache.get_or_build(
      "e",
      [] {
        return rr::SharedLruCache<int>::Built{std::make_shared<const int>(6), 10};
      },
      hit);
  EXPECT_EQ(evicted, (std::vector<std::string>{"a", "c"}));
}

// Two contents under one id (as a crafted FNV-1a collision would give) are refused, never merged.
TEST(SceneStore, SameIdWithOtherContentIsAConflict) {
  SceneStore store({}, [](const std::string&, nlohmann::ordered_json) {});
  auto scene = [](const std::string& text) {
    auto s = std::make_shared<StoredScene>();
    s->id = "0123456789abcdef";
    s->text = text;
    s->bytes = 100;
    return std::shared_ptr<const StoredScene>(s);
  };
  EXPECT_EQ(store.put(scene("{\"walls\":[]}"), ""), SceneStore::PutResult::created);
  EXPECT_EQ(store.put(scene("{\"walls\":[]}"), ""), SceneStore::PutResult::existed);
  EXPECT_EQ(store.put(scene("{\"solids\":[]}"), ""), SceneStore::PutResult::conflict);
  EXPECT_EQ(store.find("0123456789abcdef")->text, "{\"walls\":[]}");
}

// A scene stored by two owners stays until both dropped their reference; a full store refuses
// rather than evicts.
TEST(SceneStore, ReferencesPerOwnerAndNoEviction) {
  SceneStoreConfig config;
  config.max_entries = 1;
  SceneStore store(config, [](const std::string&, nlohmann::ordered_json) {});
  auto scene = [](const std::string& id) {
    auto s = std::make_shared<StoredScene>();
    s->id = id;
    s->text = "{}";
    s->bytes = 100;
    return std::shared_ptr<const StoredScene>(s);
  };
  EXPECT_EQ(store.put(scene("0000000000000001"), "a"), SceneStore::PutResult::created);
  EXPECT_EQ(store.put(scene("0000000000000001"), "b"), SceneStore::PutResult::existed);
  EXPECT_EQ(store.put(scene("0000000000000002"), "a"), SceneStore::PutResult::full);
  EXPECT_EQ(store.release("0000000000000001", "c"), SceneStore::ReleaseResult::not_owner);
  EXPECT_EQ(store.release("0000000000000001", "a"), SceneStore::ReleaseResult::reference_dropped);
  EXPECT_EQ(store.release("0000000000000001", "a"), SceneStore::ReleaseResult::not_owner);
  ASSERT_TRUE(store.find("0000000000000001"));
  EXPECT_EQ(store.release("0000000000000001", "b"), SceneStore::ReleaseResult::removed);
  EXPECT_FALSE(store.find("0000000000000001"));
  EXPECT_EQ(store.put(scene("0000000000000002"), "a"), SceneStore::PutResult::created);
  EXPECT_EQ(store.release("0000000000000002", std::nullopt), SceneStore::ReleaseResult::removed);
}

std::vector<rr::WarningText> warnings_for(const std::string& scene_json) {
  rr::RenderRequest request = rr::parse_request("{\"scene\": " + scene_json + "}");
  rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  return rr::describe(rr::placement_warnings(request.scene, soup), request.scene);
}

TEST(Placement, OverlappingSolidsWarnTouchingOnesDoNot) {
  auto warnings = warnings_for(R"({"solids": [
      {"type": "box", "center": [0, 0], "size": [1, 1, 1]},
      {"type": "box", "center": [1, 0], "size": [1, 1, 1]},
      {"type": "box", "center": [0, 0.9], "size": [1, 1, 1], "id": "b"},
      {"type": "box", "center": [5, 5], "base": 2, "size": [1, 1, 1]},
      {"type": "box", "center": [5, 5], "size": [1, 1, 1]}]})");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].pointer, "/scene/solids/2");
  EXPECT_EQ(warnings[0].detail, "solid intersects solid /scene/solids/0");
}

TEST(Placement, SolidThroughAWallAndBeyondTheFloor) {
  auto warnings = warnings_for(R"({"floor": {"cells": [4, 4]},
      "walls": [{"start": [0, 2], "end": [4, 2]}],
      "solids": [{"type": "cylinder", "center": [1, 2.05], "radius": 0.3, "height": 1, "id": "pillar"},
                 {"type": "box", "center": [3.6, 0.5], "size": [1, 1, 1]},
                 {"type": "box", "center": [3, 3], "size": [1, 1, 1]}]})");
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].pointer, "/scene/solids/1");
  EXPECT_EQ(warnings[0].detail, "solid reaches 0.1 m beyond the floor's edge");
  EXPECT_EQ(warnings[1].pointer, "/scene/solids/0");
  EXPECT_EQ(warnings[1].detail, "solid intersects wall /scene/walls/0");
}

TEST(Placement, OpeningsTooCloseToAWallEndOrEachOther) {
  auto warnings = warnings_for(R"({"walls": [{"start": [0, 0], "end": [5, 0], "openings": [
      {"type": "door", "offset": 0.04, "width": 0.9},
      {"type": "window", "offset": 0.97, "width": 1},
      {"type": "window", "offset": 3, "width": 1.97}]}]})");
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_EQ(warnings[0].pointer, "/scene/walls/0/openings/0");
  EXPECT_EQ(warnings[0].detail, "opening is 0.04 m from its wall's start (less than 0.05 m)");
  EXPECT_EQ(warnings[1].pointer, "/scene/walls/0/openings/1");
  EXPECT_EQ(warnings[1].detail, "opening is 0.03 m from opening /scene/walls/0/openings/0 (less than 0.05 m)");
  EXPECT_EQ(warnings[2].pointer, "/scene/walls/0/openings/2");
  EXPECT_EQ(warnings[2].detail, "opening is 0.03 m from its wall's end (less than 0.05 m)");
}

TEST(Placement, WarningsAreCappedWithASummary) {
  std::string solids;
  for (int i = 0; i < 20; ++i)
    solids += std::string(i ? "," : "") + R"({"type": "box", "center": [0, 0], "size": [1, 1, 1]})";
  rr::RenderRequest request = rr::parse_request("{\"scene\": {\"solids\": [" + solids + "]}}");
  rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  rr::PlacementLimits limits;
  limits.max_warnings = 5;
  auto warnings = rr::describe(rr::placement_warnings(request.scene, soup, limits), request.scene);
  ASSERT_EQ(warnings.size(), 6u);
  EXPECT_EQ(warnings.back().pointer, "/scene");
  EXPECT_EQ(warnings.back().detail, "placement checks found more problems; 185 further warning(s) not listed");
}

// The same warnings name elements relative to where the scene sits: a stored scene document is the
// scene itself, so its pointers have no "/scene" prefix.
TEST(Placement, PointersFollowTheDocumentThatHoldsTheScene) {
  rr::RenderRequest request =
      rr::parse_request(R"({"scene": {"walls": [{"start": [0, 0], "end": [4, 0], "id": "north"}],
      "solids": [{"type": "box", "center": [1, 0], "size": [1, 1, 1]}]}})");
  rr::PolygonSoup soup = rr::tessellate(request.scene.geometry);
  auto typed = rr::placement_warnings(request.scene, soup);
  ASSERT_EQ(typed.size(), 1u);
  EXPECT_EQ(typed[0].issue, rr::PlacementIssue::intersects);
  EXPECT_EQ(typed[0].element, rr::ElementRef::solid(0));
  EXPECT_EQ(typed[0].other, rr::ElementRef::wall(0));
  rr::WarningText stored = rr::describe(typed[0], request.scene, "");
  EXPECT_EQ(stored.pointer, "/solids/0");
  EXPECT_EQ(stored.detail, "solid intersects wall /walls/0 (\"north\")");
}

}  // namespace

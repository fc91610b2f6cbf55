// SharedLruCache: LRU order under the byte budget and entry count, single-flight builds under
// concurrency, failed builds that cache nothing, and an eviction listener that hears evictions only.
#include "render/core/lru_cache.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace rr {
namespace {

using Cache = SharedLruCache<int>;

Cache::Built make(int v, size_t bytes) { return {std::make_shared<const int>(v), bytes}; }

TEST(LruCache, SecondLookupIsAHitAndBuildsNothing) {
  Cache cache(100);
  int builds = 0;
  bool hit = true;
  auto a = cache.get_or_build(
      "k",
      [&] {
        ++builds;
        return make(7, 10);
      },
      hit);
  EXPECT_FALSE(hit);
  auto b = cache.get_or_build(
      "k",
      [&] {
        ++builds;
        return make(8, 10);
      },
      hit);
  EXPECT_TRUE(hit);
  EXPECT_EQ(builds, 1);
  EXPECT_EQ(a.get(), b.get());
  CacheStats s = cache.stats();
  EXPECT_EQ(s.hits, 1u);
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.builds, 1u);
  EXPECT_EQ(s.bytes, 10u);
  EXPECT_EQ(s.entries, 1u);
}

TEST(LruCache, EvictsLeastRecentlyUsedToStayWithinBudget) {
  Cache cache(30);
  cache.put("a", std::make_shared<const int>(1), 10);
  cache.put("b", std::make_shared<const int>(2), 10);
  cache.put("c", std::make_shared<const int>(3), 10);
  ASSERT_NE(cache.find("a"), nullptr);  // a is now the most recent; b the least
  cache.put("d", std::make_shared<const int>(4), 10);
  EXPECT_EQ(cache.find("b"), nullptr);
  EXPECT_NE(cache.find("a"), nullptr);
  EXPECT_NE(cache.find("c"), nullptr);
  EXPECT_NE(cache.find("d"), nullptr);
  CacheStats s = cache.stats();
  EXPECT_EQ(s.evictions, 1u);
  EXPECT_EQ(s.bytes, 30u);
}

TEST(LruCache, EntryCountIsBoundedToo) {
  Cache cache(1000, 2);
  cache.put("a", std::make_shared<const int>(1), 1);
  cache.put("b", std::make_shared<const int>(2), 1);
  cache.put("c", std::make_shared<const int>(3), 1);
  EXPECT_EQ(cache.stats().entries, 2u);
  EXPECT_EQ(cache.find("a"), nullptr);
}

TEST(LruCache, ValueLargerThanBudgetIsReturnedButNotKept) {
  Cache cache(10);
  bool hit = false;
  auto v = cache.get_or_build(
      "big", [] { return make(5, 11); }, hit);
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(*v, 5);
  EXPECT_EQ(cache.stats().entries, 0u);
  EXPECT_EQ(cache.stats().bytes, 0u);
}

TEST(LruCache, ReplacingAKeyAccountsItsBytesOnce) {
  Cache cache(100);
  cache.put("a", std::make_shared<const int>(1), 40);
  cache.put("a", std::make_shared<const int>(2), 30);
  EXPECT_EQ(cache.stats().bytes, 30u);
  EXPECT_EQ(*cache.find("a"), 2);
  EXPECT_TRUE(cache.erase("a"));
  EXPECT_FALSE(cache.erase("a"));
  EXPECT_EQ(cache.stats().bytes, 0u);
}

TEST(LruCache, ConcurrentFirstLookupsBuildOnce) {
  Cache cache(100);
  std::atomic<int> builds{0};
  std::atomic<int> arrived{0};
  constexpr int kThreads = 8;
  std::vector<std::shared_ptr<const int>> results(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      ++arrived;
      while (arrived.load() < kThreads) std::this_thread::yield();
      bool hit = false;
      results[size_t(t)] = cache.get_or_build(
          "k",
          [&] {
            ++builds;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));  // keep the build in flight
            return make(42, 1);
          },
          hit);
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(builds.load(), 1);
  for (const auto& r : results) EXPECT_EQ(r.get(), results[0].get());
  EXPECT_EQ(cache.stats().builds, 1u);
}

TEST(LruCache, FailedBuildReachesEveryWaiterAndCachesNothing) {
  Cache cache(100);
  bool hit = false;
  EXPECT_THROW(cache.get_or_build(
                   "k", []() -> Cache::Built { throw std::runtime_error("no"); }, hit),
               std::runtime_error);
  EXPECT_EQ(cache.stats().entries, 0u);
  auto v = cache.get_or_build(
      "k", [] { return make(1, 1); }, hit);  // a later lookup builds again
  EXPECT_FALSE(hit);
  EXPECT_EQ(*v, 1);
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

}  // namespace
}  // namespace rr

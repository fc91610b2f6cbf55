// SharedLruCache: LRU order under the byte budget and entry count, single-flight builds under
// concurrency, failed builds that cache nothing, an eviction listener that hears evictions only, and
// caches of different value types sharing one CachePool: one budget, one recency order, caps per part.
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

// Two parts of one pool: whichever part stores, the least recently used entry of either goes, and
// each part counts its own evictions (the part that lost the entry, not the one that made room).
TEST(CachePool, PartsShareOneBudgetAndOneRecencyOrder) {
  auto pool = std::make_shared<CachePool>(30);
  SharedLruCache<int> numbers(pool);
  SharedLruCache<std::string> names(pool);
  numbers.put("1", std::make_shared<const int>(1), 10);
  names.put("one", std::make_shared<const std::string>("one"), 10);
  numbers.put("2", std::make_shared<const int>(2), 10);
  ASSERT_NE(numbers.find("1"), nullptr);  // order, least recent first: one, 2, 1
  names.put("two", std::make_shared<const std::string>("two"), 10);
  EXPECT_EQ(names.find("one"), nullptr);
  numbers.put("3", std::make_shared<const int>(3), 10);  // evicts 2 (then: 1, two, 3)
  EXPECT_EQ(numbers.find("2"), nullptr);
  EXPECT_EQ(*numbers.find("1"), 1);
  EXPECT_EQ(*names.find("two"), "two");
  EXPECT_EQ(numbers.stats().evictions, 1u);
  EXPECT_EQ(names.stats().evictions, 1u);
  EXPECT_EQ(numbers.stats().bytes, 20u);
  EXPECT_EQ(names.stats().bytes, 10u);
  EXPECT_EQ(numbers.stats().budget_bytes, 30u);
  const CacheStats all = pool->stats();
  EXPECT_EQ(all.bytes, 30u);
  EXPECT_EQ(all.entries, 3u);
  EXPECT_EQ(all.evictions, 2u);
  EXPECT_EQ(all.budget_bytes, 30u);
}

// A part's own caps make room among its own entries first, even when older entries of another part
// would go before them by recency alone; a part capped at 0 bytes keeps nothing.
TEST(CachePool, APartsCapsEvictItsOwnEntriesOnly) {
  auto pool = std::make_shared<CachePool>(100);
  SharedLruCache<int> big(pool);
  SharedLruCache<int> capped(pool, 2, 25);
  SharedLruCache<int> none(pool, CachePool::unbounded, 0);
  big.put("old", std::make_shared<const int>(0), 10);
  capped.put("a", std::make_shared<const int>(1), 10);
  capped.put("b", std::make_shared<const int>(2), 10);
  capped.put("c", std::make_shared<const int>(3), 10);  // the entry cap: a goes, old stays
  EXPECT_EQ(capped.find("a"), nullptr);
  EXPECT_NE(big.find("old"), nullptr);
  capped.put("d", std::make_shared<const int>(4), 16);  // the entry cap takes b, the byte cap (25) c
  EXPECT_EQ(capped.stats().entries, 1u);
  EXPECT_EQ(capped.stats().bytes, 16u);
  EXPECT_EQ(capped.stats().budget_bytes, 25u);
  EXPECT_EQ(capped.stats().evictions, 3u);
  EXPECT_EQ(big.stats().evictions, 0u);
  EXPECT_FALSE(none.put("x", std::make_shared<const int>(5), 1));
  EXPECT_EQ(none.stats().budget_bytes, 0u);
  EXPECT_EQ(pool->stats().bytes, 26u);
}

// A build in one part may look up another part of the same pool (a scene's build reads its
// meshes): the pool's lock is not held while building, and a build that passes the budget evicts
// what the nested build stored.
TEST(CachePool, ABuildMayUseAnotherPartOfItsPool) {
  auto pool = std::make_shared<CachePool>(25);
  SharedLruCache<int> meshes(pool);
  SharedLruCache<int> scenes(pool);
  bool hit = false;
  auto scene = scenes.get_or_build(
      "s",
      [&] {
        bool mesh_hit = false;
        auto mesh = meshes.get_or_build(
            "m",
            [] {
              return SharedLruCache<int>::Built{std::make_shared<const int>(2), 10};
            },
            mesh_hit);
        return SharedLruCache<int>::Built{std::make_shared<const int>(*mesh * 10), 20};
      },
      hit);
  EXPECT_EQ(*scene, 20);
  EXPECT_FALSE(meshes.contains("m"));
  EXPECT_TRUE(scenes.contains("s"));
  EXPECT_EQ(meshes.stats().evictions, 1u);
  EXPECT_EQ(pool->stats().builds, 2u);
}

}  // namespace
}  // namespace rr

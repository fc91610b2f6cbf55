// A thread-safe least-recently-used cache of immutable values shared across requests, bounded by a
// byte budget and an entry count, and single-flight: concurrent lookups of one missing key run its
// build once and all receive that result (or its exception). Used for BSP trees and shadow maps of
// static scenes (keyed by scene id + options) and for the service's prepared stored scenes.
//
// Several caches of different value types may share one CachePool: one byte budget and one recency
// order over all of them, so storing in any evicts the least recently used entry of all (a BSP tree
// may make room by evicting a prepared scene, and the other way round). Each cache may cap its own
// part of the pool further (entries, bytes). A cache made with a budget alone has a pool of its own.
//
// Values are handed out as shared_ptr<const V>, so an entry evicted while a render still uses it
// stays alive until that render ends; the budget bounds what the cache holds, not what is in use.
#pragma once

#include <algorithm>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace rr {

struct CacheStats {
  size_t hits = 0;
  size_t misses = 0;  // lookups that found nothing ready (they built, or waited for a build)
  size_t builds = 0;  // builds run (one per missing key however many requests wanted it)
  size_t evictions = 0;
  size_t bytes = 0;    // held now
  size_t entries = 0;  // held now
  size_t budget_bytes = 0;
  size_t max_entries = 0;
};

// The shared part: entries of every member cache, their byte total and one recency list. Members
// are added before the pool is shared between threads; values are type-erased here and typed again
// by SharedLruCache<V>, which alone knows a member's value type.
class CachePool {
 public:
  static constexpr size_t unbounded = std::numeric_limits<size_t>::max();
  explicit CachePool(size_t budget_bytes) : budget_bytes_(budget_bytes) {}
  CachePool(const CachePool&) = delete;
  CachePool& operator=(const CachePool&) = delete;

  size_t budget_bytes() const { return budget_bytes_; }
  // Every member together: their lookups, builds and evictions, what the pool holds, its budget.
  CacheStats stats() const {
    std::lock_guard lock(mutex_);
    CacheStats all;
    for (const Member& m : members_) {
      all.hits += m.stats.hits;
      all.misses += m.stats.misses;
      all.builds += m.stats.builds;
      all.evictions += m.stats.evictions;
      all.entries += m.entries.size();
    }
    all.bytes = bytes_;
    all.budget_bytes = budget_bytes_;
    all.max_entries = unbounded;
    return all;
  }

 private:
  template <class V>
  friend class SharedLruCache;
  using Value = std::shared_ptr<const void>;
  struct Node {
    size_t member = 0;
    std::string key;
  };
  struct Entry {
    Value value;
    size_t bytes = 0;
    std::list<Node>::iterator position;  // in recency_, most recent first
  };
  using Map = std::unordered_map<std::string, Entry>;
  struct Member {
    size_t max_entries = unbounded;
    size_t max_bytes = unbounded;
    Map entries;
    std::unordered_map<std::string, std::shared_future<Value>> pending;
    CacheStats stats;  // bytes: this member's part of bytes_
    std::function<void(const std::string& key)> eviction_listener;
  };
  using Evicted = std::vector<std::pair<size_t, std::string>>;  // member, key

  size_t add_member(size_t max_entries, size_t max_bytes) {
    std::lock_guard lock(mutex_);
    members_.push_back(Member{max_entries, max_bytes, {}, {}, {}, {}});
    return members_.size() - 1;
  }

  CacheStats member_stats(size_t member) const {
    std::lock_guard lock(mutex_);
    const Member& m = members_[member];
    CacheStats s = m.stats;
    s.entries = m.entries.size();
    s.budget_bytes = std::min(m.max_bytes, budget_bytes_);
    s.max_entries = m.max_entries;
    return s;
  }

  Value touch(Member& m, const std::string& key) {
    auto it = m.entries.find(key);
    if (it == m.entries.end()) return nullptr;
    recency_.splice(recency_.begin(), recency_, it->second.position);
    return it->second.value;
  }

  void remove_locked(Member& m, Map::iterator it) {
    m.stats.bytes -= it->second.bytes;
    bytes_ -= it->second.bytes;
    recency_.erase(it->second.position);
    m.entries.erase(it);
  }

  void evict_locked(std::list<Node>::iterator node, Evicted& evicted) {
    Member& owner = members_[node->member];
    if (owner.eviction_listener) evicted.emplace_back(node->member, node->key);
    ++owner.stats.evictions;
    remove_locked(owner, owner.entries.find(node->key));
  }

  // Keeps `value` unless it alone passes its member's caps or the pool's budget; evicts first the
  // member's own least recently used entries while the member would pass its caps, then the pool's
  // least recently used entries of any member while the pool would pass its budget.
  bool insert_locked(size_t member, const std::string& key, Value value, size_t bytes, Evicted& evicted) {
    Member& m = members_[member];
    if (auto old = m.entries.find(key); old != m.entries.end()) remove_locked(m, old);
    if (bytes > budget_bytes_ || bytes > m.max_bytes || m.max_entries == 0) return false;
    auto oldest_of_member = [&] {
      auto it = recency_.end();
      do --it;
      while (it->member != member);
      return it;
    };
    while (!m.entries.empty() && (m.entries.size() >= m.max_entries || m.stats.bytes + bytes > m.max_bytes)) {
      evict_locked(oldest_of_member(), evicted);
    }
    while (!recency_.empty() && bytes_ + bytes > budget_bytes_) evict_locked(std::prev(recency_.end()), evicted);
    recency_.push_front(Node{member, key});
    m.entries.emplace(key, Entry{std::move(value), bytes, recency_.begin()});
    m.stats.bytes += bytes;
    bytes_ += bytes;
    return true;
  }

  // Called after the lock is released, so a listener may call back into the pool.
  void notify_evicted(const Evicted& evicted) const {
    for (const auto& [member, key] : evicted) members_[member].eviction_listener(key);
  }

  mutable std::mutex mutex_;
  const size_t budget_bytes_;
  size_t bytes_ = 0;
  std::deque<Member> members_;  // a deque: members never move once added
  std::list<Node> recency_;
};

template <class V>
class SharedLruCache {
 public:
  using Ptr = std::shared_ptr<const V>;
  struct Built {
    Ptr value;
    size_t bytes = 0;  // what the value costs against the budget
  };

  // A cache with a pool of its own: `budget_bytes` and `max_entries` bound it alone.
  explicit SharedLruCache(size_t budget_bytes, size_t max_entries = CachePool::unbounded)
      : SharedLruCache(std::make_shared<CachePool>(budget_bytes), max_entries) {}
  // A part of `pool`, sharing its budget and recency order with the pool's other parts, holding at
  // most `max_entries` entries and `max_bytes` bytes of it.
  explicit SharedLruCache(std::shared_ptr<CachePool> pool, size_t max_entries = CachePool::unbounded,
                          size_t max_bytes = CachePool::unbounded)
      : pool_(std::move(pool)), member_(pool_->add_member(max_entries, max_bytes)) {}
  SharedLruCache(const SharedLruCache&) = delete;
  SharedLruCache& operator=(const SharedLruCache&) = delete;

  // Called with the key of each of this cache's entries evicted to make room (not for erase() or
  // replacement), after the pool's lock is released, so it may call back into the cache. Set it
  // before the cache is shared between threads.
  void set_eviction_listener(std::function<void(const std::string& key)> listener) {
    std::lock_guard lock(pool_->mutex_);
    member().eviction_listener = std::move(listener);
  }

  // The value for `key`, running `build` when it is absent (and no other caller is building it).
  // `hit` is set when the value was ready. A build that throws caches nothing; its exception
  // reaches this caller and every caller that waited for it. A value larger than the budget (the
  // pool's or this cache's own) is returned but not kept.
  Ptr get_or_build(const std::string& key, const std::function<Built()>& build, bool& hit) {
    std::unique_lock lock(pool_->mutex_);
    CachePool::Member& m = member();
    if (CachePool::Value ready = pool_->touch(m, key)) {
      ++m.stats.hits;
      hit = true;
      return std::static_pointer_cast<const V>(ready);
    }
    hit = false;
    ++m.stats.misses;
    if (auto pending = m.pending.find(key); pending != m.pending.end()) {
      std::shared_future<CachePool::Value> wait_for = pending->second;
      lock.unlock();
      return std::static_pointer_cast<const V>(wait_for.get());
    }
    std::promise<CachePool::Value> promise;
    m.pending.emplace(key, promise.get_future().share());
    ++m.stats.builds;
    lock.unlock();
    Built built;
    try {
      built = build();
    } catch (...) {
      lock.lock();
      m.pending.erase(key);
      promise.set_exception(std::current_exception());
      throw;
    }
    lock.lock();
    m.pending.erase(key);
    CachePool::Evicted evicted;
    pool_->insert_locked(member_, key, built.value, built.bytes, evicted);
    promise.set_value(built.value);
    lock.unlock();
    pool_->notify_evicted(evicted);
    return built.value;
  }

  // The value for `key` if held (counts a hit or a miss), else null.
  Ptr find(const std::string& key) {
    std::lock_guard lock(pool_->mutex_);
    CachePool::Member& m = member();
    CachePool::Value value = pool_->touch(m, key);
    ++(value ? m.stats.hits : m.stats.misses);
    return std::static_pointer_cast<const V>(value);
  }

  // Whether `key` is held now, without counting a lookup or making it more recent.
  bool contains(const std::string& key) const {
    std::lock_guard lock(pool_->mutex_);
    return pool_->members_[member_].entries.contains(key);
  }

  // Stores (or replaces) `key`; may evict others. Returns false when the value alone exceeds the
  // budget and was not kept.
  bool put(const std::string& key, Ptr value, size_t bytes) {
    CachePool::Evicted evicted;
    bool kept = false;
    {
      std::lock_guard lock(pool_->mutex_);
      kept = pool_->insert_locked(member_, key, std::move(value), bytes, evicted);
    }
    pool_->notify_evicted(evicted);
    return kept;
  }

  bool erase(const std::string& key) {
    std::lock_guard lock(pool_->mutex_);
    CachePool::Member& m = member();
    auto it = m.entries.find(key);
    if (it == m.entries.end()) return false;
    pool_->remove_locked(m, it);
    return true;
  }

  // This cache's lookups, builds, evictions and holdings; its budget is the smaller of its own cap
  // and the pool's budget.
  CacheStats stats() const { return pool_->member_stats(member_); }
  const std::shared_ptr<CachePool>& pool() const { return pool_; }

 private:
  CachePool::Member& member() { return pool_->members_[member_]; }

  std::shared_ptr<CachePool> pool_;
  size_t member_;
};

}  // namespace rr

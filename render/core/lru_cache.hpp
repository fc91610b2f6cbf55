// A thread-safe least-recently-used cache of immutable values shared across requests, bounded by a
// byte budget and an entry count, and single-flight: concurrent lookups of one missing key run its
// build once and all receive that result (or its exception). Used for BSP trees of static scenes
// (keyed by scene id + BSP options) and for the service's stored scenes.
//
// Values are handed out as shared_ptr<const V>, so an entry evicted while a render still uses it
// stays alive until that render ends; the budget bounds what the cache holds, not what is in use.
#pragma once

#include <cstddef>
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

template <class V>
class SharedLruCache {
 public:
  using Ptr = std::shared_ptr<const V>;
  struct Built {
    Ptr value;
    size_t bytes = 0;  // what the value costs against the budget
  };

  explicit SharedLruCache(size_t budget_bytes, size_t max_entries = std::numeric_limits<size_t>::max())
      : budget_bytes_(budget_bytes), max_entries_(max_entries) {}
  SharedLruCache(const SharedLruCache&) = delete;
  SharedLruCache& operator=(const SharedLruCache&) = delete;

  // Called with the key of each entry evicted to make room (not for erase() or replacement), after
  // the cache's lock is released, so it may call back into the cache. The service's scene store
  // uses it to delete an evicted scene's file. Set it before the cache is shared between threads.
  void set_eviction_listener(std::function<void(const std::string& key)> listener) {
    eviction_listener_ = std::move(listener);
  }

  // The value for `key`, running `build` when it is absent (and no other caller is building it).
  // `hit` is set when the value was ready. A build that throws caches nothing; its exception
  // reaches this caller and every caller that waited for it. A value larger than the whole budget
  // is returned but not kept.
  Ptr get_or_build(const std::string& key, const std::function<Built()>& build, bool& hit) {
    std::unique_lock lock(mutex_);
    if (Ptr ready = touch(key)) {
      ++stats_.hits;
      hit = true;
      return ready;
    }
    hit = false;
    ++stats_.misses;
    if (auto pending = pending_.find(key); pending != pending_.end()) {
      std::shared_future<Ptr> wait_for = pending->second;
      lock.unlock();
      return wait_for.get();
    }
    std::promise<Ptr> promise;
    pending_.emplace(key, promise.get_future().share());
    ++stats_.builds;
    lock.unlock();
    Built built;
    try {
      built = build();
    } catch (...) {
      lock.lock();
      pending_.erase(key);
      promise.set_exception(std::current_exception());
      throw;
    }
    lock.lock();
    pending_.erase(key);
    std::vector<std::string> evicted;
    insert_locked(key, built.value, built.bytes, evicted);
    promise.set_value(built.value);
    lock.unlock();
    notify_evicted(evicted);
    return built.value;
  }

  // The value for `key` if held (counts a hit or a miss), else null.
  Ptr find(const std::string& key) {
    std::lock_guard lock(mutex_);
    Ptr value = touch(key);
    ++(value ? stats_.hits : stats_.misses);
    return value;
  }

  // Stores (or replaces) `key`; may evict others. Returns false when the value alone exceeds the
  // budget and was not kept.
  bool put(const std::string& key, Ptr value, size_t bytes) {
    std::vector<std::string> evicted;
    bool kept = false;
    {
      std::lock_guard lock(mutex_);
      kept = insert_locked(key, std::move(value), bytes, evicted);
    }
    notify_evicted(evicted);
    return kept;
  }

  bool erase(const std::string& key) {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(key);
    if (it == entries_.end()) return false;
    remove_locked(it);
    return true;
  }

  CacheStats stats() const {
    std::lock_guard lock(mutex_);
    CacheStats s = stats_;
    s.entries = entries_.size();
    s.budget_bytes = budget_bytes_;
    s.max_entries = max_entries_;
    return s;
  }

 private:
  struct Entry {
    Ptr value;
    size_t bytes = 0;
    typename std::list<std::string>::iterator position;  // in recency_, most recent first
  };
  using Map = std::unordered_map<std::string, Entry>;

  Ptr touch(const std::string& key) {
    auto it = entries_.find(key);
    if (it == entries_.end()) return nullptr;
    recency_.splice(recency_.begin(), recency_, it->second.position);
    return it->second.value;
  }

  void remove_locked(typename Map::iterator it) {
    stats_.bytes -= it->second.bytes;
    recency_.erase(it->second.position);
    entries_.erase(it);
  }

  bool insert_locked(const std::string& key, Ptr value, size_t bytes, std::vector<std::string>& evicted) {
    if (auto old = entries_.find(key); old != entries_.end()) remove_locked(old);
    if (bytes > budget_bytes_ || max_entries_ == 0) return false;
    while (!recency_.empty() && (stats_.bytes + bytes > budget_bytes_ || entries_.size() >= max_entries_)) {
      if (eviction_listener_) evicted.push_back(recency_.back());
      remove_locked(entries_.find(recency_.back()));
      ++stats_.evictions;
    }
    recency_.push_front(key);
    entries_.emplace(key, Entry{std::move(value), bytes, recency_.begin()});
    stats_.bytes += bytes;
    return true;
  }

  void notify_evicted(const std::vector<std::string>& keys) const {
    for (const std::string& key : keys) eviction_listener_(key);
  }

  mutable std::mutex mutex_;
  std::function<void(const std::string&)> eviction_listener_;
  const size_t budget_bytes_;
  const size_t max_entries_;
  Map entries_;
  std::list<std::string> recency_;
  std::unordered_map<std::string, std::shared_future<Ptr>> pending_;
  CacheStats stats_;
};

}  // namespace rr

// The service's one memory cache of what is prepared, within one byte budget (--cache-bytes) and
// one least-recently-used order (a CachePool, render/core/lru_cache.hpp): stored scenes prepared for
// drawing (StoredScene: parsed, tessellated, with warnings and hierarchy), stored meshes parsed
// (StoredMesh), stored images decoded with their mip chains (StoredTexture), and the BSP trees and shadow maps of
// static scenes, and the views of them that leave levels or ceilings out (their polygons and shadow-ray
// trees), which inline renders share with stored ones. Nothing acknowledged lives only here: what is evicted is
// rebuilt from its document in the store (document_store.hpp) when next wanted, once however many requests want it at
// that moment (single-flight), and draws the same bytes. Shadow maps may take at most --shadow-cache-bytes of it.
#pragma once

#include "render/core/frame.hpp"
#include "render/core/lru_cache.hpp"
#include "server/open_stores.hpp"

#include <memory>
#include <optional>
#include <string>

namespace rr::server {

struct ServerConfig;

class PreparedCache {
 public:
  // Reads documents from `stores`, which outlive it.
  PreparedCache(const ServerConfig& config, Stores& stores);
  PreparedCache(const PreparedCache&) = delete;
  PreparedCache& operator=(const PreparedCache&) = delete;

  // Document `id` of kind T (StoredScene, StoredMesh or StoredTexture) prepared, counting as an access to the
  // stored document: null when it is not stored. On a miss it is built from the document (`built`
  // then says so; a waiter on another request's build counts as built too). Throws what the store
  // throws (StoreUnavailable) and std::runtime_error when a stored document no longer reads.
  template <class T>
  std::shared_ptr<const T> find(const std::string& id, bool* built = nullptr);
  // The text of document `id` (nullopt when not stored), counting as an access; from the cache when
  // it holds the document prepared, else from the store.
  template <class T>
  std::optional<std::string> text(const std::string& id);
  // The static id (X-Scene-Id) of the stored scene `id` whose text is `text`: the prepared scene's
  // when held, else parsed (meshes resolved, not tessellated).
  std::string static_id(const std::string& id, const std::string& text);
  // `item` was just stored (or was stored already): prepared anyway, so kept for what follows.
  template <class T>
  void keep(const std::shared_ptr<const T>& item);
  // Document `id` is no longer stored: its prepared form goes too.
  template <class T>
  void forget(const std::string& id);

  // The configuration's parse limits, with mesh references ("ref") resolved to stored meshes and
  // texture images given by id to stored images, through this cache.
  const ParseLimits& limits() const { return limits_; }

  CacheStats scene_stats() const { return scenes_.stats(); }
  CacheStats mesh_stats() const { return meshes_.stats(); }
  CacheStats texture_stats() const { return textures_.stats(); }
  CacheStats all_stats() const { return pool_->stats(); }

 private:
  template <class T>
  SharedLruCache<T>& part();

  Stores& stores_;
  std::shared_ptr<CachePool> pool_;  // before the parts, which it outlives
  SharedLruCache<StoredScene> scenes_;
  SharedLruCache<StoredMesh> meshes_;
  SharedLruCache<StoredTexture> textures_;
  ParseLimits limits_;
  unsigned threads_ = 1;  // a rebuild prepares a scene on a render's threads

 public:
  BspCache bsp;        // keyed by static scene id + BSP options
  ShadowCache shadow;  // keyed by static scene id + lights + map options (+ view)
  ViewCache views;     // keyed by static scene id + a view's selection of levels and ceilings (+ "|rays")
};

}  // namespace rr::server

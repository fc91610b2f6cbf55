// PreparedCache (prepared_cache.hpp), instantiated for scenes, meshes and images at the end.
#include "server/prepared_cache.hpp"

#include "render/pipelines/bsp.hpp"
#include "render/pipelines/shadow_cache.hpp"
#include "render/pipelines/view_selection.hpp"
#include "server/server_config.hpp"

#include <stdexcept>

namespace rr::server {

namespace {

// A document deleted between the look at the store and the build that reads its text.
struct GoneMeanwhile {};

std::shared_ptr<const StoredScene> read_prepared(const std::string& text, const ParseLimits& limits, unsigned threads,
                                                 const StoredScene*) {
  return read_stored_scene(text, limits, threads);
}
std::shared_ptr<const StoredMesh> read_prepared(const std::string& text, const ParseLimits& limits, unsigned,
                                                const StoredMesh*) {
  return read_stored_mesh(text, limits);
}
std::shared_ptr<const StoredTexture> read_prepared(const std::string& bytes, const ParseLimits& limits, unsigned,
                                                   const StoredTexture*) {
  return read_stored_texture(bytes, limits);
}

}  // namespace

PreparedCache::PreparedCache(const ServerConfig& c, Stores& stores)
    : stores_(stores),
      pool_(std::make_shared<CachePool>(c.cache_bytes)),
      scenes_(pool_),
      meshes_(pool_),
      textures_(pool_),
      limits_(c.limits),
      threads_(render_threads(c)),
      bsp(pool_, c.bsp_cache_entries),
      shadow(pool_, CachePool::unbounded, c.shadow_cache_bytes),
      views(pool_) {
  // The configuration's own resolvers (the catalogue's meshes and images) first: what they hold is
  // never stored.
  limits_.resolve_mesh = [this,
                          first = c.limits.resolve_mesh](const std::string& id) -> std::shared_ptr<const MeshData> {
    if (first) {
      if (auto mesh = first(id)) return mesh;
    }
    auto stored = find<StoredMesh>(id);
    return stored ? stored->mesh : nullptr;
  };
  limits_.resolve_texture =
      [this, first = c.limits.resolve_texture](const std::string& id) -> std::shared_ptr<const TextureImage> {
    if (first) {
      if (auto image = first(id)) return image;
    }
    auto stored = find<StoredTexture>(id);
    return stored ? stored->image : nullptr;
  };
}

template <>
SharedLruCache<StoredScene>& PreparedCache::part<StoredScene>() {
  return scenes_;
}
template <>
SharedLruCache<StoredMesh>& PreparedCache::part<StoredMesh>() {
  return meshes_;
}

template <>
SharedLruCache<StoredTexture>& PreparedCache::part<StoredTexture>() {
  return textures_;
}

template <class T>
std::shared_ptr<const T> PreparedCache::find(const std::string& id, bool* built) {
  SharedLruCache<T>& cache = part<T>();
  DocumentStore<T>& store = stores_.of<T>();
  // Held prepared: the store need only say that it is still stored (a delete through another
  // replica, or an expiry, is seen at once); else its text comes with the same look.
  const bool held = cache.contains(id);
  std::optional<std::string> text = store.find(id, !held);
  if (!text) {
    cache.erase(id);
    return nullptr;
  }
  bool hit = false;
  std::shared_ptr<const T> out;
  try {
    out = cache.get_or_build(
        id,
        [&]() -> typename SharedLruCache<T>::Built {
          if (held) text = store.find(id, true);  // evicted since the look above
          if (!text) throw GoneMeanwhile{};
          std::shared_ptr<const T> item;
          try {
            item = read_prepared(*text, limits_, threads_, static_cast<const T*>(nullptr));
          } catch (const InputError& e) {  // stored once, so it read then: a mesh it places is gone, or a limit fell
            throw std::runtime_error("the stored " + std::string(T::kind) + " " + id + " no longer reads: " + e.what());
          }
          if (item->id != id) {
            throw std::runtime_error("the stored " + std::string(T::kind) + " " + id + " reads as " + item->id);
          }
          return {item, item->bytes};
        },
        hit);
  } catch (const GoneMeanwhile&) {
    return nullptr;
  }
  if (built) *built = !hit;
  return out;
}

template <class T>
std::optional<std::string> PreparedCache::text(const std::string& id) {
  SharedLruCache<T>& cache = part<T>();
  const bool held = cache.contains(id);
  std::optional<std::string> text = stores_.of<T>().find(id, !held);
  if (!text) {
    cache.erase(id);
    return std::nullopt;
  }
  if (!held) return text;
  if (auto prepared = cache.find(id)) return prepared->text;
  return stores_.of<T>().find(id, true);  // evicted since the look above
}

std::string PreparedCache::static_id(const std::string& id, const std::string& text) {
  if (scenes_.contains(id)) {
    if (auto held = scenes_.find(id)) return held->static_id;
  }
  try {
    return static_id_of(text, limits_);
  } catch (const InputError& e) {
    throw std::runtime_error("the stored scene " + id + " no longer reads: " + e.what());
  }
}

template <class T>
void PreparedCache::keep(const std::shared_ptr<const T>& item) {
  part<T>().put(item->id, item, item->bytes);
}

template <class T>
void PreparedCache::forget(const std::string& id) {
  part<T>().erase(id);
}

template std::shared_ptr<const StoredScene> PreparedCache::find(const std::string&, bool*);
template std::shared_ptr<const StoredMesh> PreparedCache::find(const std::string&, bool*);
template std::optional<std::string> PreparedCache::text<StoredScene>(const std::string&);
template std::optional<std::string> PreparedCache::text<StoredMesh>(const std::string&);
template void PreparedCache::keep(const std::shared_ptr<const StoredScene>&);
template void PreparedCache::keep(const std::shared_ptr<const StoredMesh>&);
template void PreparedCache::forget<StoredScene>(const std::string&);
template void PreparedCache::forget<StoredMesh>(const std::string&);
template std::shared_ptr<const StoredTexture> PreparedCache::find(const std::string&, bool*);
template std::optional<std::string> PreparedCache::text<StoredTexture>(const std::string&);
template void PreparedCache::keep(const std::shared_ptr<const StoredTexture>&);
template void PreparedCache::forget<StoredTexture>(const std::string&);

}  // namespace rr::server

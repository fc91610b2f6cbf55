// The parse limits that resolve the catalogue's meshes and images (see catalogue_store.hpp).
#include "server/catalogue_store.hpp"

#include <mutex>

namespace rr::server {

namespace {

// The resolvers and built-in tests of `limits` over the catalogue `get` returns.
template <class Get>
ParseLimits resolving(ParseLimits limits, Get get) {
  limits.resolve_mesh = [get](const std::string& id) -> std::shared_ptr<const MeshData> {
    const Catalogue& catalogue = get();
    auto it = catalogue.meshes.find(id);
    return it == catalogue.meshes.end() ? nullptr : it->second->mesh;
  };
  limits.builtin_mesh = [get](const std::string& id) { return get().meshes.contains(id); };
  limits.resolve_texture = [get](const std::string& id) -> std::shared_ptr<const TextureImage> {
    const Catalogue& catalogue = get();
    auto it = catalogue.images.find(id);
    return it == catalogue.images.end() ? nullptr : it->second->image;
  };
  limits.builtin_texture = [get](const std::string& id) { return get().images.contains(id); };
  return limits;
}

}  // namespace

ParseLimits catalogue_limits(ParseLimits limits, std::shared_ptr<const Catalogue> catalogue) {
  return resolving(std::move(limits), [catalogue]() -> const Catalogue& { return *catalogue; });
}

ParseLimits lazy_catalogue_limits(ParseLimits limits, const std::filesystem::path& dir) {
  struct Lazy {
    std::once_flag once;
    std::shared_ptr<const Catalogue> catalogue;
  };
  auto lazy = std::make_shared<Lazy>();
  auto get = [lazy, dir, base = limits]() -> const Catalogue& {
    std::call_once(lazy->once, [&] { lazy->catalogue = load_catalogue(dir, base); });
    return *lazy->catalogue;
  };
  return resolving(std::move(limits), get);
}

}  // namespace rr::server

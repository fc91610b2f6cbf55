// The catalogue's meshes in front of the mesh store (see catalogue_store.hpp).
#include "server/catalogue_store.hpp"

#include <mutex>

namespace rr::server {

CatalogueMeshes::PutResult CatalogueMeshes::put(const StoredDocument& document, const std::string& owner) {
  if (catalogue_->meshes.contains(document.id)) return PutResult::existed;
  return store_->put(document, owner);
}

std::optional<std::string> CatalogueMeshes::find(const std::string& id, bool with_text) {
  if (auto it = catalogue_->meshes.find(id); it != catalogue_->meshes.end()) {
    return with_text ? it->second->text : std::string();
  }
  return store_->find(id, with_text);
}

CatalogueMeshes::ReleaseResult CatalogueMeshes::release(const std::string& id,
                                                        const std::optional<std::string>& owner) {
  if (catalogue_->meshes.contains(id)) return ReleaseResult::read_only;
  return store_->release(id, owner);
}

ParseLimits catalogue_limits(ParseLimits limits, std::shared_ptr<const Catalogue> catalogue) {
  limits.resolve_mesh = [catalogue](const std::string& id) -> std::shared_ptr<const MeshData> {
    auto it = catalogue->meshes.find(id);
    return it == catalogue->meshes.end() ? nullptr : it->second->mesh;
  };
  limits.builtin_mesh = [catalogue](const std::string& id) { return catalogue->meshes.contains(id); };
  return limits;
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
  limits.resolve_mesh = [get](const std::string& id) -> std::shared_ptr<const MeshData> {
    const Catalogue& catalogue = get();
    auto it = catalogue.meshes.find(id);
    return it == catalogue.meshes.end() ? nullptr : it->second->mesh;
  };
  limits.builtin_mesh = [get](const std::string& id) { return get().meshes.contains(id); };
  return limits;
}

}  // namespace rr::server

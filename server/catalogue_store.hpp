// The catalogue's meshes and images as read-only documents of the mesh and image stores: a
// DocumentStore<T> in front of the store --store opened, answering for the catalogue's documents
// itself. They are there from the start (made from the shipped files, so alike on every replica:
// each id is the document's content hash), never charged to a budget or an owner, never deleted
// (release: read_only), and storing one again (POST /v1/meshes or /v1/textures of the same bytes)
// answers "existed". Everything else goes to the store behind. A stored scene using them pins
// nothing: mesh refs and image ids resolve through the parse limits (catalogue_limits) before the
// prepared cache is asked, and they are left out of a stored scene's refs.
#pragma once

#include "server/catalogue.hpp"
#include "server/document_store.hpp"
#include "server/mesh_store.hpp"
#include "server/texture_store.hpp"

#include <map>
#include <memory>

namespace rr::server {

template <class T>
class CatalogueDocuments final : public DocumentStore<T> {
 public:
  using typename DocumentStore<T>::PutResult;
  using typename DocumentStore<T>::ReleaseResult;
  using typename DocumentStore<T>::Page;
  using typename DocumentStore<T>::Clock;
  using Documents = std::map<std::string, std::shared_ptr<const T>>;

  // `documents` is a member of `catalogue`, which this keeps alive.
  CatalogueDocuments(std::unique_ptr<DocumentStore<T>> store, std::shared_ptr<const Catalogue> catalogue,
                     const Documents& documents)
      : store_(std::move(store)), catalogue_(std::move(catalogue)), documents_(documents) {}

  size_t load() override { return store_->load(); }
  PutResult put(const StoredDocument& document, const std::string& owner) override {
    if (documents_.contains(document.id)) return PutResult::existed;
    return store_->put(document, owner);
  }
  std::optional<std::string> find(const std::string& id, bool with_text) override {
    if (auto it = documents_.find(id); it != documents_.end()) return with_text ? it->second->text : std::string();
    return store_->find(id, with_text);
  }
  ReleaseResult release(const std::string& id, const std::optional<std::string>& owner) override {
    if (documents_.contains(id)) return ReleaseResult::read_only;
    return store_->release(id, owner);
  }
  Page list(const std::optional<std::string>& owner, size_t limit, const std::string& cursor) override {
    return store_->list(owner, limit, cursor);
  }
  std::vector<std::string> pinned_by(const std::string& id, size_t most) override {
    return store_->pinned_by(id, most);
  }
  std::optional<typename Clock::time_point> expiry_from_now() const override { return store_->expiry_from_now(); }
  CacheStats stats() override { return store_->stats(); }
  size_t max_bytes() const override { return store_->max_bytes(); }
  std::string unavailable_reason() override { return store_->unavailable_reason(); }

 private:
  std::unique_ptr<DocumentStore<T>> store_;
  std::shared_ptr<const Catalogue> catalogue_;
  const Documents& documents_;
};

using CatalogueMeshes = CatalogueDocuments<StoredMesh>;
using CatalogueImages = CatalogueDocuments<StoredTexture>;

// `limits` whose mesh refs and image ids resolve to the catalogue's meshes and images first (the
// prepared cache's resolvers ask the store after) and which name them as built in, so a stored scene
// does not count them among the stored documents it uses.
ParseLimits catalogue_limits(ParseLimits limits, std::shared_ptr<const Catalogue> catalogue);

// The same for a command-line tool: the catalogue in `dir` is read the first time a ref or an image
// id is resolved (a request that uses none never reads it).
ParseLimits lazy_catalogue_limits(ParseLimits limits, const std::filesystem::path& dir);

}  // namespace rr::server

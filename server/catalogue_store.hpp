// The catalogue's meshes as read-only documents of the mesh store: a DocumentStore<StoredMesh> in
// front of the store --store opened, answering for the catalogue's meshes itself. They are there
// from the start (made from the shipped files, so alike on every replica: each id is the mesh's
// content hash), never charged to a budget or an owner, never deleted (release: read_only), and
// storing one again (POST /v1/meshes of the same mesh) answers "existed". Everything else goes to the
// store behind. A stored scene placing them pins nothing: the refs resolve through the parse limits
// (catalogue_limits) before the prepared cache is asked, and they are left out of a stored scene's
// refs.
#pragma once

#include "server/catalogue.hpp"
#include "server/document_store.hpp"
#include "server/mesh_store.hpp"

#include <memory>

namespace rr::server {

class CatalogueMeshes final : public MeshDocuments {
 public:
  CatalogueMeshes(std::unique_ptr<MeshDocuments> store, std::shared_ptr<const Catalogue> catalogue)
      : store_(std::move(store)), catalogue_(std::move(catalogue)) {}

  size_t load() override { return store_->load(); }
  PutResult put(const StoredDocument& document, const std::string& owner) override;
  std::optional<std::string> find(const std::string& id, bool with_text) override;
  ReleaseResult release(const std::string& id, const std::optional<std::string>& owner) override;
  Page list(const std::optional<std::string>& owner, size_t limit, const std::string& cursor) override {
    return store_->list(owner, limit, cursor);
  }
  std::vector<std::string> pinned_by(const std::string& id, size_t most) override {
    return store_->pinned_by(id, most);
  }
  std::optional<Clock::time_point> expiry_from_now() const override { return store_->expiry_from_now(); }
  CacheStats stats() override { return store_->stats(); }
  size_t max_bytes() const override { return store_->max_bytes(); }
  std::string unavailable_reason() override { return store_->unavailable_reason(); }

 private:
  std::unique_ptr<MeshDocuments> store_;
  std::shared_ptr<const Catalogue> catalogue_;
};

// `limits` whose mesh refs resolve to the catalogue's meshes first (the prepared cache's resolver
// asks the store after) and which name them as built in, so a stored scene does not count them among
// the stored meshes it places.
ParseLimits catalogue_limits(ParseLimits limits, std::shared_ptr<const Catalogue> catalogue);

// The same for a command-line tool: the catalogue in `dir` is read the first time a ref is resolved
// (a request that places none never reads it).
ParseLimits lazy_catalogue_limits(ParseLimits limits, const std::filesystem::path& dir);

}  // namespace rr::server

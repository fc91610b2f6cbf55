// The service's scene, mesh and image stores, opened from its configuration by the scheme of the --store
// URL: none given -> the embedded store (memory, and files under --data-dir when given);
// postgresql: or postgres: (or libpq's key=value form) -> PostgreSQL, shared by every replica.
// Handlers see only the DocumentStore interface: each backend keeps its own rules between the two
// stores (the embedded one its MeshPins and TexturePins, PostgreSQL its foreign keys). Another backend is one row in
// open_stores.cpp's table.
#pragma once

#include "server/document_store.hpp"
#include "server/mesh_store.hpp"
#include "server/scene_store.hpp"
#include "server/texture_store.hpp"

#include <memory>
#include <string>
#include <type_traits>

namespace rr::server {

struct ServerConfig;

struct Stores {
  // What both stores use (the embedded store's mesh pins, PostgreSQL's connection pool). Declared
  // first, so it outlives them.
  std::shared_ptr<void> shared;
  std::unique_ptr<MeshDocuments> meshes;
  std::unique_ptr<TextureDocuments> textures;
  std::unique_ptr<SceneDocuments> scenes;

  template <class T>
  DocumentStore<T>& of() {
    static_assert(std::is_same_v<T, StoredScene> || std::is_same_v<T, StoredMesh> || std::is_same_v<T, StoredTexture>);
    if constexpr (std::is_same_v<T, StoredScene>) {
      return *scenes;
    } else if constexpr (std::is_same_v<T, StoredTexture>) {
      return *textures;
    } else {
      return *meshes;
    }
  }
};

using StoreLog = SceneStore::Log;  // one JSON log line: level and fields

// Opens (connects to nothing yet; load() prepares) the stores `config.store_url` names. Throws
// std::invalid_argument, naming --store, for a URL no backend takes.
Stores open_stores(const ServerConfig& config, const StoreLog& log);

// Whether a backend takes `url` ("" included: the embedded store), without connecting. Throws
// std::invalid_argument saying why not, to follow the flag's name ("has the unknown scheme ...").
void check_store_url(const std::string& url);

}  // namespace rr::server

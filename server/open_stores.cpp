// open_stores (open_stores.hpp): the table of store backends by URL scheme, and how each one opens
// and wires its scene and mesh stores.
#include "server/open_stores.hpp"

#include "server/http_server.hpp"
#include "server/postgres_store.hpp"

#include <cctype>
#include <mutex>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace rr::server {

namespace {

// The embedded mesh store: deleting a mesh holds the pins' writer lock, so it cannot slip between
// a scene's check of the meshes it places and that scene being stored (PlacingScenes).
class PinnedMeshes final : public MeshStore {
 public:
  PinnedMeshes(MeshStoreConfig config, Log log, MeshPins& pins)
      : MeshStore(std::move(config), std::move(log)), pins_(pins) {}
  ReleaseResult release(const std::string& id, const std::optional<std::string>& owner) override {
    std::lock_guard lock(pins_.writers());
    return MeshStore::release(id, owner);
  }

 private:
  MeshPins& pins_;
};

// The embedded scene store: a scene is stored only while every mesh it places is (else
// missing_reference), checked and stored under the pins' writer lock; once stored, on_change pins them.
class PlacingScenes final : public SceneStore {
 public:
  PlacingScenes(SceneStoreConfig config, Log log, MeshPins& pins, MeshDocuments& meshes)
      : SceneStore(std::move(config), std::move(log)), pins_(pins), meshes_(meshes) {}
  PutResult put(const StoredDocument& scene, const std::string& owner) override {
    std::lock_guard lock(pins_.writers());
    for (const std::string& mesh : scene.refs) {
      if (!meshes_.find(mesh, false)) return PutResult::missing_reference;
    }
    return SceneStore::put(scene, owner);
  }

 private:
  MeshPins& pins_;
  MeshDocuments& meshes_;
};

// What every backend's store of T takes from the configuration: budgets, retention, names, reader.
template <class T>
ContentStoreConfig<T> store_config(const ServerConfig& c, size_t max_entries, size_t max_bytes,
                                   std::function<StoredDocument(const std::string&)> read) {
  ContentStoreConfig<T> out;
  out.max_entries = max_entries;
  out.max_bytes = max_bytes;
  out.ttl = std::chrono::seconds(c.scene_ttl_s);
  out.kind = T::kind;
  out.plural = T::plural;
  out.read = std::move(read);
  return out;
}

MeshStoreConfig mesh_config(const ServerConfig& c) {
  return store_config<StoredMesh>(
      c, c.mesh_store_entries, c.mesh_store_bytes,
      [limits = c.limits](const std::string& text) { return read_mesh_document(text, limits); });
}

SceneStoreConfig scene_config(const ServerConfig& c) {
  return store_config<StoredScene>(
      c, c.scene_store_entries, c.scene_store_bytes,
      [limits = c.limits](const std::string& text) { return read_scene_document(text, limits); });
}

// Memory, and files under --data-dir; the pins between scenes and meshes are the two stores' shared part.
Stores open_embedded(const ServerConfig& c, const StoreLog& log) {
  auto pins = std::make_shared<MeshPins>();
  Stores out;
  out.shared = pins;
  MeshStoreConfig meshes = mesh_config(c);
  meshes.data_dir = c.data_dir;
  meshes.pinned = [&pins = *pins](const std::string& id) { return pins.pinned(id); };
  meshes.pinned_by = [&pins = *pins](const std::string& id, size_t most) { return pins.scenes_placing(id, most); };
  out.meshes = std::make_unique<PinnedMeshes>(std::move(meshes), log, *pins);
  SceneStoreConfig scenes = scene_config(c);
  scenes.data_dir = c.data_dir;
  scenes.on_change = [&pins = *pins](const std::string& id, const std::vector<std::string>& refs, bool added) {
    pins.change(id, refs, added);
  };
  out.scenes = std::make_unique<PlacingScenes>(std::move(scenes), log, *pins, *out.meshes);
  return out;
}

// One database for every replica, through one pool; pins are the database's foreign keys.
Stores open_postgresql(const ServerConfig& c, const StoreLog& log) {
  auto pool = std::make_shared<PostgresPool>(postgres_config(c), log);
  Stores out;
  out.shared = pool;
  out.meshes = std::make_unique<PostgresStore<StoredMesh>>(pool, mesh_config(c), log);
  out.scenes = std::make_unique<PostgresStore<StoredScene>>(pool, scene_config(c), log);
  return out;
}

void take_any(const std::string&) {}

void check_postgresql(const std::string& url) {
  try {
    check_postgres_url(url);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("is not a PostgreSQL connection URL: ") + e.what());
  }
}

// libpq's key=value connection string ("host=/run/postgresql dbname=rr") names no scheme; it is
// PostgreSQL's, and docs/api.md offers it.
constexpr std::string_view key_value_form = "key=value";

struct Backend {
  std::vector<std::string_view> schemes;  // "": no --store; key_value_form: libpq's key=value string
  void (*check)(const std::string& url);  // throws std::invalid_argument: why this backend does not take it
  Stores (*open)(const ServerConfig& config, const StoreLog& log);
};

// One row per backend.
const std::vector<Backend> backends = {
    {{""}, take_any, open_embedded},
    {{"postgresql", "postgres", key_value_form}, check_postgresql, open_postgresql},
};

// "postgresql" of "postgresql://rr@db/rr" (RFC 3986: a letter, then letters, digits, "+", "-" or
// ".", before the first colon); "" of ""; key_value_form of any other text.
std::string_view scheme_of(std::string_view url) {
  if (url.empty()) return "";
  const size_t colon = url.find(':');
  if (colon == std::string_view::npos || !std::isalpha(static_cast<unsigned char>(url[0]))) {
    return key_value_form;
  }
  for (char ch : url.substr(0, colon)) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '+' && ch != '-' && ch != '.') return key_value_form;
  }
  return url.substr(0, colon);
}

// The row that takes `url`, checked. Throws std::invalid_argument saying why none does.
const Backend& backend_for(const std::string& url) {
  const std::string_view scheme = scheme_of(url);
  std::string known;
  for (const Backend& b : backends) {
    for (std::string_view s : b.schemes) {
      if (s == scheme) {
        b.check(url);
        return b;
      }
      if (!s.empty()) known += (s == key_value_form ? "libpq's key=value string" : std::string(s) + ":") + ", ";
    }
  }
  throw std::invalid_argument("has the unknown scheme \"" + std::string(scheme) + ":\" (known: " + known +
                              "or none for the embedded store)");
}

}  // namespace

void check_store_url(const std::string& url) { backend_for(url); }

Stores open_stores(const ServerConfig& config, const StoreLog& log) {
  const Backend* backend = nullptr;
  try {
    backend = &backend_for(config.store_url);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--store ") + e.what());
  }
  return backend->open(config, log);
}

}  // namespace rr::server

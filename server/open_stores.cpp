// open_stores (open_stores.hpp): the table of store backends by URL scheme, and how each one opens
// and wires its scene, mesh and image stores.
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

// The embedded stores' pins: which stored scenes place which meshes and name which images. One
// writer lock (the meshes') serialises storing a scene with deleting a mesh or an image.
struct EmbeddedPins {
  MeshPins meshes;
  TexturePins textures;
  std::mutex& writers() { return meshes.writers(); }
};

// An embedded mesh or image store: deleting holds the pins' writer lock, so it cannot slip between
// a scene's check of the documents it uses and that scene being stored (PlacingScenes).
template <class T>
class PinnedDocuments final : public ContentStore<T> {
 public:
  using typename ContentStore<T>::ReleaseResult;
  PinnedDocuments(ContentStoreConfig<T> config, typename ContentStore<T>::Log log, EmbeddedPins& pins)
      : ContentStore<T>(std::move(config), std::move(log)), pins_(pins) {}
  ReleaseResult release(const std::string& id, const std::optional<std::string>& owner) override {
    std::lock_guard lock(pins_.writers());
    return ContentStore<T>::release(id, owner);
  }

 private:
  EmbeddedPins& pins_;
};

// The embedded scene store: a scene is stored only while every mesh it places and every image it
// names is (else missing_reference), checked and stored under the pins' writer lock; once stored,
// on_change pins them.
class PlacingScenes final : public SceneStore {
 public:
  PlacingScenes(SceneStoreConfig config, Log log, EmbeddedPins& pins, MeshDocuments& meshes, TextureDocuments& textures)
      : SceneStore(std::move(config), std::move(log)), pins_(pins), meshes_(meshes), textures_(textures) {}
  PutResult put(const StoredDocument& scene, const std::string& owner) override {
    std::lock_guard lock(pins_.writers());
    for (const std::string& mesh : scene.refs) {
      if (!meshes_.find(mesh, false)) return PutResult::missing_reference;
    }
    for (const std::string& image : scene.texture_refs) {
      if (!textures_.find(image, false)) return PutResult::missing_reference;
    }
    return SceneStore::put(scene, owner);
  }

 private:
  EmbeddedPins& pins_;
  MeshDocuments& meshes_;
  TextureDocuments& textures_;
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

TextureStoreConfig texture_config(const ServerConfig& c) {
  TextureStoreConfig out =
      store_config<StoredTexture>(c, c.texture_store_entries, c.texture_store_bytes,
                                  [](const std::string& bytes) { return read_texture_document(bytes); });
  out.extension = ".img";
  return out;
}

SceneStoreConfig scene_config(const ServerConfig& c) {
  return store_config<StoredScene>(
      c, c.scene_store_entries, c.scene_store_bytes,
      [limits = c.limits](const std::string& text) { return read_scene_document(text, limits); });
}

// Memory, and files under --data-dir; the pins between scenes and meshes are the two stores' shared part.
Stores open_embedded(const ServerConfig& c, const StoreLog& log) {
  auto pins = std::make_shared<EmbeddedPins>();
  Stores out;
  out.shared = pins;
  // A mesh or an image is pinned while a stored scene names it, as its half of the pins records.
  auto pinned_config = [&c](auto config, MeshPins& half) {
    config.data_dir = c.data_dir;
    config.pinned = [&half](const std::string& id) { return half.pinned(id); };
    config.pinned_by = [&half](const std::string& id, size_t most) { return half.scenes_placing(id, most); };
    return config;
  };
  out.meshes = std::make_unique<PinnedDocuments<StoredMesh>>(pinned_config(mesh_config(c), pins->meshes), log, *pins);
  out.textures =
      std::make_unique<PinnedDocuments<StoredTexture>>(pinned_config(texture_config(c), pins->textures), log, *pins);
  SceneStoreConfig scenes = scene_config(c);
  scenes.data_dir = c.data_dir;
  scenes.on_change = [&pins = *pins](const std::string& id, const std::vector<std::string>& refs,
                                     const std::vector<std::string>& texture_refs, bool added) {
    pins.meshes.change(id, refs, added);
    pins.textures.change(id, texture_refs, added);
  };
  out.scenes = std::make_unique<PlacingScenes>(std::move(scenes), log, *pins, *out.meshes, *out.textures);
  return out;
}

// One database for every replica, through one pool; pins are the database's foreign keys.
Stores open_postgresql(const ServerConfig& c, const StoreLog& log) {
  auto pool = std::make_shared<PostgresPool>(postgres_config(c), log);
  Stores out;
  out.shared = pool;
  out.meshes = std::make_unique<PostgresStore<StoredMesh>>(pool, mesh_config(c), log);
  out.textures = std::make_unique<PostgresStore<StoredTexture>>(pool, texture_config(c), log);
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

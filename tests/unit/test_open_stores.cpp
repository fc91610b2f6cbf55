// open_stores: the --store URL's scheme picks the backend (none: embedded; postgresql:, postgres:
// or libpq's key=value form: PostgreSQL, opened without connecting), an unknown scheme is refused
// naming the flag, and the embedded backend keeps the pins between its scene and mesh stores itself:
// a scene placing a mesh that is not stored is refused, and a placed mesh is not deleted.
#include "server/content_store.hpp"
#include "server/http_server.hpp"
#include "server/open_stores.hpp"
#include "server/postgres_store.hpp"
#include "server/serve_command.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace {

using namespace rr::server;

void quiet(const std::string&, nlohmann::ordered_json) {}

std::string refusal(const std::string& url) {
  try {
    check_store_url(url);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(OpenStores, TheSchemePicksTheBackend) {
  ServerConfig config = default_server_config();
  Stores embedded = open_stores(config, quiet);
  EXPECT_NE(dynamic_cast<SceneStore*>(embedded.scenes.get()), nullptr);
  EXPECT_NE(dynamic_cast<MeshStore*>(embedded.meshes.get()), nullptr);
  EXPECT_NE(embedded.shared, nullptr);

  for (const char* url : {"postgresql://rr@/rr?host=/nonexistent", "postgres://rr:secret@db.example:5432/rr",
                          "host=/nonexistent dbname=rr"}) {
    config.store_url = url;
    EXPECT_EQ(refusal(url), "") << url;
    Stores shared = open_stores(config, quiet);  // connects to nothing until load()
    EXPECT_NE(dynamic_cast<PostgresStore<StoredScene>*>(shared.scenes.get()), nullptr) << url;
    EXPECT_NE(dynamic_cast<PostgresStore<StoredMesh>*>(shared.meshes.get()), nullptr) << url;
    EXPECT_NE(shared.shared, nullptr);
  }
}

TEST(OpenStores, AnUnknownSchemeOrABadUrlIsRefusedNamingTheFlag) {
  EXPECT_EQ(refusal(""), "");
  EXPECT_EQ(refusal("mysql://rr@db/rr"),
            "has the unknown scheme \"mysql:\" (known: postgresql:, postgres:, libpq's key=value string, or none "
            "for the embedded store)");
  EXPECT_EQ(refusal("file:/var/lib/roomrender").rfind("has the unknown scheme \"file:\"", 0), 0u);
  EXPECT_EQ(refusal("postgresql://rr@db/rr?nosuchoption=1").rfind("is not a PostgreSQL connection URL: ", 0), 0u);
  EXPECT_EQ(refusal("dbname").rfind("is not a PostgreSQL connection URL: ", 0), 0u);

  ServerConfig config = default_server_config();
  config.store_url = "mysql://rr@db/rr";
  try {
    open_stores(config, quiet);
    ADD_FAILURE() << "opened a store for " << config.store_url;
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--store has the unknown scheme \"mysql:\"", 0), 0u) << e.what();
  }
  for (const bool from_flag : {true, false}) {
    std::vector<std::string> args;
    if (from_flag) args = {"--store", "mysql://rr@db/rr"};
    auto env = [&](const char* name) -> std::optional<std::string> {
      if (!from_flag && std::string(name) == "ROOMRENDER_STORE") return "mysql://rr@db/rr";
      return std::nullopt;
    };
    try {
      serve_config_from(args, env);
      ADD_FAILURE() << "accepted an unknown store scheme";
    } catch (const UsageError& e) {
      const std::string named = from_flag ? "--store" : "ROOMRENDER_STORE";
      EXPECT_EQ(std::string(e.what()).rfind(named + " has the unknown scheme \"mysql:\"", 0), 0u) << e.what();
    }
  }
}

StoredDocument scene_placing(const std::string& id, const std::string& mesh) {
  return {id, "{\"solids\":[{\"ref\":\"" + mesh + "\"}]}", {mesh}, {}};
}

TEST(OpenStores, TheEmbeddedBackendHoldsScenesToTheMeshesTheyPlace) {
  Stores stores = open_stores(default_server_config(), quiet);
  auto mesh = prepare_mesh(rr::make_mesh_data({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                                              {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, {}));
  StoredDocument scene = scene_placing("00000000000000aa", mesh->id);
  EXPECT_EQ(stores.scenes->put(scene, ""), SceneDocuments::PutResult::missing_reference);
  EXPECT_FALSE(stores.scenes->find(scene.id, false));

  ASSERT_EQ(stores.meshes->put(mesh_document(*mesh), ""), MeshDocuments::PutResult::created);
  ASSERT_EQ(stores.scenes->put(scene, ""), SceneDocuments::PutResult::created);
  EXPECT_EQ(stores.meshes->release(mesh->id, std::nullopt), MeshDocuments::ReleaseResult::pinned);
  EXPECT_EQ(stores.meshes->pinned_by(mesh->id, 5), std::vector<std::string>{scene.id});
  EXPECT_EQ(stores.scenes->release(scene.id, std::nullopt), SceneDocuments::ReleaseResult::removed);
  EXPECT_TRUE(stores.meshes->pinned_by(mesh->id, 5).empty());
  EXPECT_EQ(stores.meshes->release(mesh->id, std::nullopt), MeshDocuments::ReleaseResult::removed);
}

// The same rule for the images a scene's textures name: stored only while they are, and they stay
// while it does. The store holds bytes; only their hash names them.
TEST(OpenStores, TheEmbeddedBackendHoldsScenesToTheImagesTheirTexturesName) {
  Stores stores = open_stores(default_server_config(), quiet);
  const StoredDocument image = read_texture_document("not decoded by the store");
  const StoredDocument scene{
      "00000000000000ab", "{\"floor\":{\"texture\":{\"image\":\"" + image.id + "\"}}}", {}, {image.id}};
  EXPECT_EQ(stores.scenes->put(scene, ""), SceneDocuments::PutResult::missing_reference);

  ASSERT_EQ(stores.textures->put(image, ""), TextureDocuments::PutResult::created);
  ASSERT_EQ(stores.scenes->put(scene, ""), SceneDocuments::PutResult::created);
  EXPECT_EQ(stores.textures->release(image.id, std::nullopt), TextureDocuments::ReleaseResult::pinned);
  EXPECT_EQ(stores.textures->pinned_by(image.id, 5), std::vector<std::string>{scene.id});
  EXPECT_EQ(stores.scenes->release(scene.id, std::nullopt), SceneDocuments::ReleaseResult::removed);
  EXPECT_TRUE(stores.textures->pinned_by(image.id, 5).empty());
  EXPECT_EQ(stores.textures->release(image.id, std::nullopt), TextureDocuments::ReleaseResult::removed);
}

}  // namespace

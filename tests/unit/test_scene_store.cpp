// The embedded scene store (server/scene_store.hpp): one content per id, references per owner, a
// full store that refuses rather than evicts, and documents that are their text alone.
#include "server/scene_store.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>

namespace {

using namespace rr::server;

// Two contents under one id (as a crafted FNV-1a collision would give) are refused, never merged.
TEST(SceneStore, SameIdWithOtherContentIsAConflict) {
  SceneStore store({}, [](const std::string&, nlohmann::ordered_json) {});
  auto scene = [](const std::string& text) { return StoredDocument{"0123456789abcdef", text, {}, {}}; };
  EXPECT_EQ(store.put(scene("{\"walls\":[]}"), ""), SceneStore::PutResult::created);
  EXPECT_EQ(store.put(scene("{\"walls\":[]}"), ""), SceneStore::PutResult::existed);
  EXPECT_EQ(store.put(scene("{\"solids\":[]}"), ""), SceneStore::PutResult::conflict);
  EXPECT_EQ(store.put(scene("{\"walls\":[1]}"), ""), SceneStore::PutResult::conflict);  // same size, other text
  EXPECT_EQ(store.find("0123456789abcdef", true), "{\"walls\":[]}");
  EXPECT_EQ(store.find("0123456789abcdef", false), "");
}

// A scene stored by two owners stays until both dropped their reference; a full store refuses
// rather than evicts.
TEST(SceneStore, ReferencesPerOwnerAndNoEviction) {
  SceneStoreConfig config;
  config.max_entries = 1;
  SceneStore store(config, [](const std::string&, nlohmann::ordered_json) {});
  auto scene = [](const std::string& id) { return StoredDocument{id, "{}", {}, {}}; };
  EXPECT_EQ(store.put(scene("0000000000000001"), "a"), SceneStore::PutResult::created);
  EXPECT_EQ(store.put(scene("0000000000000001"), "b"), SceneStore::PutResult::existed);
  EXPECT_EQ(store.put(scene("0000000000000002"), "a"), SceneStore::PutResult::full);
  EXPECT_EQ(store.release("0000000000000001", "c"), SceneStore::ReleaseResult::not_owner);
  EXPECT_EQ(store.release("0000000000000001", "a"), SceneStore::ReleaseResult::reference_dropped);
  EXPECT_EQ(store.release("0000000000000001", "a"), SceneStore::ReleaseResult::not_owner);
  ASSERT_TRUE(store.find("0000000000000001", false));
  EXPECT_EQ(store.release("0000000000000001", "b"), SceneStore::ReleaseResult::removed);
  EXPECT_FALSE(store.find("0000000000000001", false));
  EXPECT_EQ(store.put(scene("0000000000000002"), "a"), SceneStore::PutResult::created);
  EXPECT_EQ(store.release("0000000000000002", std::nullopt), SceneStore::ReleaseResult::removed);
}

}  // namespace

// The furniture catalogue the server offers (GET /v1/catalogue): read once at start from
// --catalogue-dir (catalogue.json, models/, icons/; catalogue/README.md). Each entry's OBJ model
// becomes the parts of a piece as the Sweet Home 3D importer makes them (import_furniture_model: one
// mesh per material group, in the unit box, coloured by the default material library), and each part's
// mesh a stored mesh that every replica makes alike from the same files (its id is its content hash).
// Those meshes are read-only documents of the mesh store (catalogue_store.hpp). The texture
// catalogue (textures.json, textures/; GET /v1/catalogue/textures) is read alike: each image is a
// read-only document of the image store, its id the hash of the file's bytes.
#pragma once

#include "server/mesh_store.hpp"
#include "server/texture_store.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rr::server {

struct CatalogueItem {
  std::string id;  // [a-z0-9_]+, e.g. "bedside_table"
  std::string name, category;
  double width_cm = 0, depth_cm = 0, height_cm = 0, elevation_cm = 0;
  std::filesystem::path icon;  // the PNG file
  nlohmann::json piece;        // {"type": "piece", "size", "base", "parts": [{"name", "ref", "color"[, "material"]}]}
};

struct CatalogueTexture {
  std::string id;          // the stored image's id: hash_hex of the file's bytes
  std::string catalog_id;  // Sweet Home 3D's, e.g. "eTeks#woodenFloor"
  std::string name, category;
  double width_cm = 0, height_cm = 0;  // one tile's real size
};

struct Catalogue {
  std::vector<CatalogueItem> items;                                 // in the catalogue file's order
  std::map<std::string, std::shared_ptr<const StoredMesh>> meshes;  // by id: every part's mesh
  std::string attribution, licence;
  std::string answer;                                                  // the GET /v1/catalogue body, made once
  std::string etag;                                                    // its content hash, quoted
  std::vector<CatalogueTexture> textures;                              // in textures.json's order
  std::map<std::string, std::shared_ptr<const StoredTexture>> images;  // by id: every texture's image
  std::string textures_answer;                                         // the GET /v1/catalogue/textures body, made once
  std::string textures_etag;                                           // its content hash, quoted
  std::vector<std::string> problems;  // entries left out, and why (the service logs them at start)

  const CatalogueItem* find(const std::string& id) const;
};

// Reads the catalogue in `dir`; an empty catalogue when dir has no catalogue.json (no textures when
// it has no textures.json). An entry whose model or image cannot be read is left out and said in
// `problems`; a catalogue.json or textures.json that does not read is an error (std::runtime_error
// naming the file).
std::shared_ptr<const Catalogue> load_catalogue(const std::filesystem::path& dir, const ParseLimits& limits);

}  // namespace rr::server

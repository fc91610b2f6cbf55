// Reading the furniture catalogue (see catalogue.hpp): catalogue.json's entries, each model through
// import_furniture_model, each part's mesh prepared as a stored mesh, textures.json's images decoded
// as stored images, and the answers of GET /v1/catalogue and GET /v1/catalogue/textures written once.
#include "server/catalogue.hpp"

#include "render/core/hash.hpp"
#include "render/import/import.hpp"
#include "render/scene_io/mesh_json.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rr::server {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::optional<std::string> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

double rounded(double metres) { return std::round(metres * 1e6) / 1e6; }

// One entry: its model as parts whose "ref" names the stored mesh of each part.
CatalogueItem read_item(const json& entry, const fs::path& dir, const ParseLimits& limits, Catalogue& catalogue) {
  CatalogueItem item;
  item.id = entry.at("id").get<std::string>();
  item.name = entry.at("name").get<std::string>();
  item.category = entry.at("category").get<std::string>();
  item.width_cm = entry.at("width").get<double>();
  item.depth_cm = entry.at("depth").get<double>();
  item.height_cm = entry.at("height").get<double>();
  item.elevation_cm = entry.value("elevation", 0.0);
  item.icon = dir / entry.at("icon").get<std::string>();
  const fs::path model = dir / entry.at("model").get<std::string>();
  const std::optional<std::string> obj = read_file(model);
  if (!obj) throw std::runtime_error("cannot read " + model.string());
  ImportOptions options;
  options.read_companion = [folder = model.parent_path()](const std::string& name) { return read_file(folder / name); };
  FurnitureModel furniture = import_furniture_model(*obj, item.id, options, entry.value("model_rotation", ""));
  std::map<std::string, std::string> stored_ids;
  for (const auto& [key, document] : furniture.meshes) {
    std::shared_ptr<const StoredMesh> mesh = prepare_mesh(mesh_from_json(document, limits));
    stored_ids[key] = mesh->id;
    catalogue.meshes.emplace(mesh->id, std::move(mesh));
  }
  for (json& part : furniture.parts) part["ref"] = stored_ids.at(part["ref"].get<std::string>());
  item.piece = {
      {"type", "piece"},
      {"size", {rounded(item.width_cm / 100.0), rounded(item.height_cm / 100.0), rounded(item.depth_cm / 100.0)}},
      {"base", rounded(item.elevation_cm / 100.0)},
      {"parts", std::move(furniture.parts)}};
  return item;
}

std::string answer_of(const Catalogue& catalogue) {
  json items = json::array();
  for (const CatalogueItem& item : catalogue.items) {
    items.push_back({{"id", item.id},
                     {"name", item.name},
                     {"category", item.category},
                     {"size_cm", {{"width", item.width_cm}, {"depth", item.depth_cm}, {"height", item.height_cm}}},
                     {"elevation_cm", item.elevation_cm},
                     {"icon", "/v1/catalogue/" + item.id + "/icon.png"},
                     {"piece", item.piece}});
  }
  return json{{"items", std::move(items)}, {"licence", catalogue.licence}, {"attribution", catalogue.attribution}}
      .dump();
}

// One texture: its image decoded with the service's caps, as POST /v1/textures would store it.
CatalogueTexture read_texture(const json& entry, const fs::path& dir, const ParseLimits& limits, Catalogue& catalogue) {
  CatalogueTexture texture;
  texture.catalog_id = entry.at("catalog_id").get<std::string>();
  texture.name = entry.at("name").get<std::string>();
  texture.category = entry.at("category").get<std::string>();
  texture.width_cm = entry.at("width").get<double>();
  texture.height_cm = entry.at("height").get<double>();
  const fs::path file = dir / entry.at("image").get<std::string>();
  const std::optional<std::string> bytes = read_file(file);
  if (!bytes) throw std::runtime_error("cannot read " + file.string());
  std::shared_ptr<const StoredTexture> image = read_stored_texture(*bytes, limits);
  texture.id = image->id;
  catalogue.images.emplace(image->id, std::move(image));
  return texture;
}

std::string textures_answer_of(const Catalogue& catalogue, const json& document) {
  json textures = json::array();
  for (const CatalogueTexture& texture : catalogue.textures) {
    const StoredTexture& image = *catalogue.images.at(texture.id);
    textures.push_back({{"id", texture.id},
                        {"catalog_id", texture.catalog_id},
                        {"name", texture.name},
                        {"category", texture.category},
                        {"size_cm", {{"width", texture.width_cm}, {"height", texture.height_cm}}},
                        {"pixels", {{"width", image.image->width()}, {"height", image.image->height()}}},
                        {"url", "/v1/textures/" + texture.id}});
  }
  return json{{"textures", std::move(textures)},
              {"licence", document.value("licence", "")},
              {"attribution", document.value("attribution", "")}}
      .dump();
}

std::string quoted_hash(const std::string& text) {
  // Appended, not concatenated: GCC 12 warns of a memcpy overlap in "\"" + std::string (-Wrestrict).
  std::string out;
  out.append(1, '"').append(hash_hex(text)).append(1, '"');
  return out;
}

void read_textures(const fs::path& dir, const ParseLimits& limits, Catalogue& catalogue) {
  const fs::path index = dir / "textures.json";
  json document = json::object();
  if (const std::optional<std::string> text = dir.empty() ? std::nullopt : read_file(index)) {
    try {
      document = json::parse(*text);
      for (const json& entry : document.at("textures")) {
        try {
          catalogue.textures.push_back(read_texture(entry, dir, limits, catalogue));
        } catch (const std::exception& e) {
          catalogue.problems.push_back("catalogue texture " + entry.value("catalog_id", std::string("?")) +
                                       " is left out: " + e.what());
        }
      }
    } catch (const json::exception& e) {
      throw std::runtime_error(index.string() + " does not read: " + e.what());
    }
  }
  catalogue.textures_answer = textures_answer_of(catalogue, document);
  catalogue.textures_etag = quoted_hash(catalogue.textures_answer);
}

}  // namespace

const CatalogueItem* Catalogue::find(const std::string& id) const {
  for (const CatalogueItem& item : items) {
    if (item.id == id) return &item;
  }
  return nullptr;
}

std::shared_ptr<const Catalogue> load_catalogue(const fs::path& dir, const ParseLimits& limits) {
  auto catalogue = std::make_shared<Catalogue>();
  const fs::path index = dir / "catalogue.json";
  if (const std::optional<std::string> text = dir.empty() ? std::nullopt : read_file(index)) {
    json document;
    try {
      document = json::parse(*text);
      catalogue->licence = document.value("licence", "");
      catalogue->attribution = document.value("attribution", "");
      for (const json& entry : document.at("items")) {
        try {
          catalogue->items.push_back(read_item(entry, dir, limits, *catalogue));
        } catch (const std::exception& e) {
          catalogue->problems.push_back("catalogue entry " + entry.value("id", std::string("?")) +
                                        " is left out: " + e.what());
        }
      }
    } catch (const json::exception& e) {
      throw std::runtime_error(index.string() + " does not read: " + e.what());
    }
  }
  catalogue->answer = answer_of(*catalogue);
  catalogue->etag = quoted_hash(catalogue->answer);
  read_textures(dir, limits, *catalogue);
  return catalogue;
}

}  // namespace rr::server

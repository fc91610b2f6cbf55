// POST /v1/import/{format}: a file made by another tool (a Sweet Home 3D Home.xml, .sh3d or zip of a
// home and its furniture models, an R2V floor plan, a Wavefront OBJ model or a zip of one and its
// .mtl) -> the complete render request it describes (render/import/import.hpp), ready for POST
// /v1/render. With ?store=1 the scene is stored instead (as POST /v1/scenes), its furniture meshes
// each once in the mesh store (as POST /v1/meshes) placed by ref, its images each once in the image
// store (as POST /v1/textures) named by id, and the answer names it and carries the default camera
// and options. Query: scale (metres per file unit; the format's
// default otherwise), width and height (the request's image size), store, furniture (boxes|models:
// models by default when the file is a zip, which is where they come from).
// Files of other tools are larger than requests: the route has its own body limit
// (--max-import-bytes, 64 MiB), and importing holds a render slot like a render does.
#include "render/core/hash.hpp"
#include "render/core/texture.hpp"
#include "render/import/import.hpp"
#include "render/scene_io/mesh_json.hpp"
#include "server/problem.hpp"
#include "server/routes.hpp"

#include <httplib.h>

#include <charconv>
#include <cmath>
#include <map>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

double number_param(const Request& req, const std::string& name, double fallback, double lo, double hi) {
  if (!req.has_param(name.c_str())) return fallback;
  const std::string text = req.get_param_value(name.c_str());
  double value = 0.0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value) || value < lo || value > hi) {
    throw HttpError(400,
                    "The query parameter " + name + " must be a number in [" + std::to_string(lo) + ", " +
                        std::to_string(hi) + "].",
                    {{"", "not a number in range: \"" + quote_input(text) + "\"", name}});
  }
  return value;
}

bool furniture_param(const Request& req, bool fallback) {
  if (!req.has_param("furniture")) return fallback;
  const std::string text = req.get_param_value("furniture");
  if (text != "boxes" && text != "models") {
    throw HttpError(400, "The query parameter furniture must be boxes or models.",
                    {{"", "not boxes or models: \"" + quote_input(text) + "\"", "furniture"}});
  }
  return text == "models";
}

// Each distinct furniture mesh of `imported` stored once (as POST /v1/meshes stores it), and the
// solids and parts placing it rewritten to name its stored id.
void store_furniture_meshes(ServiceState& state, ImportResult& imported) {
  std::map<std::string, std::string> stored_ids;
  for (const auto& [key, mesh] : imported.meshes) {
    std::shared_ptr<const StoredMesh> stored;
    try {
      stored = prepare_mesh(mesh_from_json(mesh, state.limits));
    } catch (const InputError& e) {  // the importer wrote it, so only a limit can refuse it
      throw InputError(e.kind(), "", "furniture mesh " + key + ": " + e.summary());
    }
    store_document(state, stored);
    stored_ids[key] = stored->id;
  }
  for_each_mesh_holder(imported.request["scene"]["solids"], [&](json& holder) {
    auto ref = holder.find("ref");
    if (ref != holder.end()) *ref = stored_ids.at(ref->get<std::string>());
  });
  imported.meshes.clear();
}

// The id of the image a data: URI holds, stored as POST /v1/textures stores it; an image of the
// server's texture catalogue is there already and is not decoded again. nullopt, with *problem
// saying why, when it does not decode.
std::optional<std::string> store_image(ServiceState& state, const std::string& uri, std::string* problem) {
  std::vector<uint8_t> bytes;
  if (!decode_data_uri(uri, state.limits.max_texture_image_bytes, bytes, problem)) return std::nullopt;
  const std::string encoded(bytes.begin(), bytes.end());
  if (std::string id = hash_hex(encoded); state.limits.builtin_texture && state.limits.builtin_texture(id)) return id;
  std::shared_ptr<const StoredTexture> stored;
  try {
    stored = read_stored_texture(encoded, state.limits);
  } catch (const InputError& e) {
    *problem = e.summary();
    return std::nullopt;
  }
  store_document(state, stored);
  return stored->id;
}

// Each distinct image of `imported`'s textures (a data: URI, as the importers write them) stored once
// (as POST /v1/textures stores it), and every texture showing it rewritten to name its stored id:
// a textured home's scene then holds each image's 16-digit id instead of megabytes of base64. An
// image the store refuses (its data does not decode; the importers checked the header) leaves its
// surfaces untextured, with a warning naming the first of them.
void store_texture_images(ServiceState& state, ImportResult& imported) {
  std::map<std::string, std::optional<std::string>> stored_ids;  // data: URI -> stored image id
  for_each_texture(imported.request["scene"], "", [&](json& texture, const std::string& pointer) {
    json& image = texture["image"];
    if (!image.is_string() || !image.get_ref<const std::string&>().starts_with("data:")) return true;
    auto [it, first] = stored_ids.try_emplace(image.get<std::string>());
    std::string problem;
    if (first && !(it->second = store_image(state, it->first, &problem))) {
      imported.warnings.push_back("the image of " + pointer +
                                  " (and of any surface sharing it) was refused: " + problem + "; drawn untextured");
    }
    if (!it->second) return false;
    image = *it->second;
    return true;
  });
}

void handle_import(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  const ImportFormatInfo* format = find_import_format(match.params.at(0));
  if (!format) throw HttpError(404, "There is no importer " + match.params[0] + ".");
  ImportOptions options;
  options.scale = number_param(req, "scale", 0.0, 1e-6, 1e6);
  options.width = int(number_param(req, "width", options.width, 1, state.config.limits.max_image_side));
  options.height = int(number_param(req, "height", options.height, 1, state.config.limits.max_image_side));
  const bool store = number_param(req, "store", 0, 0, 1) == 1.0;
  options.furniture_models = furniture_param(req, looks_like_zip(req.body));

  options.mesh_refs = store;  // stored meshes keep each furniture mesh once; answers inline them

  ImportResult imported;
  std::shared_ptr<const StoredScene> scene;
  with_render_slot(state, [&](const CancelToken&, Stopwatch&) {
    imported = import_file_text(req.body, format->format, options);  // companion files only from a zip
    if (!store) return;
    store_furniture_meshes(state, imported);
    store_texture_images(state, imported);
    scene = prepare_scene(imported.request.at("scene"), state.limits, render_threads(state.config));
  });
  json warnings = json::array();
  for (const std::string& w : imported.warnings) warnings.push_back(w);
  res.set_header("X-Warning-Count", std::to_string(imported.warnings.size()));
  if (!store) {
    send_json(res, imported.request);
    return;
  }
  store_and_answer(
      state, res, scene,
      {{"camera", imported.request.at("camera")}, {"options", imported.request.at("options")}, {"warnings", warnings}});
}

}  // namespace

std::vector<Route> import_routes(const ServerConfig& config) {
  // What clients send files as; the format comes from the path, not the media type.
  const std::vector<std::string> files = {
      "application/octet-stream",    "application/xml", "text/xml", "application/zip",
      "application/vnd.sweethome3d", "text/plain",      "model/obj"};
  Route route{"POST", "/v1/import/{format}", files, {"application/json"}, handle_import};
  route.max_body_bytes = config.max_import_bytes;
  route.access = Access::write_when_stored;
  return {route};
}

}  // namespace rr::server

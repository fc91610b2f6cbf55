// Stored images: POST /v1/textures (the encoded bytes of a PNG or JPEG as the body, told apart by
// their first bytes, whatever the Content-Type says) -> 201 and the image's id, the hash of its
// bytes, so sending the same bytes again answers 200 with the same id; GET /v1/textures/{id} (the
// bytes as sent, image/png or image/jpeg) and DELETE /v1/textures/{id}, refused with 409 while a
// stored scene's texture names the image. The caps are an inline image's: 413 over them, 422 for
// what does not decode.
#include "server/problem.hpp"
#include "server/routes.hpp"

#include <httplib.h>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

// The body decoded with the service's texture caps; decoding holds a render slot, as parsing a mesh does.
std::shared_ptr<const StoredTexture> read_texture_body(ServiceState& state, const Request& req) {
  std::shared_ptr<const StoredTexture> texture;
  with_render_slot(state,
                   [&](const CancelToken&, Stopwatch&) { texture = read_stored_texture(req.body, state.limits); });
  return texture;
}

void handle_post_texture(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  std::shared_ptr<const StoredTexture> stored = read_texture_body(state, req);
  store_and_answer(state, res, stored,
                   {{"media_type", texture_media_type(stored->text)},
                    {"width", stored->image->width()},
                    {"height", stored->image->height()},
                    {"bytes", stored->text.size()}});
}

void handle_get_texture(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  const std::string& id = match.params.at(0);
  std::optional<std::string> bytes = state.cache.text<StoredTexture>(id);
  if (!bytes) throw HttpError(404, "There is no stored image " + id + ".");
  send_stored_document(req, res, id, *bytes, texture_media_type(*bytes));
}

// With tokens, a delete drops the caller's reference only; the image goes with the last one, unless
// a stored scene's texture names it (409, naming a few of those scenes).
void handle_delete_texture(ServiceState& state, const Request&, Response& res, const RouteMatch& match) {
  const std::optional<std::string> owner = releasing_owner(state);
  const std::string& id = match.params.at(0);
  const TextureDocuments::ReleaseResult released = state.stores.textures->release(id, owner);
  if (released == TextureDocuments::ReleaseResult::removed) state.cache.forget<StoredTexture>(id);
  switch (released) {
    case TextureDocuments::ReleaseResult::not_found:
      throw HttpError(404, "There is no stored image " + id + ".");
    case TextureDocuments::ReleaseResult::not_owner:
      throw HttpError(
          403, "The image " + id + " is stored, but not by this token's owner; only an owner can drop its reference.");
    case TextureDocuments::ReleaseResult::pinned: {
      std::vector<FieldError> errors;
      std::string list;
      for (const std::string& scene : state.stores.textures->pinned_by(id, 5)) {
        errors.push_back({"", "used by stored scene " + scene});
        list += (list.empty() ? "" : ", ") + scene;
      }
      throw HttpError(409,
                      "The image " + id + " is used by the textures of stored scenes (" + list +
                          (errors.size() == 5 ? ", ..." : "") +
                          "); delete those scenes first. An image stays while a stored scene uses it.",
                      errors);
    }
    case TextureDocuments::ReleaseResult::read_only:  // no image ships with the server
    case TextureDocuments::ReleaseResult::removed:
    case TextureDocuments::ReleaseResult::reference_dropped:
      res.status = 204;
  }
}

}  // namespace

std::vector<Route> texture_routes() {
  // What clients send image files as; the format comes from the bytes, not the media type.
  const std::vector<std::string> images = {"image/png", "image/jpeg", "application/octet-stream"};
  std::vector<Route> routes = {
      {"POST", "/v1/textures", images, {"application/json"}, handle_post_texture},
      {"GET", "/v1/textures/{id}", {}, {}, handle_get_texture},
      {"DELETE", "/v1/textures/{id}", {}, {}, handle_delete_texture},
  };
  for (Route& r : routes) r.access = r.method == "GET" ? Access::read : Access::write;
  return routes;
}

}  // namespace rr::server

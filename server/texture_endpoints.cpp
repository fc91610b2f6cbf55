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
// a stored scene's texture names it (409, naming a few of those scenes). The texture catalogue's
// images are read-only (403).
void handle_delete_texture(ServiceState& state, const Request&, Response& res, const RouteMatch& match) {
  release_and_answer<StoredTexture>(
      state, res, match.params.at(0),
      {"image", "used by stored scene", "used by the textures of stored scenes",
       "An image stays while a stored scene uses it.",
       " is part of the server's texture catalogue (GET /v1/catalogue/textures): it is read-only and stays for "
       "every scene that uses it."});
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

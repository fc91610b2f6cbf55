// The furniture catalogue (catalogue.hpp): GET /v1/catalogue lists its entries (id, name, category,
// real size in cm, icon URL, and the piece a client places: its parts name read-only stored meshes),
// GET /v1/catalogue/{name}/icon.png serves an entry's icon, GET /v1/catalogue/textures lists the
// texture catalogue (id of the read-only stored image, Sweet Home 3D's catalogue id, name, category,
// one tile's size in cm, pixels, image URL). All are the same on every replica and
// for the life of the server: cacheable, with an ETag.
#include "server/problem.hpp"
#include "server/routes.hpp"

#include <httplib.h>

#include <fstream>
#include <sstream>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;

void handle_catalogue(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  const Catalogue& catalogue = *state.catalogue;
  res.set_header("Cache-Control", "public, max-age=3600");
  if (answer_not_modified(req, res, catalogue.etag)) return;
  res.set_content(catalogue.answer, "application/json");
}

void handle_textures(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  const Catalogue& catalogue = *state.catalogue;
  res.set_header("Cache-Control", "public, max-age=3600");
  if (answer_not_modified(req, res, catalogue.textures_etag)) return;
  res.set_content(catalogue.textures_answer, "application/json");
}

void handle_icon(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  const CatalogueItem* item = state.catalogue->find(match.params.at(0));
  if (!item) throw HttpError(404, "The catalogue has no entry " + match.params[0] + ".");
  std::ifstream in(item->icon, std::ios::binary);
  if (!in) throw HttpError(404, "The catalogue entry " + item->id + " has no icon on this server.");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  res.set_header("Cache-Control", "public, max-age=3600");
  if (answer_not_modified(req, res, state.catalogue->etag)) return;
  res.set_content(bytes.str(), "image/png");
}

}  // namespace

std::vector<Route> catalogue_routes() {
  return {
      {"GET", "/v1/catalogue", {}, {"application/json"}, handle_catalogue},
      {"GET", "/v1/catalogue/textures", {}, {"application/json"}, handle_textures},
      {"GET", "/v1/catalogue/{name}/icon.png", {}, {"image/png"}, handle_icon},
  };
}

}  // namespace rr::server

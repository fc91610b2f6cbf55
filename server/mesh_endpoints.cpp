// Stored meshes: POST /v1/meshes (an OBJ file as text/plain or model/obj, or a JSON mesh document
// {"vertices", "faces"[, "normals"]} as application/json) -> 201 and the mesh's id, its content hash,
// so sending it again (in either form) answers 200 with the same id; GET /v1/meshes/{id} (the
// canonical JSON mesh) and DELETE /v1/meshes/{id}, refused with 409 while a stored scene places the
// mesh. OBJ errors name their line ("/line/17"), JSON errors their pointer ("/faces/7/2").
#include "render/import/obj_mesh.hpp"
#include "render/scene_io/mesh_json.hpp"
#include "server/problem.hpp"
#include "server/routes.hpp"

#include <httplib.h>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

json vec_json(Vec3 v) { return json::array({v.x, v.y, v.z}); }

// The body as a mesh; parsing holds a render slot, as storing a scene does.
std::shared_ptr<const MeshData> read_mesh_body(ServiceState& state, const Request& req,
                                               std::vector<std::string>& warnings) {
  std::shared_ptr<const MeshData> mesh;
  with_render_slot(state, [&](const CancelToken&, Stopwatch&) {
    const std::string type = req.get_header_value("Content-Type");
    if (type.starts_with("application/json")) {
      mesh = mesh_from_json(parse_body(state, req), state.limits);
      return;
    }
    json document = obj_mesh_document(req.body, warnings);
    try {
      mesh = mesh_from_json(document, state.limits);
    } catch (const InputError& e) {  // repaired OBJ faces pass; only limits land here
      throw InputError(e.kind(), "", e.summary());
    }
  });
  return mesh;
}

void handle_post_mesh(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  std::vector<std::string> warnings;
  std::shared_ptr<const StoredMesh> stored = prepare_mesh(read_mesh_body(state, req, warnings));
  const MeshData& mesh = *stored->mesh;
  store_and_answer(state, res, stored,
                   {{"vertices", mesh.vertices.size()},
                    {"faces", mesh.faces.size()},
                    {"normals", !mesh.normals.empty()},
                    {"bounds", {{"min", vec_json(mesh.bounds_min)}, {"max", vec_json(mesh.bounds_max)}}},
                    {"warnings", warnings}});
}

void handle_get_mesh(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  const std::string& id = match.params.at(0);
  std::optional<std::string> text = state.cache.text<StoredMesh>(id);
  if (!text) throw HttpError(404, "There is no stored mesh " + id + ".");
  send_stored_document(req, res, id, *text);
}

// With tokens, a delete drops the caller's reference only; the mesh goes with the last one, unless
// a stored scene places it (409, naming a few of those scenes).
void handle_delete_mesh(ServiceState& state, const Request&, Response& res, const RouteMatch& match) {
  release_and_answer<StoredMesh>(
      state, res, match.params.at(0),
      {"mesh", "placed by stored scene", "placed by stored scenes", "A mesh stays while a stored scene places it.",
       " is part of the server's furniture catalogue (GET /v1/catalogue): it is read-only and stays for every scene "
       "that places it."});
}

}  // namespace

std::vector<Route> mesh_routes(const ServerConfig& config) {
  const std::vector<std::string> bodies = {"application/json", "text/plain", "model/obj", "application/octet-stream"};
  const std::vector<std::string> json_answer = {"application/json"};
  std::vector<Route> routes = {
      {"POST", "/v1/meshes", bodies, json_answer, handle_post_mesh},
      {"GET", "/v1/meshes/{id}", {}, json_answer, handle_get_mesh},
      {"DELETE", "/v1/meshes/{id}", {}, {}, handle_delete_mesh},
  };
  routes[0].max_body_bytes = config.max_import_bytes;  // an OBJ is text, larger than its JSON request
  for (Route& r : routes) r.access = r.method == "GET" ? Access::read : Access::write;
  return routes;
}

}  // namespace rr::server

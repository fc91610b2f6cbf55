// Stored scenes: POST /v1/scenes (the server names it), PUT /v1/scenes/{id} (the client names it,
// and the name must be the content's hash), GET and DELETE /v1/scenes/{id}. Bodies are scene
// documents (scene.schema.json); errors point into them ("/walls/0/end"). Storing parses and
// tessellates, so it holds a render slot like a render does.
#include "server/routes.hpp"

#include "render/core/timer.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "server/problem.hpp"

#include <httplib.h>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

std::string scene_location(const std::string& id) { return "/v1/scenes/" + id; }

std::shared_ptr<const StoredScene> read_scene_body(ServiceState& state, const Request& req) {
  std::shared_ptr<const StoredScene> scene;
  with_render_slot(state, [&](const CancelToken&, Stopwatch&) {
    scene = prepare_scene(parse_body(state, req), state.config.limits);
  });
  return scene;
}

void store_and_answer(ServiceState& state, Response& res, const std::shared_ptr<const StoredScene>& scene) {
  request_context().scene_id = scene->static_id;
  SceneStore::PutResult result = state.scenes.put(scene);
  if (result == SceneStore::PutResult::conflict) {
    throw HttpError(409, "A different scene with the id " + scene->id + " is stored already (a hash collision).",
                    {{"", "content differs from the stored scene with this id"}});
  }
  if (result == SceneStore::PutResult::too_large) {
    throw HttpError(413, "The stored form of this scene takes about " + std::to_string(scene->bytes) +
                             " bytes; the scene store holds at most " +
                             std::to_string(state.scenes.config().max_bytes) + ".",
                    {{"", "scene too large to store"}});
  }
  json warnings = json::array();
  for (const WarningText& w : describe(scene->warnings, scene->scene, "")) {
    warnings.push_back({{"pointer", w.pointer}, {"detail", w.detail}});
  }
  res.set_header("Location", scene_location(scene->id));
  res.set_header("X-Scene-Id", scene->static_id);
  send_json(res,
            {{"id", scene->id}, {"location", scene_location(scene->id)}, {"scene_id", scene->static_id},
             {"created", result == SceneStore::PutResult::created}, {"warnings", warnings}},
            result == SceneStore::PutResult::created ? 201 : 200);
}

void handle_post_scene(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  store_and_answer(state, res, read_scene_body(state, req));
}

void handle_put_scene(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  auto scene = read_scene_body(state, req);
  if (scene->id != match.params.at(0)) {
    throw HttpError(422, "Scene ids are content hashes: this scene's id is " + scene->id + ", not " +
                             quote_input(match.params[0]) + "; PUT it at " + scene_location(scene->id) + " (or POST it to /v1/scenes).",
                    {{"", "content hashes to " + scene->id}});
  }
  store_and_answer(state, res, scene);
}

void handle_get_scene(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  auto scene = state.scenes.find(match.params.at(0));
  if (!scene) throw HttpError(404, "There is no stored scene " + match.params[0] + ".");
  request_context().scene_id = scene->static_id;
  res.set_header("Cache-Control", "public, max-age=31536000, immutable");  // content-addressed
  res.set_header("X-Scene-Id", scene->static_id);
  if (answer_not_modified(req, res, "\"" + scene->id + "\"")) return;
  res.set_content(scene->text, "application/json");
}

void handle_delete_scene(ServiceState& state, const Request&, Response& res, const RouteMatch& match) {
  if (!state.scenes.erase(match.params.at(0))) {
    throw HttpError(404, "There is no stored scene " + match.params[0] + ".");
  }
  res.status = 204;
}

}  // namespace

std::vector<Route> scene_routes() {
  const std::vector<std::string> json_body = {"application/json"};
  const std::vector<std::string> json_answer = {"application/json"};
  const char* one = "/v1/scenes/([0-9a-f]{16})";
  return {
      {"POST", "/v1/scenes", "/v1/scenes", json_body, json_answer, handle_post_scene},
      {"PUT", "/v1/scenes/{id}", one, json_body, json_answer, handle_put_scene},
      {"GET", "/v1/scenes/{id}", one, {}, json_answer, handle_get_scene},
      {"DELETE", "/v1/scenes/{id}", one, {}, {}, handle_delete_scene},
  };
}

}  // namespace rr::server

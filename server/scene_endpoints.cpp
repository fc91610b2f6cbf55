// Stored scenes: POST /v1/scenes (the server names it), PUT /v1/scenes/{id} (the client names it,
// and the name must be the content's hash), GET and DELETE /v1/scenes/{id}, and GET /v1/scenes (a
// page of stored scenes, newest first). Bodies are scene documents (scene.schema.json) or whole
// render requests, whose "scene" is stored (a scene document has no "scene" member, so the two never
// mix up); errors point into the body as sent. Storing parses and tessellates, so it holds a render
// slot like a render does. Writes and listing are screened for origin and token before they get here.
#include "server/routes.hpp"

#include "render/core/timer.hpp"
#include "render/scene_io/report_json.hpp"
#include "server/problem.hpp"

#include <httplib.h>

#include <charconv>
#include <stdexcept>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;
using Clock = SceneDocuments::Clock;

// The scene of a body, and where it sits in the body ("" for a scene document, "/scene" in a whole
// request), so errors and warnings point into what the client sent.
struct SceneBody {
  std::shared_ptr<const StoredScene> scene;
  std::string pointer;
};

SceneBody read_scene_body(ServiceState& state, const Request& req) {
  SceneBody out;
  with_render_slot(state, [&](const CancelToken&, Stopwatch&) {
    json body = parse_body(state, req);
    if (!body.is_object() || !body.contains("scene")) {
      out.scene = prepare_scene(body, state.limits, render_threads(state.config));
      return;
    }
    out.pointer = "/scene";  // a whole render request: its camera and options are not stored
    try {
      out.scene = prepare_scene(body["scene"], state.limits, render_threads(state.config));
    } catch (const InputError& e) {
      throw InputError(e.kind(), out.pointer + e.pointer(), e.what());
    }
  });
  return out;
}

void answer_stored(ServiceState& state, Response& res, const SceneBody& sent) {
  store_and_answer(state, res, sent.scene,
                   {{"warnings", warnings_json(sent.scene->warnings, sent.scene->scene, sent.pointer)},
                    {"warning_count", placement_problem_count(sent.scene->warnings)}});
}

void handle_post_scene(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  answer_stored(state, res, read_scene_body(state, req));
}

void handle_put_scene(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  SceneBody sent = read_scene_body(state, req);
  const std::shared_ptr<const StoredScene>& scene = sent.scene;
  if (scene->id != match.params.at(0)) {
    throw HttpError(422,
                    "Scene ids are content hashes: this scene's id is " + scene->id + ", not " +
                        quote_input(match.params[0]) + "; PUT it at " + location_of<StoredScene>(scene->id) +
                        " (or POST it to /v1/scenes).",
                    {{sent.pointer, "content hashes to " + scene->id}});
  }
  answer_stored(state, res, sent);
}

// The document as stored, byte for byte; reading it prepares nothing (its static id is parsed out
// when the scene is not held prepared).
void handle_get_scene(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  const std::string& id = match.params.at(0);
  std::optional<std::string> text = state.cache.text<StoredScene>(id);
  if (!text) throw HttpError(404, "There is no stored scene " + id + ".");
  const std::string static_id = state.cache.static_id(id, *text);
  request_context().scene_id = static_id;
  res.set_header("X-Scene-Id", static_id);
  send_stored_document(req, res, id, *text);
}

// With tokens, a delete drops the caller's reference only; the scene goes with the last one. Scenes
// are never pinned nor read-only.
void handle_delete_scene(ServiceState& state, const Request&, Response& res, const RouteMatch& match) {
  release_and_answer<StoredScene>(state, res, match.params.at(0), {"scene"});
}

size_t limit_param(const Request& req) {
  constexpr size_t fallback = 100, most = 1000;
  if (!req.has_param("limit")) return fallback;
  const std::string text = req.get_param_value("limit");
  size_t value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < 1 || value > most) {
    throw HttpError(400, "The query parameter limit must be an integer in [1, " + std::to_string(most) + "].",
                    {{"", "not an integer in range: \"" + quote_input(text) + "\"", "limit"}});
  }
  return value;
}

// Ids act as capabilities (whoever knows one may render it), so listing them is per owner with
// tokens and off on an open server unless the operator turns it on.
void handle_list_scenes(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  const bool tokens = !state.access.tokens.empty();
  if (!tokens && !state.access.allow_listing) {
    throw HttpError(403,
                    "Listing stored scenes is off on this server: stored ids act as capabilities. The "
                    "operator turns it on with --allow-listing 1, or gives tokens (--api-token-file).");
  }
  const size_t limit = limit_param(req);
  const std::string cursor = req.has_param("cursor") ? req.get_param_value("cursor") : "";
  SceneDocuments::Page page;
  try {
    page = state.stores.scenes->list(tokens ? std::optional(request_context().owner) : std::nullopt, limit, cursor);
  } catch (const std::invalid_argument&) {
    throw HttpError(400, "The query parameter cursor must be the \"next\" of an earlier page.",
                    {{"", "not a cursor: \"" + quote_input(cursor) + "\"", "cursor"}});
  }
  json scenes = json::array();
  for (const SceneDocuments::Listed& s : page.scenes) {
    scenes.push_back({{"id", s.id},
                      {"location", location_of<StoredScene>(s.id)},
                      {"created", time_or_null(Clock::time_point(std::chrono::microseconds(s.created_us)))},
                      {"expires", time_or_null(s.expires)},
                      {"bytes", s.bytes}});
  }
  json next = nullptr;
  if (page.next_cursor) next = "/v1/scenes?limit=" + std::to_string(limit) + "&cursor=" + *page.next_cursor;
  res.set_header("Cache-Control", "no-store");
  send_json(res, {{"scenes", scenes}, {"next", next}});
}

}  // namespace

std::vector<Route> scene_routes() {
  const std::vector<std::string> json_body = {"application/json"};
  const std::vector<std::string> json_answer = {"application/json"};
  std::vector<Route> routes = {
      {"POST", "/v1/scenes", json_body, json_answer, handle_post_scene},
      {"PUT", "/v1/scenes/{id}", json_body, json_answer, handle_put_scene},
      {"GET", "/v1/scenes/{id}", {}, json_answer, handle_get_scene},
      {"DELETE", "/v1/scenes/{id}", {}, {}, handle_delete_scene},
      {"GET", "/v1/scenes", {}, json_answer, handle_list_scenes},
  };
  for (Route& r : routes) r.access = r.method == "GET" ? Access::read : Access::write;
  routes.back().access = Access::owner_read;
  return routes;
}

}  // namespace rr::server

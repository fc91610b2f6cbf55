// Picking: POST /v1/pick ({scene, camera, options, x, y}) and POST /v1/scenes/{id}/pick ({camera,
// options, x, y}) answer which element of the scene is visible at image pixel (x, y): the frame is
// drawn as /v1/render would draw it (not encoded) and its id buffer names the polygon there, whose
// object names the element as a JSON Pointer into the document the client sent (as warnings do): a
// piece whole, with the part under the pixel as a detail.
#include "server/routes.hpp"

#include "render/core/camera.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "server/http_util.hpp"
#include "server/problem.hpp"
#include "server/serve_command.hpp"

#include <httplib.h>

#include <cmath>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

struct PixelRequest {
  json view;  // the body without x and y: what request_from_json reads
  json x, y;
};

// Takes x and y out of the body so the rest parses as a render request (which refuses them).
PixelRequest split_pixel(json body) {
  PixelRequest out;
  if (body.is_object()) {
    for (auto [key, slot] : {std::pair{"x", &out.x}, std::pair{"y", &out.y}}) {
      if (auto it = body.find(key); it != body.end()) {
        *slot = *it;
        body.erase(it);
      }
    }
  }
  out.view = std::move(body);
  return out;
}

// A pixel coordinate within [0, size): 422 at the member otherwise.
int pixel_coordinate(const json& value, const char* name, int size, const char* side) {
  const std::string pointer = std::string("/") + name;
  const std::string range = std::to_string(size - 1);
  const std::string expected =
      "an integer pixel index from 0 to " + range + " (the image is " + std::to_string(size) + " pixels " + side + ")";
  if (value.is_null()) throw InputError(InputError::Kind::invalid, pointer, "is required: " + expected);
  if (!value.is_number_integer() || value.get<long long>() < 0 || value.get<long long>() >= size) {
    throw InputError(InputError::Kind::invalid, pointer, "must be " + expected);
  }
  return int(value.get<long long>());
}

// The world point seen through the centre of pixel (x, y) on the plane of `polygon`.
Vec3 point_on_polygon(const Camera& camera, int width, int height, int x, int y, const Polygon& polygon) {
  const ViewTransform view = make_view(camera, width, height);
  const Mat4 world_from_clip = glm::inverse(view.clip_from_world);
  const double nx = (x + 0.5) / width * 2.0 - 1.0, ny = 1.0 - (y + 0.5) / height * 2.0;
  const Vec4 far_h = world_from_clip * Vec4(nx, ny, 1.0, 1.0);
  const Vec3 direction = glm::normalize(Vec3(far_h) / far_h.w - camera.position);
  const double along = glm::dot(polygon.normal, direction);
  const double t = along != 0.0 ? (polygon.offset - glm::dot(polygon.normal, camera.position)) / along : 0.0;
  return camera.position + direction * t;
}

json vec_json(Vec3 v) { return json::array({v.x, v.y, v.z}); }

// Draws the view (no PNG) and answers the element at the pixel; runs holding a render slot.
void pick_and_answer(ServiceState& state, Response& res, const PixelRequest& pixel, const RenderRequest& view,
                     const PreparedScene& scene, std::string_view scene_pointer, const CancelToken& token) {
  const int x = pixel_coordinate(pixel.x, "x", view.options.width, "wide");
  const int y = pixel_coordinate(pixel.y, "y", view.options.height, "tall");
  {
    RenderContext context{&state.cache.bsp, &token, scene.static_id, &state.cache.shadow};
    context.view_cache = &state.cache.views;
    context.threads = render_threads(state.config);
    context.encode = false;
    const RenderOutcome out = state.workers.run([&] { return render(view, scene, context); });
    const uint32_t id = out.frame.ids.at(x, y);
    json body = {{"x", x},
                 {"y", y},
                 {"scene_id", scene.static_id},
                 {"pointer", nullptr},
                 {"part", nullptr},
                 {"polygon", nullptr},
                 {"point", nullptr},
                 {"depth", nullptr},
                 {"camera", camera_json(out.camera)}};
    if (id != background_id && id < scene.soup.polygons.size()) {
      const Polygon& polygon = scene.soup.polygons[id];
      const Vec3 point = point_on_polygon(out.camera, view.options.width, view.options.height, x, y, polygon);
      const Vec3 forward = glm::normalize(out.camera.target - out.camera.position);
      const ElementRef element = scene.soup.objects[polygon.object].element;
      body["pointer"] = element_pointer(element, scene_pointer);
      // A piece is picked whole; the part under the pixel is a detail of the answer.
      if (const int part = polygon_part(scene.soup, id); part >= 0) {
        const PiecePart& p = scene.scene.geometry.solids[element.index].parts[size_t(part)];
        body["part"] = {{"index", part},
                        {"pointer", body["pointer"].get<std::string>() + "/parts/" + std::to_string(part)},
                        {"name", p.name}};
      }
      body["polygon"] = id;
      body["point"] = vec_json(point);
      body["depth"] = glm::dot(point - out.camera.position, forward);
    }
    res.set_header("X-Scene-Id", scene.static_id);
    send_json(res, body);
  }
}

void handle_pick(ServiceState& state, const Request& req, Response& res, const RouteMatch&) {
  res.set_header("Cache-Control", "no-store");
  with_render_slot(state, [&](const CancelToken& token, SlotClock&) {  // parsing included, as /v1/render
    PixelRequest pixel = split_pixel(parse_body(state, req));
    RenderRequest request = request_from_json(pixel.view, state.limits);
    check_cancel(&token);
    PreparedScene scene = prepare_scene(std::move(request.scene), 1, PrepareLamps::no);  // a pick casts no shadow ray
    request_context().scene_id = scene.static_id;
    pick_and_answer(state, res, pixel, request, scene, "/scene", token);
  });
}

// The scene is prepared holding the render slot: one the prepared cache evicted is rebuilt here.
void handle_stored_pick(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  res.set_header("Cache-Control", "no-store");
  with_render_slot(state, [&](const CancelToken& token, SlotClock&) {
    auto scene = state.cache.find<StoredScene>(match.params.at(0));
    if (!scene) throw HttpError(404, "There is no stored scene " + match.params[0] + ".");
    request_context().scene_id = scene->static_id;
    PixelRequest pixel = split_pixel(parse_body(state, req));
    if (pixel.view.is_object() && pixel.view.contains("scene")) {
      throw InputError(InputError::Kind::invalid, "/scene",
                       "a stored scene is picked with only camera, options, x and y; the scene is not allowed here");
    }
    RenderRequest request = request_from_json(pixel.view, state.limits);
    check_view_levels(request.options, scene->scene.geometry.levels);
    pick_and_answer(state, res, pixel, request, *scene, "", token);
  });
}

}  // namespace

nlohmann::json camera_json(const Camera& c) {
  return {{"position", vec_json(c.position)},
          {"target", vec_json(c.target)},
          {"up", vec_json(c.up)},
          {"fov_y", c.fov_y_deg},
          {"near", c.near},
          {"far", c.far}};
}

std::vector<Route> pick_routes() {
  const std::vector<std::string> json_body = {"application/json"};
  const std::vector<std::string> json_answer = {"application/json"};
  return {
      {"POST", "/v1/pick", json_body, json_answer, handle_pick},
      {"POST", "/v1/scenes/{id}/pick", json_body, json_answer, handle_stored_pick},
  };
}

}  // namespace rr::server

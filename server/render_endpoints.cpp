// Render endpoints: POST /v1/render (a whole request), POST /v1/scenes/{id}/render ({camera,
// options} for a stored scene) and GET /v1/scenes/{id}/render.png (camera and options as query
// parameters). All three end in draw_and_answer, which calls render() (render/pipelines/render.hpp)
// as the CLI does, so a stored scene, the same scene sent inline and `roomrender render` produce the
// same bytes. The ETag hashes the renderer version, the scene document, the camera and
// options as sent, and the response media type; a matching If-None-Match answers 304 before drawing.
#include "server/routes.hpp"

#include "render/core/timer.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/element_pointer.hpp"
#include "render/scene_io/report_json.hpp"
#include "server/http_util.hpp"
#include "server/problem.hpp"
#include "server/serve_command.hpp"

#include <httplib.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

const std::vector<std::string> render_types = {"image/png", "application/json"};

// A render about to be drawn: the prepared scene (stored, or prepared from the request) and the view.
struct FramePlan {
  const PreparedScene& scene;
  const RenderRequest& view;       // camera and options (its scene is unused)
  std::string_view scene_pointer;  // where the scene sits in the client's document: "/scene" or ""
  std::string etag;
  double parse_ms = 0.0;
  double tessellate_ms = 0.0;   // for a stored scene 0, unless the prepared cache had to rebuild it
  double before_slot_ms = 0.0;  // spent on this request before it queued for a slot (parse start on)
};

// The member of a request object, or {} when absent: absent and empty render alike.
const json& member(const json& object, const char* key) {
  static const json empty = json::object();
  if (!object.is_object()) return empty;
  auto it = object.find(key);
  return it == object.end() ? empty : *it;
}

std::string render_etag(const std::string& scene_hash, const json& view, const std::string& media_type) {
  std::string key = std::string(version()) + '\n' + media_type + '\n' + scene_hash + '\n' +
                    member(view, "camera").dump() + '\n' + member(view, "options").dump();
  return "\"" + hash_hex(key) + "\"";
}

// W3C Server-Timing with every stage of stage_table, so this header, the JSON answer's timings_ms and
// the CLI's line name the same stages.
std::string server_timing(const StageTimings& timings) {
  std::string header;
  char buffer[96];
  for (const StageField& stage : stage_table) {
    std::snprintf(buffer, sizeof buffer, "%s%s;dur=%.3f", header.empty() ? "" : ", ", stage.name, timings.*stage.ms);
    header += buffer;
  }
  return header;
}

void draw_and_answer(ServiceState& state, Response& res, const RouteMatch& match, const FramePlan& plan,
                     const CancelToken& token, const SlotClock& clock) {
  check_cancel(&token);
  RenderContext context{&state.cache.bsp, &token, plan.scene.static_id, &state.cache.shadow};
  context.view_cache = &state.cache.views;
  context.threads = render_threads(state.config);  // the server's setting, never the request's
  context.queue_ms = clock.queue_ms;
  context.parse_ms = plan.parse_ms;
  context.tessellate_ms = plan.tessellate_ms;
  context.before_ms = plan.before_slot_ms + clock.elapsed_ms();
  RenderOutcome out = state.workers.run([&] { return render(plan.view, plan.scene, context); });
  const RenderReport& report = out.report;

  const char* pipeline = pipeline_info(report.pipeline).name;
  state.metrics.record_render(pipeline, report.timings, report.stats);
  RequestContext& log = request_context();
  log.pipeline = pipeline;
  log.cache = report.stats.bsp_cache;

  res.set_header("Server-Timing", server_timing(report.timings));
  if (!report.stats.bsp_cache.empty()) res.set_header("X-Cache", report.stats.bsp_cache);
  res.set_header("X-Shadow-Cache", report.stats.shadow_cache);
  res.set_header("X-Exposure", nlohmann::json(report.exposure).dump());
  const size_t problems = placement_problem_count(plan.scene.warnings);
  res.set_header("X-Warning-Count", std::to_string(problems));
  if (match.media_type == "application/json") {
    nlohmann::ordered_json body = report_json(report);
    body["scene_id"] = report.scene_id;
    body["pipeline"] = pipeline;
    body["width"] = report.width;
    body["height"] = report.height;
    body["cache"] = report.stats.bsp_cache.empty() ? "none" : report.stats.bsp_cache;
    body["etag"] = plan.etag;
    // Warnings name elements of the document the client sent: the request inline, the scene document
    // when the scene is stored.
    body["warnings"] = warnings_json(plan.scene.warnings, plan.scene.scene, plan.scene_pointer);
    body["warning_count"] = problems;
    if (plan.view.camera.frame_all) body["camera"] = camera_json(out.camera);  // the frame chosen, to continue from
    body["png_base64"] = base64_encode(out.png);
    res.set_content(body.dump(), "application/json");
  } else {
    res.body = std::move(out.png);
    res.set_header("Content-Type", "image/png");
  }
  res.status = 200;
}

void handle_render(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  res.set_header("Cache-Control", "no-store");
  res.set_header("Vary", "Accept");
  with_render_slot(state, [&](const CancelToken& token, SlotClock& clock) {
    Stopwatch parse_clock;
    json body = parse_body(state, req);
    RenderRequest request = request_from_json(body, state.limits);
    double parse_ms = parse_clock.elapsed_ms();
    std::string etag = render_etag(hash_hex(member(body, "scene").dump()), body, match.media_type);
    if (answer_not_modified(req, res, etag)) return;  // before the scene is prepared: a 304 costs no tessellation
    check_cancel(&token);
    PreparedScene scene =
        prepare_scene(std::move(request.scene), render_threads(state.config), lamps_for(request.options));
    request_context().scene_id = scene.static_id;
    res.set_header("X-Scene-Id", scene.static_id);
    FramePlan plan{scene, request, "/scene", etag, parse_ms, scene.tessellate_ms};
    draw_and_answer(state, res, match, plan, token, clock);
  });
}

// A stored scene ready to draw, and what preparing it cost this request (0 when it was held).
struct StoredFrame {
  std::shared_ptr<const StoredScene> scene;
  double parse_ms = 0.0;       // reading the document, when it was rebuilt
  double tessellate_ms = 0.0;  // its tessellation and hierarchy, when it was rebuilt
};

// The stored scene the route names, prepared; 404 when not stored. Called holding a render slot:
// a scene the prepared cache evicted is rebuilt from its document here, which is a render's work.
StoredFrame require_scene(ServiceState& state, const RouteMatch& match) {
  Stopwatch clock;
  bool built = false;
  StoredFrame out{state.cache.find<StoredScene>(match.params.at(0), &built)};
  if (!out.scene) throw HttpError(404, "There is no stored scene " + match.params[0] + ".");
  request_context().scene_id = out.scene->static_id;
  if (built) {
    out.tessellate_ms = out.scene->tessellate_ms;
    out.parse_ms = std::max(0.0, clock.elapsed_ms() - out.tessellate_ms);
  }
  return out;
}

// The camera and options of a stored-scene render (which must not carry a scene of its own),
// validated; sets the ETag and answers 304 when it matches (then returns nullopt).
std::optional<std::pair<RenderRequest, std::string>> read_view(const ServiceState& state, const Request& req,
                                                               Response& res, const RouteMatch& match,
                                                               const StoredScene& scene, const json& view) {
  if (view.is_object() && view.contains("scene")) {
    throw InputError(InputError::Kind::invalid, "/scene",
                     "a stored scene is rendered with only camera and options; the scene is not allowed here");
  }
  RenderRequest request = request_from_json(view, state.limits);
  check_view_levels(request.options, scene.scene.geometry.levels);
  res.set_header("X-Scene-Id", scene.static_id);
  std::string etag = render_etag(scene.id, view, match.media_type);
  if (answer_not_modified(req, res, etag)) return std::nullopt;
  return std::pair{std::move(request), etag};
}

// `view_parse_ms`: reading the view; the scene's rebuild, if any, is added to parse and tessellate.
void draw_stored(ServiceState& state, Response& res, const RouteMatch& match, const StoredFrame& stored,
                 const std::pair<RenderRequest, std::string>& view, double view_parse_ms, const CancelToken& token,
                 const SlotClock& clock) {
  FramePlan plan{*stored.scene, view.first, "", view.second, view_parse_ms + stored.parse_ms, stored.tessellate_ms};
  draw_and_answer(state, res, match, plan, token, clock);
}

void handle_stored_render(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  res.set_header("Cache-Control", "no-store");
  res.set_header("Vary", "Accept");
  with_render_slot(state, [&](const CancelToken& token, SlotClock& clock) {
    StoredFrame stored = require_scene(state, match);
    Stopwatch parse_clock;
    auto view = read_view(state, req, res, match, *stored.scene, parse_body(state, req));
    if (view) draw_stored(state, res, match, stored, *view, parse_clock.elapsed_ms(), token, clock);
  });
}

// --- query parameters of GET /v1/scenes/{id}/render.png ------------------------------------------

enum class ParamKind { number, number_or_auto, integer, boolean, text, vec3 };

struct QueryParam {
  const char* name;
  const char* pointer;  // where the value goes in {camera, options}
  ParamKind kind;
};

// Documented in docs/api.md and schemas/openapi.json; each maps to one request member.
constexpr QueryParam query_params[] = {
    {"position", "/camera/position", ParamKind::vec3},
    {"target", "/camera/target", ParamKind::vec3},
    {"up", "/camera/up", ParamKind::vec3},
    {"fov_y", "/camera/fov_y", ParamKind::number},
    {"near", "/camera/near", ParamKind::number},
    {"far", "/camera/far", ParamKind::number},
    {"frame", "/camera/frame", ParamKind::text},
    {"width", "/options/width", ParamKind::integer},
    {"height", "/options/height", ParamKind::integer},
    {"pipeline", "/options/pipeline", ParamKind::text},
    {"shading", "/options/shading", ParamKind::text},
    {"shadows", "/options/shadows", ParamKind::boolean},
    {"painter_key", "/options/painter/key", ParamKind::text},
    {"bsp_w1", "/options/bsp/w1", ParamKind::number},
    {"bsp_w2", "/options/bsp/w2", ParamKind::number},
    {"bsp_w3", "/options/bsp/w3", ParamKind::number},
    {"bsp_epsilon", "/options/bsp/epsilon", ParamKind::number},
    {"bsp_max_candidates", "/options/bsp/max_candidates", ParamKind::integer},
    {"bsp_traversal", "/options/bsp/traversal", ParamKind::text},
    {"shadow_size", "/options/shadow/size", ParamKind::integer},
    {"shadow_pcf", "/options/shadow/pcf", ParamKind::integer},
    {"shadow_bias", "/options/shadow/bias", ParamKind::number},
    {"shadow_slope_bias", "/options/shadow/slope_bias", ParamKind::number},
    {"shadow_fit", "/options/shadow/fit", ParamKind::text},
    {"shadow_method", "/options/shadow/method", ParamKind::text},
    {"png", "/options/png/compression", ParamKind::text},
    {"antialias", "/options/antialias", ParamKind::integer},
    {"culling", "/options/culling", ParamKind::text},
    {"texture_filter", "/options/texture_filter", ParamKind::text},
    {"exposure", "/options/exposure", ParamKind::number_or_auto},
};

[[noreturn]] void bad_parameter(const QueryParam& p, const std::string& detail) {
  throw HttpError(400, "Query parameter '" + std::string(p.name) + "' " + detail + ".", {{p.pointer, detail, p.name}});
}

// A finite decimal number, all of `text` (no "nan", "inf", hex or leading '+'), as JSON: "50" is
// the integer 50 and "2.5" the double 2.5, as a JSON body would carry them, so a query and the
// equivalent POST body hash to the same ETag. Whether a non-integer suits an integer member is the
// validator's call (it answers 422 at the field).
std::optional<json> parse_number(std::string_view text) {
  const char* first = text.data();
  const char* last = text.data() + text.size();
  long long integer = 0;
  if (auto [end, ec] = std::from_chars(first, last, integer); !text.empty() && ec == std::errc() && end == last) {
    return json(integer);
  }
  double value = 0.0;
  auto [end, ec] = std::from_chars(first, last, value);
  if (text.empty() || ec != std::errc() || end != last || !std::isfinite(value)) return std::nullopt;
  return json(value);
}

json parse_param(const QueryParam& p, const std::string& text) {
  switch (p.kind) {
    case ParamKind::text:
      return text;
    case ParamKind::boolean:
      if (text == "true" || text == "false") return text == "true";
      bad_parameter(p, "must be true or false");
    case ParamKind::number_or_auto:
      if (text == "auto") return text;
      if (auto number = parse_number(text)) return *number;
      bad_parameter(p, "must be a finite number or auto");
    case ParamKind::integer:
    case ParamKind::number:
      if (auto number = parse_number(text)) return *number;
      bad_parameter(p, p.kind == ParamKind::integer ? "must be an integer" : "must be a finite number");
    case ParamKind::vec3: {
      json vec = json::array();
      size_t start = 0;
      for (int i = 0; i < 3; ++i) {
        size_t comma = i < 2 ? text.find(',', start) : text.size();
        auto number = comma == std::string::npos ? std::nullopt
                                                 : parse_number(std::string_view(text).substr(start, comma - start));
        if (!number || (i == 2 && text.find(',', start) != std::string::npos)) {
          bad_parameter(p, "must be three finite numbers separated by commas (x,y,z)");
        }
        vec.push_back(*number);
        start = comma + 1;
      }
      return vec;
    }
  }
  bad_parameter(p, "is not understood");
}

json view_from_query(const Request& req) {
  json view = json::object();
  for (const auto& [name, value] : req.params) {
    const QueryParam* param = nullptr;
    for (const QueryParam& p : query_params) {
      if (name == p.name) param = &p;
    }
    if (!param) {
      throw HttpError(400, "Unknown query parameter '" + quote_input(name) + "'.",
                      {{"", "unknown query parameter", quote_input(name)}});
    }
    if (req.get_param_value_count(name) > 1) bad_parameter(*param, "is given more than once");
    view[json::json_pointer(param->pointer)] = parse_param(*param, value);
  }
  return view;
}

// An InputError about the view built from the query, told in terms of the parameter.
[[noreturn]] void rethrow_for_query(const InputError& e) {
  for (const QueryParam& p : query_params) {
    std::string_view pointer = e.pointer();
    if (pointer == p.pointer || (pointer.starts_with(p.pointer) && pointer[std::strlen(p.pointer)] == '/')) {
      throw HttpError(status_for(e.kind()), "Query parameter '" + std::string(p.name) + "': " + e.what(),
                      {{e.pointer(), e.what(), p.name}});
    }
  }
  throw e;
}

void handle_render_png(ServiceState& state, const Request& req, Response& res, const RouteMatch& match) {
  // Content-addressed scene + every parameter in the URL: the answer at this URL never changes
  // (until the renderer's version does, which changes the ETag).
  res.set_header("Cache-Control", "public, max-age=31536000, immutable");
  with_render_slot(state, [&](const CancelToken& token, SlotClock& clock) {
    StoredFrame stored = require_scene(state, match);
    std::optional<std::pair<RenderRequest, std::string>> view;
    Stopwatch parse_clock;
    try {
      view = read_view(state, req, res, match, *stored.scene, view_from_query(req));
    } catch (const InputError& e) {
      rethrow_for_query(e);
    }
    if (view) draw_stored(state, res, match, stored, *view, parse_clock.elapsed_ms(), token, clock);
  });
}

}  // namespace

std::vector<Route> render_routes() {
  const std::vector<std::string> json_body = {"application/json"};
  return {
      {"POST", "/v1/render", json_body, render_types, handle_render},
      {"POST", "/v1/scenes/{id}/render", json_body, render_types, handle_stored_render},
      {"GET", "/v1/scenes/{id}/render.png", {}, {"image/png"}, handle_render_png},
  };
}

}  // namespace rr::server

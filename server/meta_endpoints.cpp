// Endpoints about the service rather than a render: health (livez, readyz, healthz), metrics, the
// pipeline table, the OpenAPI document and JSON Schemas, the web page, the API page (/docs) and the
// bundled examples.
// Files are served only by names that match a strict pattern, so a name can never leave its
// directory.
#include "server/routes.hpp"

#include "render/core/scene_names.hpp"
#include "server/problem.hpp"
#include "server/serve_command.hpp"

#include <httplib.h>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace rr::server {

namespace {

using httplib::Request;
using httplib::Response;
namespace fs = std::filesystem;

std::optional<std::string> read_text_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

// The sorted stems of the files in `dir` named <stem><suffix> whose stem matches `name`.
std::vector<std::string> list_names(const fs::path& dir, const std::string& suffix, const std::regex& name) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::string file = entry.path().filename().string();
    if (!file.ends_with(suffix)) continue;
    std::string stem = file.substr(0, file.size() - suffix.size());
    if (std::regex_match(stem, name)) names.push_back(stem);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Serves dir/<name><suffix> or answers 404 naming `what`.
void send_file(Response& res, const fs::path& dir, const std::string& name, const std::string& suffix,
               const std::string& content_type, const std::string& what) {
  auto text = read_text_file(dir / (name + suffix));
  if (!text) throw HttpError(404, "There is no " + what + " named '" + quote_input(name) + "'.");
  res.set_header("Cache-Control", "no-cache");
  res.set_content(*text, content_type);
}

void no_store(Response& res) { res.set_header("Cache-Control", "no-store"); }

void handle_livez(ServiceState&, const Request&, Response& res, const RouteMatch&) {
  no_store(res);
  send_json(res, {{"status", "ok"}});
}

// Ready means a render sent now would be taken: not draining, and a slot or queue place is free.
void handle_readyz(ServiceState& state, const Request&, Response& res, const RouteMatch&) {
  no_store(res);
  GateLoad load = state.gate.load();
  const char* status = state.draining || load.closed ? "draining" : load.saturated() ? "saturated" : "ok";
  // A replica whose shared store does not answer cannot serve stored ids: the balancer should
  // prefer one that can (inline renders still work here if it has no other).
  std::string store_reason = std::string_view(status) == "ok" ? state.stores.scenes->unavailable_reason() : "";
  if (!store_reason.empty()) status = "store_unavailable";
  if (std::string_view(status) != "ok") res.set_header("Retry-After", std::to_string(state.config.retry_after_s));
  nlohmann::json body = {{"status", status}, {"renders_in_flight", load.running}, {"renders_queued", load.queued}};
  if (!store_reason.empty()) body["store"] = store_reason;
  send_json(res, body, std::string_view(status) == "ok" ? 200 : 503);
}

void handle_metrics(ServiceState& state, const Request&, Response& res, const RouteMatch&) {
  no_store(res);
  MetricsSnapshot snapshot{state.gate.load(),
                           state.cache.bsp.stats(),
                           state.cache.shadow.stats(),
                           state.cache.views.stats(),
                           state.cache.scene_stats(),
                           state.cache.mesh_stats(),
                           state.cache.texture_stats(),
                           state.cache.all_stats(),
                           state.stores.scenes->stats(),
                           state.stores.meshes->stats(),
                           state.stores.textures->stats(),
                           resident_bytes(),
                           std::string(version()),
                           state.front_stats ? state.front_stats() : FrontStats{}};
  res.set_content(state.metrics.prometheus_text(snapshot), "text/plain; version=0.0.4; charset=utf-8");
}

// The pipeline table, and the shading modes this build knows (both tables grow as branches land).
void handle_pipelines(ServiceState&, const Request&, Response& res, const RouteMatch&) {
  nlohmann::json list = nlohmann::json::array();
  for (const PipelineInfo& p : pipeline_table()) list.push_back({{"name", p.name}, {"summary", p.summary}});
  nlohmann::json shading = nlohmann::json::array();
  for (const auto& s : shading_names) shading.push_back(s.name);
  send_json(res, {{"pipelines", list}, {"shading", shading}});
}

const std::regex schema_name("[a-z0-9_-]+");
const std::regex example_name("[a-z0-9_]+");

// The document's $refs are relative to its file, which sits beside the schemas: right as it is at
// /v1/schemas/openapi.json, but from /openapi.json they would resolve to /request.schema.json. So
// that URL serves it with each relative reference made an absolute path under /v1/schemas/.
void make_refs_absolute(nlohmann::ordered_json& node) {
  if (node.is_array()) {
    for (auto& item : node) make_refs_absolute(item);
  } else if (node.is_object()) {
    for (auto& [key, value] : node.items()) {
      if (key != "$ref" || !value.is_string()) {
        make_refs_absolute(value);
        continue;
      }
      const std::string ref = value.get<std::string>();
      const bool relative = !ref.starts_with('/') && !ref.starts_with('#') && ref.find(':') == std::string::npos;
      if (relative) value = "/v1/schemas/" + ref;
    }
  }
}

RouteHandler openapi_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch&) {
    auto text = read_text_file(dir / "openapi.json");
    if (!text) throw HttpError(404, "There is no document named 'openapi'.");
    nlohmann::ordered_json document = nlohmann::ordered_json::parse(*text);  // keeps the authored order
    make_refs_absolute(document);
    res.set_header("Cache-Control", "no-cache");
    res.set_content(document.dump(2), "application/json");
  };
}

RouteHandler openapi_file_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch&) {
    send_file(res, dir, "openapi", ".json", "application/json", "document");
  };
}

RouteHandler schema_list_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch&) {
    nlohmann::json names = nlohmann::json::array();
    for (const std::string& stem : list_names(dir, ".schema.json", schema_name)) names.push_back(stem + ".schema");
    send_json(res, {{"schemas", names}});
  };
}

// GET /v1/schemas/{name}.json serves schemas/{name}.json; names are "<stem>.schema".
RouteHandler schema_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch& match) {
    send_file(res, dir, match.params.at(0), ".schema.json", "application/schema+json", "schema");
  };
}

RouteHandler examples_list_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch&) {
    send_json(res, {{"examples", list_names(dir, ".json", example_name)}});
  };
}

RouteHandler example_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch& match) {
    send_file(res, dir, match.params.at(0), ".json", "application/json", "example");
  };
}

RouteHandler index_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch&) {
    auto text = read_text_file(dir / "index.html");
    if (!text) throw HttpError(404, "The web client is not installed on this server.");
    // The page is self-contained: nothing may load from elsewhere.
    res.set_header("Content-Security-Policy",
                   "default-src 'self'; script-src 'self' 'unsafe-inline'; "
                   "style-src 'self' 'unsafe-inline'; img-src 'self' blob: data:");
    res.set_content(*text, "text/html; charset=utf-8");
  };
}

// The API page (clients/web/docs): Redoc, served from here, drawing /v1/schemas/openapi.json. The
// web build empties the one CDN URL of Redoc's bundle, and the policy refuses any other origin;
// Redoc styles with inline <style> elements and searches in a worker it makes from a blob.
RouteHandler docs_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch&) {
    auto text = read_text_file(dir / "docs" / "index.html");
    if (!text) throw HttpError(404, "The API page is not installed on this server.");
    res.set_header("Content-Security-Policy",
                   "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; "
                   "img-src 'self' data:; worker-src blob:");
    res.set_header("Cache-Control", "no-cache");
    res.set_content(*text, "text/html; charset=utf-8");
  };
}

// The page's files, by name: the pattern admits only these two.
RouteHandler docs_asset_handler(fs::path dir) {
  return [dir](ServiceState&, const Request&, Response& res, const RouteMatch& match) {
    const std::string& name = match.params.at(0);
    const char* type = name.ends_with(".js") ? "text/javascript; charset=utf-8" : "text/plain; charset=utf-8";
    send_file(res, dir / "docs", name, "", type, "file of the API page");
  };
}

}  // namespace

std::vector<Route> meta_routes(const ServerConfig& config) {
  const std::vector<std::string> json_answer = {"application/json"};
  return {
      {"GET", "/livez", {}, json_answer, handle_livez},
      {"GET", "/readyz", {}, json_answer, handle_readyz},
      {"GET", "/healthz", {}, json_answer, handle_readyz},
      {"GET", "/metrics", {}, {"text/plain"}, handle_metrics},
      {"GET", "/v1/pipelines", {}, json_answer, handle_pipelines},
      {"GET", "/openapi.json", {}, json_answer, openapi_handler(config.schemas_dir)},
      {"GET", "/v1/schemas/openapi.json", {}, json_answer, openapi_file_handler(config.schemas_dir)},
      {"GET", "/v1/schemas", {}, json_answer, schema_list_handler(config.schemas_dir), "/v1/schemas/?"},
      // A schema's name may hold '-', and its file is <name>.schema.json.
      {"GET",
       "/v1/schemas/{name}.json",
       {},
       {"application/schema+json", "application/json"},
       schema_handler(config.schemas_dir),
       "/v1/schemas/([a-z0-9_-]+)\\.schema\\.json"},
      {"GET", "/docs", {}, {"text/html"}, docs_handler(config.web_dir)},
  };
}

std::vector<Route> page_routes(const ServerConfig& config) {
  const std::vector<std::string> json_answer = {"application/json"};
  return {
      {"GET", "/", {}, {"text/html"}, index_handler(config.web_dir)},
      // Only the files the API page loads, by name.
      {"GET",
       "/docs/{file}",
       {},
       {},
       docs_asset_handler(config.web_dir),
       "/docs/(redoc\\.standalone\\.js(?:\\.LICENSE\\.txt)?)"},
      {"GET", "/examples/", {}, json_answer, examples_list_handler(config.examples_dir), "/examples/?"},
      {"GET", "/examples/{name}.json", {}, json_answer, example_handler(config.examples_dir)},
  };
}

}  // namespace rr::server

// The route table as one list, and each route's path regex: derived from its template where the
// template says everything (literal characters and the placeholders below), the row's own pattern
// where it cannot. In: the *_routes() lists of the endpoint files. Out: routes whose regex matches the
// whole decoded path and captures the placeholders in order.
#include "server/routes.hpp"

#include <stdexcept>
#include <string_view>

namespace rr::server {

namespace {

struct Placeholder {
  std::string_view name;
  std::string_view pattern;
};

// What a {placeholder} of a template matches. A template whose placeholder means something else
// under the same name (a schema's name, which allows '-' and is served from <name>.schema.json) gives
// its own pattern instead.
constexpr Placeholder placeholders[] = {
    {"id", "[0-9a-f]{16}"},   // a stored scene's, mesh's or image's id: 16 hex digits of its content hash
    {"format", "[a-z0-9]+"},  // an importer's name
    {"name", "[a-z0-9_]+"},   // an example request's file stem, a catalogue entry's id
};

std::string_view placeholder_pattern(std::string_view name, const std::string& path_template) {
  for (const Placeholder& p : placeholders) {
    if (p.name == name) return p.pattern;
  }
  throw std::logic_error("route " + path_template + ": no pattern for {" + std::string(name) + "}");
}

}  // namespace

std::string route_pattern(const Route& route) {
  if (!route.pattern.empty()) return route.pattern;
  const std::string& t = route.path_template;
  std::string out;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] == '{') {
      const size_t end = t.find('}', i);
      if (end == std::string::npos) throw std::logic_error("route " + t + ": an unclosed {");
      out += '(';
      out += placeholder_pattern(std::string_view(t).substr(i + 1, end - i - 1), t);
      out += ')';
      i = end;
    } else {
      if (std::string_view("\\^$.|?*+()[]{}").find(t[i]) != std::string_view::npos) out += '\\';
      out += t[i];
    }
  }
  return out;
}

std::vector<Route> service_routes(const ServerConfig& config) {
  std::vector<Route> routes;
  for (std::vector<Route> list :
       {render_routes(), scene_routes(), mesh_routes(config), texture_routes(), import_routes(config),
        meta_routes(config), page_routes(config), pick_routes(), catalogue_routes()}) {
    routes.insert(routes.end(), list.begin(), list.end());
  }
  for (Route& r : routes) r.regex = std::regex(route_pattern(r));
  return routes;
}

}  // namespace rr::server

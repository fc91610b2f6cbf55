// The service's API as operations ("GET /v1/scenes/{id}"), from its route table and from an OpenAPI
// document, for the tests that hold the two to each other. The web page's own routes
// (server::page_routes) are not part of the API; every other route is.
#pragma once

#include "server/routes.hpp"

#include <nlohmann/json.hpp>

#include <set>
#include <string>

namespace rr::testing {

// "METHOD template" for every route of the service but the page's own.
inline std::set<std::string> api_operations(const rr::server::ServerConfig& config) {
  std::set<std::string> page;
  for (const rr::server::Route& r : rr::server::page_routes(config)) page.insert(r.method + " " + r.path_template);
  std::set<std::string> operations;
  for (const rr::server::Route& r : rr::server::service_routes(config)) {
    std::string operation = r.method + " " + r.path_template;
    if (!page.contains(operation)) operations.insert(std::move(operation));
  }
  return operations;
}

// "METHOD path" for every operation of an OpenAPI document's paths (methods upper-cased; a path's
// other members, such as its parameters, are not operations).
inline std::set<std::string> openapi_operations(const nlohmann::json& document) {
  std::set<std::string> operations;
  for (const auto& [path, item] : document.at("paths").items()) {
    for (const auto& [key, value] : item.items()) {
      for (const char* method : {"get", "put", "post", "delete", "options", "head", "patch", "trace"}) {
        if (key != method) continue;
        std::string upper;
        for (char c : key) upper += char(c - 'a' + 'A');
        operations.insert(upper + " " + path);
      }
    }
  }
  return operations;
}

}  // namespace rr::testing

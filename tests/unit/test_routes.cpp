// The route table against schemas/openapi.json: the service's API routes are exactly the document's
// operations, path templates and methods (the web page's own routes are not part of the API); and a
// route's regex comes from its template: literal characters, placeholders as groups.
#include "server/routes.hpp"
#include "support/api_routes.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

namespace rr::server {
namespace {

std::string pattern_of(const std::string& path_template) {
  Route route;
  route.path_template = path_template;
  return route_pattern(route);
}

TEST(Routes, AreExactlyTheOperationsOfOpenApi) {
  const nlohmann::json document = nlohmann::json::parse(
      testing::read_file(std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "schemas" / "openapi.json"));
  const std::set<std::string> described = testing::openapi_operations(document);
  const ServerConfig config = default_server_config();
  const std::set<std::string> served = testing::api_operations(config);
  for (const std::string& operation : served) {
    EXPECT_TRUE(described.contains(operation))
        << operation << " is routed but schemas/openapi.json has no such operation";
  }
  for (const std::string& operation : described) {
    EXPECT_TRUE(served.contains(operation)) << operation << " is in schemas/openapi.json but no route serves it";
  }
}

TEST(Routes, ATemplatesRegexIsItsLiteralsAndItsPlaceholdersAsGroups) {
  EXPECT_EQ(pattern_of("/v1/scenes"), "/v1/scenes");
  EXPECT_EQ(pattern_of("/v1/scenes/{id}/render.png"), "/v1/scenes/([0-9a-f]{16})/render\\.png");
  EXPECT_EQ(pattern_of("/v1/import/{format}"), "/v1/import/([a-z0-9]+)");
  EXPECT_THROW(pattern_of("/v1/things/{thing}"), std::logic_error);
  EXPECT_THROW(pattern_of("/v1/things/{id"), std::logic_error);
  Route explicit_route;
  explicit_route.path_template = "/examples/";
  explicit_route.pattern = "/examples/?";
  EXPECT_EQ(route_pattern(explicit_route), "/examples/?");
}

}  // namespace
}  // namespace rr::server

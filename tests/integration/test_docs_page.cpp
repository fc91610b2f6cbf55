// The service's description over real HTTP: the API page at /docs loads only files of the same
// server and those files are served; the OpenAPI document resolves from both of its URLs.
#include "server_fixture.hpp"

#include <regex>
#include <set>

namespace {

using nlohmann::json;
using namespace rr::testing;

// Every URL an attribute of the page names: script src, link href, Redoc's spec-url.
std::vector<std::string> page_urls(const std::string& html) {
  static const std::regex attribute(R"re(\b(?:src|href|spec-url)\s*=\s*"([^"]*)")re", std::regex::icase);
  std::vector<std::string> urls;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), attribute); it != std::sregex_iterator(); ++it) {
    urls.push_back((*it)[1].str());
  }
  return urls;
}

// Same origin: a path, absolute or relative, never a scheme or a network-path ("//host"). data:
// URLs carry their bytes inline and fetch nothing.
bool same_origin(const std::string& url) {
  if (url.starts_with("data:")) return true;
  return !url.starts_with("//") && !std::regex_search(url, std::regex("^[a-zA-Z][a-zA-Z0-9+.-]*:"));
}

TEST(DocsPage, IsHtmlLoadingOnlySameOriginFilesThatAreServed) {
  TestServer server;
  auto client = server.client();
  auto page = client.Get("/docs");
  ASSERT_TRUE(page);
  ASSERT_EQ(page->status, 200);
  EXPECT_EQ(page->get_header_value("Content-Type"), "text/html; charset=utf-8");
  // The policy is what stops Redoc's CDN logo; "default-src 'self'" covers every other kind.
  EXPECT_NE(page->get_header_value("Content-Security-Policy").find("default-src 'self'"), std::string::npos);

  std::vector<std::string> urls = page_urls(page->body);
  size_t fetched = 0;
  bool loads_script = false, loads_document = false;
  for (const std::string& url : urls) {
    ASSERT_TRUE(same_origin(url)) << url;
    if (url.starts_with("data:")) continue;
    // Relative to /docs, whose directory is /.
    std::string path = url.starts_with("/") ? url : "/" + url;
    auto res = client.Get(path.c_str());
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_FALSE(res->body.empty()) << path;
    ++fetched;
    if (res->get_header_value("Content-Type").starts_with("text/javascript")) loads_script = true;
    if (res->get_header_value("Content-Type") == "application/json" && json::parse(res->body).contains("openapi")) {
      loads_document = true;
    }
  }
  EXPECT_GE(fetched, 2u) << page->body;
  EXPECT_TRUE(loads_script) << "the page names no script the server serves";
  EXPECT_TRUE(loads_document) << "the page names no OpenAPI document the server serves";
}

TEST(DocsPage, ServesItsBundleAsCommittedAndNothingElse) {
  TestServer server;
  auto client = server.client();
  auto script = client.Get("/docs/redoc.standalone.js");
  ASSERT_TRUE(script);
  ASSERT_EQ(script->status, 200);
  EXPECT_EQ(script->body,
            read_file(std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "clients/web/docs/redoc.standalone.js"));
  auto licence = client.Get("/docs/redoc.standalone.js.LICENSE.txt");
  ASSERT_TRUE(licence);
  EXPECT_EQ(licence->status, 200);
  EXPECT_EQ(licence->get_header_value("Content-Type"), "text/plain; charset=utf-8");
  for (const char* path : {"/docs/index.html", "/docs/..%2Fbuild.mjs", "/docs/redoc.standalone.js.map"}) {
    auto res = client.Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 404) << path;
  }
}

// Collects every "$ref" string of a JSON document.
void collect_refs(const json& node, std::set<std::string>& out) {
  if (node.is_object()) {
    for (const auto& [key, value] : node.items()) {
      if (key == "$ref" && value.is_string()) out.insert(value.get<std::string>());
      else collect_refs(value, out);
    }
  } else if (node.is_array()) {
    for (const json& item : node) collect_refs(item, out);
  }
}

// The path a reference names when resolved against a document at `base_dir` (ending in '/'),
// without its fragment. The document's references are plain names or absolute paths.
std::string resolve(const std::string& base_dir, const std::string& ref) {
  std::string target = ref.substr(0, ref.find('#'));
  return target.starts_with("/") ? target : base_dir + target;
}

TEST(OpenApiDocument, ResolvesFromBothOfItsUrls) {
  TestServer server;
  auto client = server.client();
  auto file = client.Get("/v1/schemas/openapi.json");
  auto root = client.Get("/openapi.json");
  ASSERT_TRUE(file && root);
  ASSERT_EQ(file->status, 200);
  ASSERT_EQ(root->status, 200);
  EXPECT_EQ(file->body, read_file(std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "schemas/openapi.json"));

  for (const char* path : {"/docs", "/v1/schemas/openapi.json", "/openapi.json"}) {
    EXPECT_TRUE(json::parse(file->body)["paths"].contains(path)) << path;
  }

  std::set<std::string> file_refs, root_refs;
  collect_refs(json::parse(file->body), file_refs);
  collect_refs(json::parse(root->body), root_refs);
  ASSERT_FALSE(file_refs.empty());
  std::set<std::string> file_targets, root_targets;
  for (const std::string& ref : file_refs) file_targets.insert(resolve("/v1/schemas/", ref));
  for (const std::string& ref : root_refs) root_targets.insert(resolve("/", ref));
  // Both name the same schema files, and each of those is served.
  EXPECT_EQ(file_targets, root_targets);
  for (const std::string& path : file_targets) {
    auto res = client.Get(path.c_str());
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
  }
}

}  // namespace

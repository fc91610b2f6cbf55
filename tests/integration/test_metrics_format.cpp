// /metrics over real HTTP, read as a scraper reads it: every line is a HELP, TYPE or sample line of
// the Prometheus text format (0.0.4), and each family is one block, its HELP and TYPE, then all of
// its samples, never split by another family's lines.
#include "server_fixture.hpp"

#include "render/pipelines/pipeline_table.hpp"

#include <map>
#include <regex>
#include <set>
#include <sstream>

namespace {

using nlohmann::json;
using namespace rr::testing;

// One parsed line of the Prometheus text format (0.0.4).
struct MetricLine {
  enum Kind { help, type, sample } kind;
  std::string name;   // the metric name as written
  std::string value;  // the TYPE's type
};

MetricLine parse_metric_line(const std::string& line) {
  static const std::regex comment(R"(# (HELP|TYPE) ([a-zA-Z_:][a-zA-Z0-9_:]*) (.*))");
  static const std::regex sample_line(R"(([a-zA-Z_:][a-zA-Z0-9_:]*)(\{.*\})? [-+0-9.eEInfNa]+)");
  std::smatch m;
  if (std::regex_match(line, m, comment)) {
    return {m[1] == "HELP" ? MetricLine::help : MetricLine::type, m[2], m[3]};
  }
  if (std::regex_match(line, m, sample_line)) return {MetricLine::sample, m[1], ""};
  ADD_FAILURE() << "not a line of the text format: " << line;
  return {MetricLine::sample, "", ""};
}

// The family a sample belongs to: its own name, or for histograms and summaries the name without
// the _bucket/_sum/_count suffix.
std::string family_of(const std::string& sample, const std::map<std::string, std::string>& types) {
  if (types.contains(sample)) return sample;
  for (const char* suffix : {"_bucket", "_sum", "_count"}) {
    if (!sample.ends_with(suffix)) continue;
    std::string base = sample.substr(0, sample.size() - std::string_view(suffix).size());
    auto it = types.find(base);
    if (it != types.end() && (it->second == "histogram" || it->second == "summary")) return base;
  }
  return "";
}

TEST(MetricsText, EachFamilyIsOneBlockUnderItsHelpAndType) {
  TestServer server;
  auto client = server.client();
  // Fill the labelled families: a render per pipeline for stage histograms, and a stored scene.
  for (const rr::PipelineInfo& pipeline : rr::pipeline_table()) {
    json request = json::parse(small_request);
    request["options"]["pipeline"] = pipeline.name;
    auto res = client.Post("/v1/render", request.dump(), "application/json");
    ASSERT_TRUE(res && res->status == 200);
  }
  auto stored = client.Post("/v1/scenes", json::parse(small_request)["scene"].dump(), "application/json");
  ASSERT_TRUE(stored && stored->status / 100 == 2);
  auto res = client.Get("/metrics");
  ASSERT_TRUE(res && res->status == 200);

  std::map<std::string, std::string> types;  // family -> type, filled as TYPE lines come
  std::set<std::string> closed;              // families whose block has ended
  std::string current;                       // the family whose block we are in
  std::map<std::string, size_t> samples;
  std::istringstream lines(res->body);
  for (std::string line; std::getline(lines, line);) {
    ASSERT_FALSE(line.empty()) << "blank line in /metrics";
    MetricLine parsed = parse_metric_line(line);
    std::string family = parsed.kind == MetricLine::sample ? family_of(parsed.name, types) : parsed.name;
    ASSERT_FALSE(family.empty()) << "sample before its family's TYPE: " << line;
    if (family != current) {
      // A family seen before comes back: its samples are split into two blocks.
      ASSERT_FALSE(closed.contains(family)) << "family " << family << " starts a second block at: " << line;
      ASSERT_NE(parsed.kind, MetricLine::sample) << "sample outside its family's block: " << line;
      if (!current.empty()) closed.insert(current);
      current = family;
    }
    if (parsed.kind == MetricLine::type) {
      ASSERT_FALSE(types.contains(family)) << "second TYPE for " << family;
      types[family] = parsed.value;
    }
    if (parsed.kind == MetricLine::sample) ++samples[family];
  }
  // The cache families list all three caches, so they had several samples to keep together.
  const std::map<std::string, std::string> cache_families = {{"roomrender_cache_hits_total", "counter"},
                                                             {"roomrender_cache_bytes", "gauge"},
                                                             {"roomrender_cache_entries", "gauge"}};
  for (const auto& [family, type] : cache_families) {
    EXPECT_EQ(types[family], type) << family;
    EXPECT_GE(samples[family], 3u) << family;
  }
  EXPECT_GE(samples["roomrender_render_stage_duration_seconds"], 2u);
  EXPECT_GE(types.size(), 10u);
}

}  // namespace

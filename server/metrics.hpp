// The service's counters and histograms, exposed at GET /metrics in the Prometheus text format
// (version 0.0.4), written by hand. Labels are bounded: routes are the route table's templates (or
// "unmatched"), methods the few httplib accepts, stages the names of stage_table, pipelines the
// pipeline table's names. Thread-safe; one Metrics object per Service.
#pragma once

#include "render/core/lru_cache.hpp"
#include "render/pipelines/pipeline.hpp"
#include "server/connection_front.hpp"
#include "server/render_gate.hpp"

#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

namespace rr::server {

struct Histogram {
  std::vector<double> bounds;    // upper bounds in seconds, ascending; +Inf is implicit
  std::vector<uint64_t> counts;  // per bound, not cumulative (made cumulative on output)
  uint64_t count = 0;
  double sum = 0.0;
  explicit Histogram(std::vector<double> upper_bounds);
  void observe(double value);
};

// What /metrics reports besides the Metrics object's own counters.
struct MetricsSnapshot {
  GateLoad gate;
  // The prepared cache (server/prepared_cache.hpp) by part, and all of it.
  CacheStats bsp_cache;
  CacheStats shadow_cache;
  CacheStats view_cache;
  CacheStats scene_cache;
  CacheStats mesh_cache;
  CacheStats texture_cache;
  CacheStats all_cache;
  // The document stores (server/document_store.hpp): fill against their budgets, finds.
  CacheStats scene_store;
  CacheStats mesh_store;
  CacheStats texture_store;
  double resident_bytes = 0.0;  // this process's RSS, from /proc/self/statm
  std::string version;
  FrontStats connections;
};

class Metrics {
 public:
  void record_request(std::string_view route, std::string_view method, int status, double seconds);
  // One render's stages, named by stage_table; stages that did not run (0 ms) are not observed. Its
  // culling counts (polygons projected, objects occluded, nodes tested) are added to counters.
  void record_render(std::string_view pipeline, const StageTimings& timings, const RenderStats& stats = {});
  void record_rejection(std::string_view reason);  // saturated, expired, deadline, draining

  // The whole exposition text, this object's series followed by the snapshot's.
  std::string prometheus_text(const MetricsSnapshot& snapshot) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, int>, uint64_t> requests_;  // route, method, status
  std::map<std::string, Histogram> request_seconds_;                        // route
  std::map<std::pair<std::string, std::string>, Histogram> stage_seconds_;  // pipeline, stage
  std::map<std::string, uint64_t> rejections_;
  std::map<std::pair<std::string, std::string>, uint64_t> culling_;  // pipeline, count
};

// Resident set size of this process in bytes (0 when /proc is unavailable).
double resident_bytes();

}  // namespace rr::server

// Metrics (see metrics.hpp). Histograms use fixed buckets from 0.5 ms to 10 s, wide enough for a
// health check and a 4096x4096 render alike; exposition follows the Prometheus text format: HELP and
// TYPE lines, cumulative buckets ending in le="+Inf", then _sum and _count.
#include "server/metrics.hpp"

#include <httplib.h>
#include <unistd.h>

#include <charconv>
#include <fstream>

namespace rr::server {

namespace {

const std::vector<double> duration_buckets = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                              0.1,    0.25,  0.5,    1.0,   2.5,  5.0,   10.0};

// Label values are our own constants or numbers, but escape them anyway as the format requires.
std::string escape_label(std::string_view value) {
  std::string out;
  for (char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

std::string number(double value) {
  char buffer[32];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);  // shortest round-trip form
  return std::string(buffer, result.ptr);
}

void header(std::string& out, const char* name, const char* type, const char* help) {
  out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
}

void sample(std::string& out, const std::string& name, const std::string& labels, double value) {
  out += name + (labels.empty() ? "" : "{" + labels + "}") + " " + number(value) + "\n";
}

void histogram_samples(std::string& out, const std::string& name, const std::string& labels, const Histogram& h) {
  uint64_t cumulative = 0;
  std::string prefix = labels.empty() ? "" : labels + ",";
  for (size_t i = 0; i < h.bounds.size(); ++i) {
    cumulative += h.counts[i];
    sample(out, name + "_bucket", prefix + "le=\"" + number(h.bounds[i]) + "\"", double(cumulative));
  }
  sample(out, name + "_bucket", prefix + "le=\"+Inf\"", double(h.count));
  sample(out, name + "_sum", labels, h.sum);
  sample(out, name + "_count", labels, double(h.count));
}

std::string label(const char* name, std::string_view value) {
  return std::string(name) + "=\"" + escape_label(value) + "\"";
}

// One row per cache family. Prometheus wants all samples of a family together after its HELP and
// TYPE, so the caches are the inner loop, not the outer one.
struct CacheFamily {
  const char* name;
  const char* type;
  const char* help;
  size_t CacheStats::*field;
};
const CacheFamily cache_families[] = {
    {"roomrender_cache_hits_total", "counter", "Cache lookups that found their value.", &CacheStats::hits},
    {"roomrender_cache_misses_total", "counter", "Cache lookups that did not.", &CacheStats::misses},
    {"roomrender_cache_evictions_total", "counter", "Entries evicted to stay within budget.", &CacheStats::evictions},
    {"roomrender_cache_builds_total", "counter", "Values built on a miss (once per key however many waited).",
     &CacheStats::builds},
    {"roomrender_cache_bytes", "gauge", "Bytes held (approximate).", &CacheStats::bytes},
    {"roomrender_cache_budget_bytes", "gauge", "Byte budget.", &CacheStats::budget_bytes},
    {"roomrender_cache_entries", "gauge", "Entries held.", &CacheStats::entries},
};

void cache_samples(std::string& out, const MetricsSnapshot& snap) {
  const std::pair<const char*, const CacheStats*> caches[] = {
      {"bsp", &snap.bsp_cache},      {"shadow", &snap.shadow_cache}, {"views", &snap.view_cache},
      {"scenes", &snap.scene_cache}, {"meshes", &snap.mesh_cache},   {"textures", &snap.texture_cache},
      {"all", &snap.all_cache}};
  for (const CacheFamily& family : cache_families) {
    header(out, family.name, family.type, family.help);
    for (const auto& [cache, stats] : caches)
      sample(out, family.name, label("cache", cache), double(stats->*family.field));
  }
}

// The document stores keep what they stored (507 when full), so their fill against both budgets is
// what an operator watches; finds are every look at a stored id (renders of stored scenes included).
const CacheFamily store_families[] = {
    {"roomrender_store_entries", "gauge", "Documents stored.", &CacheStats::entries},
    {"roomrender_store_max_entries", "gauge", "Most documents the store holds; beyond, storing answers 507.",
     &CacheStats::max_entries},
    {"roomrender_store_bytes", "gauge", "Bytes of the documents stored (their canonical text).", &CacheStats::bytes},
    {"roomrender_store_budget_bytes", "gauge", "Most document bytes the store holds; beyond, storing answers 507.",
     &CacheStats::budget_bytes},
    {"roomrender_store_found_total", "counter", "Looks at a stored id that found it stored.", &CacheStats::hits},
    {"roomrender_store_missing_total", "counter", "Looks at an id that is not stored.", &CacheStats::misses},
};

void store_samples(std::string& out, const MetricsSnapshot& snap) {
  const std::pair<const char*, const CacheStats*> stores[] = {
      {"scenes", &snap.scene_store}, {"meshes", &snap.mesh_store}, {"textures", &snap.texture_store}};
  for (const CacheFamily& family : store_families) {
    header(out, family.name, family.type, family.help);
    for (const auto& [store, stats] : stores)
      sample(out, family.name, label("store", store), double(stats->*family.field));
  }
}

void connection_samples(std::string& out, const FrontStats& s) {
  header(out, "roomrender_connections", "gauge", "Open client connections by state.");
  const std::pair<const char*, size_t> states[] = {
      {"reading", s.reading}, {"processing", s.processing}, {"writing", s.writing}, {"idle", s.idle}};
  for (const auto& [name, count] : states) sample(out, "roomrender_connections", label("state", name), double(count));
  header(out, "roomrender_requests_pending", "gauge", "Complete requests waiting for a worker.");
  sample(out, "roomrender_requests_pending", "", double(s.pending));
  header(out, "roomrender_connections_accepted_total", "counter", "Connections accepted.");
  sample(out, "roomrender_connections_accepted_total", "", double(s.accepted));
  header(out, "roomrender_connections_closed_total", "counter",
         "Connections the server closed on its own (deadlines, caps), by reason.");
  for (size_t i = 0; i < size_t(CloseReason::count); ++i) {
    sample(out, "roomrender_connections_closed_total", label("reason", close_reason_name(CloseReason(i))),
           double(s.closed[i]));
  }
  header(out, "roomrender_shed_total", "counter", "503 answers the connection front gave without a worker.");
  sample(out, "roomrender_shed_total", "", double(s.shed));
}

void snapshot_samples(std::string& out, const MetricsSnapshot& snap) {
  header(out, "roomrender_renders_in_flight", "gauge", "Renders (and scene parses) running now.");
  sample(out, "roomrender_renders_in_flight", "", double(snap.gate.running));
  header(out, "roomrender_renders_queued", "gauge", "Renders waiting for a slot.");
  sample(out, "roomrender_renders_queued", "", double(snap.gate.queued));
  header(out, "roomrender_render_slots", "gauge", "Render concurrency (slots) and queue length.");
  sample(out, "roomrender_render_slots", label("kind", "concurrency"), double(snap.gate.concurrency));
  sample(out, "roomrender_render_slots", label("kind", "queue"), double(snap.gate.queue_limit));
  cache_samples(out, snap);
  store_samples(out, snap);
  connection_samples(out, snap.connections);
  header(out, "process_resident_memory_bytes", "gauge", "Resident memory size in bytes.");
  sample(out, "process_resident_memory_bytes", "", snap.resident_bytes);
  header(out, "roomrender_build_info", "gauge", "Build information; the value is always 1.");
  sample(out, "roomrender_build_info", label("version", snap.version) + "," + label("httplib", CPPHTTPLIB_VERSION),
         1.0);
}

}  // namespace

Histogram::Histogram(std::vector<double> upper_bounds) : bounds(std::move(upper_bounds)), counts(bounds.size(), 0) {}

void Histogram::observe(double value) {
  for (size_t i = 0; i < bounds.size(); ++i) {
    if (value <= bounds[i]) {
      ++counts[i];
      break;
    }
  }
  ++count;
  sum += value;
}

void Metrics::record_request(std::string_view route, std::string_view method, int status, double seconds) {
  std::lock_guard lock(mutex_);
  ++requests_[{std::string(route), std::string(method), status}];
  request_seconds_.try_emplace(std::string(route), duration_buckets).first->second.observe(seconds);
}

void Metrics::record_render(std::string_view pipeline, const StageTimings& timings, const RenderStats& stats) {
  std::lock_guard lock(mutex_);
  const std::string name(pipeline);
  culling_[{name, "polygons_projected"}] += stats.polygons_projected;
  culling_[{name, "objects_occluded"}] += stats.objects_occluded;
  culling_[{name, "nodes_tested"}] += stats.nodes_tested;
  culling_[{name, "cells_visited"}] += stats.cells_visited;
  culling_[{name, "portals_walked"}] += stats.portals_walked;
  for (const StageField& stage : stage_table) {
    const double ms = timings.*stage.ms;
    if (ms <= 0.0) continue;
    stage_seconds_.try_emplace({std::string(pipeline), stage.name}, duration_buckets)
        .first->second.observe(ms / 1000.0);
  }
}

void Metrics::record_rejection(std::string_view reason) {
  std::lock_guard lock(mutex_);
  ++rejections_[std::string(reason)];
}

std::string Metrics::prometheus_text(const MetricsSnapshot& snapshot) const {
  std::string out;
  {
    std::lock_guard lock(mutex_);
    header(out, "roomrender_http_requests_total", "counter",
           "HTTP requests answered, by route template, method and status.");
    for (const auto& [key, count] : requests_) {
      const auto& [route, method, status] = key;
      sample(out, "roomrender_http_requests_total",
             label("route", route) + "," + label("method", method) + "," + label("status", std::to_string(status)),
             double(count));
    }
    header(out, "roomrender_http_request_duration_seconds", "histogram",
           "Time from reading the request head to writing the response, by route template.");
    for (const auto& [route, h] : request_seconds_) {
      histogram_samples(out, "roomrender_http_request_duration_seconds", label("route", route), h);
    }
    header(out, "roomrender_render_stage_duration_seconds", "histogram",
           "Render stage durations by pipeline and stage.");
    for (const auto& [key, h] : stage_seconds_) {
      histogram_samples(out, "roomrender_render_stage_duration_seconds",
                        label("pipeline", key.first) + "," + label("stage", key.second), h);
    }
    header(out, "roomrender_render_culling_total", "counter",
           "Occlusion culling's counts summed over renders, by pipeline and count: polygons_projected, "
           "objects_occluded, nodes_tested, cells_visited, portals_walked (docs/culling.md).");
    for (const auto& [key, count] : culling_) {
      sample(out, "roomrender_render_culling_total", label("pipeline", key.first) + "," + label("count", key.second),
             double(count));
    }
    header(out, "roomrender_renders_rejected_total", "counter",
           "Renders refused or stopped: saturated (queue full), expired (deadline while queued), "
           "deadline (while rendering), draining.");
    for (const auto& [reason, count] : rejections_) {
      sample(out, "roomrender_renders_rejected_total", label("reason", reason), double(count));
    }
  }
  snapshot_samples(out, snapshot);
  return out;
}

double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  double pages_total = 0.0, pages_resident = 0.0;
  if (!(statm >> pages_total >> pages_resident)) return 0.0;
  return pages_resident * double(::sysconf(_SC_PAGESIZE));
}

}  // namespace rr::server

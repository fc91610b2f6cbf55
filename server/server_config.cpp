// Config resolution (see server_config.hpp): the defaults with the served directories in the source
// tree, what 0 / -1 resolve to on this machine, and the effective configuration as JSON, named and
// ordered by the settings table.
#include "server/server_config.hpp"

#include "server/settings.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <thread>

#ifndef ROOMRENDER_SOURCE_DIR
#define ROOMRENDER_SOURCE_DIR "."
#endif

namespace rr::server {

ServerConfig default_server_config() {
  ServerConfig config;
  config.web_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "clients" / "web";
  config.examples_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "examples";
  config.catalogue_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "catalogue";
  config.schemas_dir = std::filesystem::path(ROOMRENDER_SOURCE_DIR) / "schemas";
  return config;
}

size_t render_workers(const ServerConfig& config) {
  if (config.render_workers > 0) return size_t(config.render_workers);
  return std::max<size_t>(1, std::thread::hardware_concurrency());
}

unsigned render_threads(const ServerConfig& config) {
  if (config.render_threads > 0) return unsigned(config.render_threads);
  return std::max(1u, std::thread::hardware_concurrency());
}

size_t render_queue_length(const ServerConfig& config) {
  if (config.render_queue >= 0) return size_t(config.render_queue);
  return 4 * render_workers(config);
}

size_t request_workers(const ServerConfig& config) {
  // Every admitted or queued render holds a worker; the 8 beyond those answer health checks,
  // metrics, stored scenes and 503s while renders run.
  if (config.threads > 0) return size_t(config.threads);
  return render_workers(config) + render_queue_length(config) + 8;
}

size_t max_pending_requests(const ServerConfig& config) {
  if (config.max_pending_requests >= 0) return std::max<size_t>(1, size_t(config.max_pending_requests));
  return request_workers(config);
}

std::string config_json(const ServerConfig& config) {
  nlohmann::ordered_json j;
  for (const ServerSetting& setting : server_settings()) j[setting.key()] = setting.member.report(config);
  // The request limits no flag sets, so the line names every bound the service applies.
  const ParseLimits& l = config.limits;
  j["max_cylinder_segments"] = l.max_cylinder_segments;
  j["max_floor_cells"] = l.max_floor_cells;
  j["max_abs_coordinate"] = l.max_abs_coordinate;
  j["max_far_over_near"] = l.max_far_over_near;
  j["max_mesh_vertices"] = l.max_mesh_vertices;
  return j.dump();
}

}  // namespace rr::server

// Furnished homes stored and drawn over HTTP as a user would (support/sweet_homes.hpp): each zip
// POSTed to /v1/import/sh3d?store=1 (every distinct model a stored mesh, the scene placing them by
// ref), then drawn from its observer camera by POST /v1/scenes/{id}/render. Shared by the store
// suite (data directory) and the PostgreSQL suite.
#pragma once

#include "server/server_config.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rr::testing {

struct StoredHome {
  std::string name;       // DistinctHome::name
  std::string location;   // /v1/scenes/{id}
  int status = 0;         // the import's answer: 201 when stored now
  nlohmann::json camera;  // the home's observer camera, from the answer
};

// Imports distinct_sweet_home(i) with store=1; ADD_FAILUREs unless the answer is 201.
StoredHome store_home(httplib::Client& client, size_t i);

// The home drawn at width x height (default options: zbuffer, flat) from its camera: the PNG, or "" after an
// ADD_FAILURE when the answer is not a 200 PNG of that size.
std::string draw_home(httplib::Client& client, const StoredHome& home, int width = 96, int height = 72);

// Homes 0 .. count-1 stored from `clients` at once (each imports every clients.size()-th home), in
// home order.
std::vector<StoredHome> store_homes(std::vector<httplib::Client*> clients, size_t count);

// On a server made with `config`: homes 0 .. count-1 stored (two clients at once), each answered 201
// under its own id and drawn; then on a new server with the same config (a restart: same data
// directory or database) every one is still stored and draws the same bytes, each rebuilt once.
// Prints the times and the stores' fill.
void expect_homes_kept_across_restart(const rr::server::ServerConfig& config, size_t count);

}  // namespace rr::testing

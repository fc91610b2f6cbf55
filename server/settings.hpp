// The settings table of `roomrender serve`: one row per setting, naming its flag (the ROOMRENDER_*
// variable is named after it), the ServerConfig member it sets, its unit and what it means. Flags and
// variables (serve_config_from), `serve --help`, config_json and unit.ServerSettings (every row in
// docs/api.md's table with its variable, default and unit, and no other) all iterate it. A setting's
// default is its member's initializer (ServerConfig, or ParseLimits for the request limits): the
// table shows it and never writes it again.
#pragma once

#include "server/server_config.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rr::server {

// A flag or variable that cannot be obeyed; `roomrender serve` exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// How a row reaches its member: made by the member kinds in settings.cpp (integer, switch_01, text,
// one_of, origins), each of which checks the text it is given.
struct SettingMember {
  using Set = std::function<void(ServerConfig& config, const std::string& text, const std::string& source)>;
  using Show = std::function<std::string(const ServerConfig& config)>;
  using Report = std::function<nlohmann::ordered_json(const ServerConfig& config)>;

  Set set;        // reads a flag's or variable's text; throws UsageError naming `source`, the flag or variable
  Show show;      // the value as --help and docs/api.md show it ("8080", "none")
  Report report;  // the effective value config_json reports

  // The same member, reported as `effective` gives it (what a 0 / -1 resolves to, a URL without
  // its password).
  SettingMember reported_as(Report effective) const;
  // The same member, with `check` run on the text first (it throws UsageError).
  SettingMember checked_by(std::function<void(const std::string& text, const std::string& source)> check) const;
};

struct ServerSetting {
  std::string_view flag;  // "--render-queue"
  SettingMember member;
  std::string_view unit;  // "ms", "s", "bytes", "bytes/s" or "pixels"; "" for counts, names and switches
  std::string_view help;  // what it sets; --help adds the default and the unit

  std::string env() const;           // "ROOMRENDER_RENDER_QUEUE": the variable named after the flag
  std::string key() const;           // "render_queue": the setting's name in config_json
  std::string default_text() const;  // the member's initializer, shown ("8080", "none")
};

// Every setting, in the order `serve --help` and docs/api.md list them.
const std::vector<ServerSetting>& server_settings();

// The setting a flag names ("--port"), or nullptr.
const ServerSetting* find_setting(std::string_view flag);

}  // namespace rr::server

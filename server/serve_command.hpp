// `roomrender serve`: the service's configuration from flags and ROOMRENDER_* variables, and its
// start-up. The CLI (cli/) dispatches to run_serve; everything else of the service sits beside it.
#pragma once

#include "server/http_server.hpp"
#include "server/settings.hpp"

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace rr::server {

std::string_view version();  // the project's version, as CMake sets it

int run_serve(std::span<const std::string> args);
std::string serve_usage();  // every serve option with its default and unit

// The serve configuration: defaults, then ROOMRENDER_* variables read through `getenv`, then flags
// (flags win). Throws UsageError naming the flag or variable that is wrong.
ServerConfig serve_config_from(std::span<const std::string> args,
                               const std::function<std::optional<std::string>(const char*)>& getenv);

}  // namespace rr::server

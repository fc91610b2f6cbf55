// `roomrender serve`: the configuration from flags and ROOMRENDER_* variables and its --help, both read
// off the settings table (server/settings.hpp), and the process life cycle: print the configuration
// once, serve until SIGTERM or SIGINT, drain, exit 0. Declared in cli.hpp.
#include "server/serve_command.hpp"

#include <nlohmann/json.hpp>

#include <pthread.h>

#if defined(__GLIBC__)
#include <malloc.h>  // mallopt
#endif

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <thread>

namespace rr::server {

#ifndef ROOMRENDER_VERSION
#define ROOMRENDER_VERSION "0.0.0"
#endif

std::string_view version() { return ROOMRENDER_VERSION; }

namespace {

// `--name VALUE` and `--name=VALUE`; every flag takes a value and may appear once.
std::map<std::string, std::string> parse_serve_flags(std::span<const std::string> args) {
  std::map<std::string, std::string> flags;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string name = args[i], value;
    if (!name.starts_with("--")) throw UsageError("unexpected argument " + name);
    if (size_t eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name.resize(eq);
    } else if (i + 1 < args.size()) {
      value = args[++i];
    } else {
      throw UsageError(name + " needs a value");
    }
    if (!find_setting(name)) throw UsageError("unknown option " + name);
    if (!flags.emplace(name, value).second) throw UsageError(name + " given twice");
  }
  return flags;
}

void print_json_line(std::FILE* stream, const nlohmann::ordered_json& line) {
  std::string text = line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  std::fwrite(text.data(), 1, text.size(), stream);
  std::fflush(stream);
}

}  // namespace

std::string serve_usage() {
  std::string text =
      "usage: roomrender serve [OPTIONS]\n\nEvery option may also come from the variable named "
      "after it (--render-queue: ROOMRENDER_RENDER_QUEUE); flags win.\n\n";
  for (const ServerSetting& s : server_settings()) {
    std::string flag = std::string(s.flag) + " VALUE";
    flag.resize(std::max<size_t>(flag.size() + 1, 26), ' ');
    text.append("  ").append(flag).append(s.help).append(" (default ").append(s.default_text());
    if (!s.unit.empty()) text.append(" ").append(s.unit);
    text.append(")\n");
  }
  return text;
}

ServerConfig serve_config_from(std::span<const std::string> argv,
                               const std::function<std::optional<std::string>(const char*)>& getenv) {
  std::map<std::string, std::string> flags = parse_serve_flags(argv);
  ServerConfig config = default_server_config();
  for (const ServerSetting& s : server_settings()) {
    if (auto it = flags.find(std::string(s.flag)); it != flags.end()) {
      s.member.set(config, it->second, it->first);
    } else if (std::string variable = s.env(); auto value = getenv(variable.c_str())) {
      s.member.set(config, *value, variable);
    }
  }
  return config;
}

// glibc gives threads up to 8 malloc arenas per core, and malloc_trim cannot return the free top of
// an arena other than the main one: after large requests parsed on 18 worker threads, each arena
// kept 4-8 MiB (+190 MiB in all). One arena per core bounds that; renders measured no slower
// (docs/api.md, "Connections"). MALLOC_ARENA_MAX in the environment still decides when set.
void limit_malloc_arenas() {
#if defined(__GLIBC__)
  if (std::getenv("MALLOC_ARENA_MAX")) return;
  mallopt(M_ARENA_MAX, int(std::max(2u, std::thread::hardware_concurrency())));
#endif
}

int run_serve(std::span<const std::string> argv) {
  if (std::find(argv.begin(), argv.end(), "--help") != argv.end() ||
      std::find(argv.begin(), argv.end(), "-h") != argv.end()) {
    std::fputs(serve_usage().c_str(), stdout);
    return 0;
  }
  ServerConfig config;
  try {
    config = serve_config_from(argv, [](const char* name) -> std::optional<std::string> {
      const char* value = std::getenv(name);
      return value ? std::optional<std::string>(value) : std::nullopt;
    });
  } catch (const UsageError& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", nullptr}, {"usage", "roomrender serve --help"}});
    return 2;
  }
  try {
    // Block the stop signals before any thread starts, so every thread inherits the mask and
    // sigwait below is the only place they arrive.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
    std::signal(SIGPIPE, SIG_IGN);  // a client that hangs up must not end the process
    limit_malloc_arenas();
    Service service(config);
    service.start();
    nlohmann::ordered_json line = {{"event", "listening"},
                                   {"port", service.port()},
                                   {"url", "http://" + config.bind + ":" + std::to_string(service.port()) + "/"},
                                   {"version", version()}};
    line["config"] = nlohmann::ordered_json::parse(config_json(config));
    print_json_line(stdout, line);
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    DrainReport report = service.stop();
    print_json_line(
        stdout,
        {{"event", "stopped"}, {"signal", signal_number}, {"drained", report.drained}, {"seconds", report.seconds}});
    return 0;
  } catch (const std::exception& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", nullptr}});
    return 1;
  }
}

}  // namespace rr::server

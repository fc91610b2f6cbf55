// roomrender entry point: `roomrender <subcommand> [args]` -> the subcommand in cli/cli.hpp.
// Exit codes: 0 ok, 1 the command failed, 2 usage error (unknown subcommand, bad flags).
#include "cli/cli.hpp"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

struct Command {
  const char* name;
  int (*run)(std::span<const std::string> args);
};

constexpr Command commands[] = {
    {"render", rr::cli::run_render},
    {"export", rr::cli::run_export},
    {"import", rr::cli::run_import},
    {"serve", rr::server::run_serve},
    {"bench-render", rr::cli::run_bench_render},
    {"compare", rr::cli::run_compare},
};

int dispatch(const std::vector<std::string>& args) {
  if (args.empty()) {
    std::fputs(rr::cli::usage_text().c_str(), stderr);
    return 2;
  }
  const std::string& name = args[0];
  if (name == "help" || name == "--help" || name == "-h") {
    std::fputs(rr::cli::usage_text().c_str(), stdout);
    return 0;
  }
  if (name == "--version") {
    std::printf("roomrender %s\n", std::string(rr::cli::version()).c_str());
    return 0;
  }
  for (const Command& command : commands) {
    if (name == command.name) return command.run(std::span(args).subspan(1));
  }
  std::fprintf(stderr, "roomrender: unknown command '%s'\n\n%s", name.c_str(), rr::cli::usage_text().c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception&) {  // the subcommands report their own errors; this is a backstop
    std::fprintf(stderr, "{\"error\":\"internal error\",\"pointer\":null}\n");
    return 1;
  }
}

// Command-line plumbing every roomrender subcommand shares: flags are `--name VALUE` or
// `--name=VALUE`, each at most once ("-o" is short for "--output"); value parsers throw UsageError
// naming the flag; a file argument of `-` is stdin (inputs) or stdout (outputs). Machine output is
// one JSON line; errors are {"error", "pointer"} on stderr, plus "usage" (exit 2) or "flag".
#pragma once

#include "server/serve_command.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rr::cli {

using server::UsageError;

struct ParsedArgs {
  std::vector<std::string> positional;
  std::map<std::string, std::string> flags;  // "--name" -> value
  bool help = false;
};

// `value_flags` are the accepted flags (each takes a value); anything else starting with '-'
// (except "-" itself) is a usage error.
ParsedArgs parse_args(std::span<const std::string> args, const std::vector<std::string_view>& value_flags);
std::optional<std::string> flag(const ParsedArgs& args, const std::string& name);

int parse_int(const std::string& text, const std::string& what, int lo, int hi);
// Any int: for values whose range the request validator owns (it reports them with a pointer).
int parse_any_int(const std::string& text, const std::string& what);
double parse_double_flag(const std::string& text, const std::string& what);
nlohmann::json parse_vec3_flag(const std::string& text, const std::string& what);  // "x,y,z"
bool parse_switch_flag(const std::string& text, const std::string& what, const char* on, const char* off);
double parse_scale(const std::string& text);  // --scale, metres per file unit

std::string read_input(const std::string& path);                       // "-" reads stdin
void write_output(const std::string& path, const std::string& bytes);  // "-" writes stdout
// At most one of the named output flags may be "-": stdout carries one stream of bytes.
void check_one_stdout(const ParsedArgs& args, std::initializer_list<const char*> output_flags);
// Where the result line goes: stdout, unless one of the output flags sends its file there.
std::FILE* line_stream(const ParsedArgs& args, std::initializer_list<const char*> output_flags);

void print_json_line(std::FILE* stream, const nlohmann::ordered_json& line);
int usage_failure(const char* synopsis, const std::string& message);

// Runs a subcommand's work, turning exceptions into the one error line and exit code 1. An
// InputError at (or inside) a pointer in `flag_by_pointer` also names the flag that set it.
using FlagByPointer = std::map<std::string, std::string>;
int run_reporting_errors(const std::function<void()>& work, const FlagByPointer& flag_by_pointer = {});

}  // namespace rr::cli

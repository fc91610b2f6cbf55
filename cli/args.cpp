// The command-line plumbing of args.hpp: flag syntax, value parsers, files and the JSON lines.
#include "cli/args.hpp"

#include "render/scene_io/errors.hpp"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rr::cli {

ParsedArgs parse_args(std::span<const std::string> args, const std::vector<std::string_view>& value_flags) {
  ParsedArgs parsed;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string arg = args[i] == "-o" ? "--output" : args[i];
    if (arg == "--help" || arg == "-h") {
      parsed.help = true;
      continue;
    }
    if (arg.size() < 2 || arg[0] != '-') {  // includes "-", which means stdin
      parsed.positional.push_back(arg);
      continue;
    }
    std::optional<std::string> value;
    if (auto eq = arg.find('='); eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg.resize(eq);
    }
    if (std::find(value_flags.begin(), value_flags.end(), arg) == value_flags.end()) {
      throw UsageError("unknown option " + arg);
    }
    if (!value) {
      if (i + 1 == args.size()) throw UsageError(arg + " needs a value");
      value = args[++i];
    }
    if (!parsed.flags.emplace(arg, *value).second) throw UsageError(arg + " given twice");
  }
  return parsed;
}

std::optional<std::string> flag(const ParsedArgs& args, const std::string& name) {
  auto it = args.flags.find(name);
  if (it == args.flags.end()) return std::nullopt;
  return it->second;
}

int parse_int(const std::string& text, const std::string& what, int lo, int hi) {
  int value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || value < lo || value > hi) {
    throw UsageError(what + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], not '" +
                     text + "'");
  }
  return value;
}

int parse_any_int(const std::string& text, const std::string& what) {
  return parse_int(text, what, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
}

double parse_double_flag(const std::string& text, const std::string& what) {
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size()) {
    throw UsageError(what + " must be a number, not '" + text + "'");
  }
  return v;
}

nlohmann::json parse_vec3_flag(const std::string& text, const std::string& what) {
  nlohmann::json xyz = nlohmann::json::array();
  size_t at = 0;
  for (int k = 0; k < 3; ++k) {
    size_t end = k < 2 ? text.find(',', at) : text.size();
    double v = 0.0;
    auto [ptr, ec] = std::from_chars(text.data() + at, text.data() + std::min(end, text.size()), v);
    if (end == std::string::npos || ec != std::errc() || ptr != text.data() + end) {
      throw UsageError(what + " must be x,y,z, not '" + text + "'");
    }
    xyz.push_back(v);
    at = end + 1;
  }
  return xyz;
}

bool parse_switch_flag(const std::string& text, const std::string& what, const char* on, const char* off) {
  if (text == on) return true;
  if (text == off) return false;
  throw UsageError(what + " must be " + on + " or " + off + ", not '" + text + "'");
}

double parse_scale(const std::string& text) {
  char* end = nullptr;
  double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(value >= 1e-9 && value <= 1e7)) {
    throw UsageError("--scale must be a number in [1e-9, 1e7] (metres per file unit), not '" + text + "'");
  }
  return value;
}

std::string read_input(const std::string& path) {
  std::ostringstream text;
  if (path == "-") {
    text << std::cin.rdbuf();
    return text.str();
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  text << in.rdbuf();
  return text.str();
}

void write_output(const std::string& path, const std::string& bytes) {
  if (path == "-") {
    if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() || std::fflush(stdout) != 0) {
      throw std::runtime_error("cannot write to stdout");
    }
    return;
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path);
}

void check_one_stdout(const ParsedArgs& args, std::initializer_list<const char*> output_flags) {
  std::vector<std::string> to_stdout;
  for (const char* name : output_flags) {
    if (flag(args, name) == "-") to_stdout.push_back(name);
  }
  if (to_stdout.size() > 1) throw UsageError(to_stdout[0] + " and " + to_stdout[1] + " cannot both be - (stdout)");
}

std::FILE* line_stream(const ParsedArgs& args, std::initializer_list<const char*> output_flags) {
  for (const char* name : output_flags) {
    if (flag(args, name) == "-") return stderr;
  }
  return stdout;
}

void print_json_line(std::FILE* stream, const nlohmann::ordered_json& line) {
  std::string text = line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  std::fwrite(text.data(), 1, text.size(), stream);
  std::fflush(stream);
}

int usage_failure(const char* synopsis, const std::string& message) {
  print_json_line(stderr, {{"error", message}, {"pointer", nullptr}, {"usage", synopsis}});
  return 2;
}

namespace {

// The flag whose member holds `pointer`: the longest key that is the pointer or a parent of it.
std::optional<std::string> flag_for(const FlagByPointer& flag_by_pointer, const std::string& pointer) {
  std::optional<std::string> found;
  size_t found_length = 0;
  for (const auto& [key, name] : flag_by_pointer) {
    bool inside = pointer == key || (pointer.starts_with(key) && pointer[key.size()] == '/');
    if (inside && key.size() >= found_length) found = name, found_length = key.size();
  }
  return found;
}

}  // namespace

int run_reporting_errors(const std::function<void()>& work, const FlagByPointer& flag_by_pointer) {
  try {
    work();
    return 0;
  } catch (const InputError& e) {
    nlohmann::ordered_json line = {{"error", e.summary()}, {"pointer", e.pointer()}};
    if (auto name = flag_for(flag_by_pointer, e.pointer())) line["flag"] = *name;
    print_json_line(stderr, line);
  } catch (const std::exception& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", nullptr}});
  }
  return 1;
}

}  // namespace rr::cli

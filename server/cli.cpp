// The roomrender subcommands (see cli.hpp). Flags are `--name VALUE` or `--name=VALUE`; a request
// path of `-` reads stdin. Render overrides (--width, --height, --pipeline) are written into the
// request's "options" before validation, so they are checked exactly like values in the file.
#include "server/cli.hpp"

#include "render/errors.hpp"
#include "render/pipeline.hpp"
#include "render/scene_json.hpp"
#include "server/import_files.hpp"

#include <nlohmann/json.hpp>

#include <pthread.h>

#include <algorithm>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <vector>

#ifndef ROOMRENDER_VERSION
#define ROOMRENDER_VERSION "0.0.0"
#endif

namespace rr::server {
namespace {

constexpr const char* render_synopsis =
    "roomrender render REQUEST.json -o OUT.png [--ids FILE] [--width N] [--height N] [--pipeline NAME]\n"
    "  roomrender render --obj MODEL.obj [--scale S] -o OUT.png [...the same options]";
constexpr const char* import_synopsis =
    "roomrender import FILE [--format sh3d|r2v|obj] [--scale S] [--width N] [--height N] [--furniture boxes|models]";
constexpr const char* export_synopsis = "roomrender export REQUEST.json --obj FILE";
constexpr const char* serve_synopsis =
    "roomrender serve [--port 8080] [--bind 127.0.0.1] [OPTIONS]  (roomrender serve --help lists them)";

struct ParsedArgs {
  std::vector<std::string> positional;
  std::map<std::string, std::string> flags;  // "--name" -> value
  bool help = false;
};

// `value_flags` are the accepted flags (each takes a value); "-o" is short for "--output".
ParsedArgs parse_args(std::span<const std::string> args, std::initializer_list<std::string_view> value_flags) {
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

int parse_int(const std::string& text, const std::string& what, int lo, int hi) {
  int value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || value < lo || value > hi) {
    throw UsageError(what + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "], not '" + text + "'");
  }
  return value;
}

// Any int: for values whose range the request validator owns (it reports them with a pointer).
int parse_any_int(const std::string& text, const std::string& what) {
  return parse_int(text, what, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
}

std::optional<std::string> flag(const ParsedArgs& args, const std::string& name) {
  auto it = args.flags.find(name);
  if (it == args.flags.end()) return std::nullopt;
  return it->second;
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
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path);
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

// Runs a subcommand's work, turning exceptions into the one error line and exit code 1.
int run_reporting_errors(const std::function<void()>& work) {
  try {
    work();
    return 0;
  } catch (const InputError& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", e.pointer()}});
  } catch (const std::exception& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", nullptr}});
  }
  return 1;
}

// The request text with the command-line overrides written into its "options". Text that is not
// an object with an object "options" is passed on untouched, so validation reports it as usual.
std::string apply_overrides(const std::string& text, const ParsedArgs& args) {
  auto width = flag(args, "--width"), height = flag(args, "--height"), pipeline = flag(args, "--pipeline");
  if (!width && !height && !pipeline) return text;
  nlohmann::json request = parse_json_text(text);
  if (!request.is_object()) return text;
  nlohmann::json& options = request["options"];
  if (options.is_null()) options = nlohmann::json::object();
  if (!options.is_object()) return text;
  if (width) options["width"] = parse_any_int(*width, "--width");
  if (height) options["height"] = parse_any_int(*height, "--height");
  if (pipeline) options["pipeline"] = *pipeline;
  return request.dump();
}

void write_number(std::string& out, double value) {
  char buffer[32];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);  // shortest round-trip form
  out.append(buffer, result.ptr);
}

double parse_scale(const std::string& text) {
  char* end = nullptr;
  double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(value >= 1e-9 && value <= 1e6)) {
    throw UsageError("--scale must be a number in [1e-9, 1e6] (metres per file unit), not '" + text + "'");
  }
  return value;
}

// Imports FILE (format given, or recognised when nullopt) with the --scale/--width/--height flags;
// warnings go to stderr as JSON lines. Returns the request as JSON text.
std::string imported_request_text(const ParsedArgs& args, std::optional<ImportFormat> format, const std::string& file) {
  ImportOptions options;
  if (auto scale = flag(args, "--scale")) options.scale = parse_scale(*scale);
  // Only the aspect matters here: sizes out of range are reported by the request validator later.
  if (auto w = flag(args, "--width")) options.width = std::max(1, parse_any_int(*w, "--width"));
  if (auto h = flag(args, "--height")) options.height = std::max(1, parse_any_int(*h, "--height"));
  options.furniture_models = flag(args, "--furniture") == "models";
  ImportResult result = import_path(file, format, options);
  for (const std::string& warning : result.warnings) print_json_line(stderr, {{"warning", warning}});
  return result.request.dump();
}

}  // namespace

std::string_view version() { return ROOMRENDER_VERSION; }

std::string usage_text() {
  return std::string("roomrender ") + ROOMRENDER_VERSION + ": a CPU room renderer served over HTTP\n\nusage:\n  " +
         render_synopsis + "\n  " + import_synopsis + "\n  " + export_synopsis + "\n  " + serve_synopsis +
         "\n  roomrender help | --help\n  roomrender --version\n\n"
         "REQUEST.json may be '-' for stdin. render prints one JSON line of timings (ms) and counts;\n"
         "errors are one JSON line on stderr: {\"error\": ..., \"pointer\": ...}. Exit codes: 0 ok,\n"
         "1 failed, 2 usage. serve also reads each option from a ROOMRENDER_* variable (--data-dir:\n"
         "ROOMRENDER_DATA_DIR; flags win).\n";
}

int run_render(std::span<const std::string> argv) {
  ParsedArgs args;
  try {
    args = parse_args(argv, {"--output", "--ids", "--width", "--height", "--pipeline", "--obj", "--scale"});
    if (args.help) return std::printf("usage: %s\n", render_synopsis), 0;
    if (args.positional.size() != (flag(args, "--obj") ? 0u : 1u)) {
      throw UsageError(flag(args, "--obj") ? "give either a request file or --obj, not both" : "expected one request file");
    }
    if (flag(args, "--scale") && !flag(args, "--obj")) throw UsageError("--scale goes with --obj");
    if (auto scale = flag(args, "--scale")) parse_scale(*scale);
    if (!flag(args, "--output")) throw UsageError("-o OUT.png is required");
    // Checked now so a bad number is a usage error, not a failed render.
    if (auto w = flag(args, "--width")) parse_any_int(*w, "--width");
    if (auto h = flag(args, "--height")) parse_any_int(*h, "--height");
  } catch (const UsageError& e) {
    return usage_failure(render_synopsis, e.what());
  }
  return run_reporting_errors([&] {
    std::string text = flag(args, "--obj") ? imported_request_text(args, ImportFormat::obj, *flag(args, "--obj"))
                                           : read_input(args.positional[0]);
    EncodedRender out = render_request_text(apply_overrides(text, args));
    write_output(*flag(args, "--output"), out.png);
    if (auto ids = flag(args, "--ids")) write_output(*ids, encode_id_buffer(out.result.frame.ids));
    nlohmann::ordered_json line = nlohmann::ordered_json::parse(timings_json(out.result.timings, out.result.stats));
    line["scene_id"] = out.scene_id;
    line["width"] = out.result.frame.image.width;
    line["height"] = out.result.frame.image.height;
    print_json_line(stdout, line);
  });
}

int run_import(std::span<const std::string> argv) {
  ParsedArgs args;
  std::optional<ImportFormat> format;
  try {
    args = parse_args(argv, {"--format", "--scale", "--width", "--height", "--furniture"});
    if (args.help) return std::printf("usage: %s\n", import_synopsis), 0;
    if (args.positional.size() != 1) throw UsageError("expected one file to import");
    if (auto name = flag(args, "--format")) {
      const ImportFormatInfo* info = find_import_format(*name);
      if (!info) throw UsageError("--format must be sh3d, r2v or obj, not '" + *name + "'");
      format = info->format;
    }
    if (auto scale = flag(args, "--scale")) parse_scale(*scale);
    if (auto w = flag(args, "--width")) parse_any_int(*w, "--width");
    if (auto h = flag(args, "--height")) parse_any_int(*h, "--height");
    if (auto f = flag(args, "--furniture"); f && *f != "boxes" && *f != "models") {
      throw UsageError("--furniture must be boxes or models, not '" + *f + "'");
    }
  } catch (const UsageError& e) {
    return usage_failure(import_synopsis, e.what());
  }
  return run_reporting_errors([&] {
    std::string text = imported_request_text(args, format, args.positional[0]) + "\n";
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::fflush(stdout);
  });
}

std::string encode_obj(const PolygonSoup& soup, std::string_view comment) {
  std::vector<uint32_t> order(soup.polygons.size());
  std::iota(order.begin(), order.end(), 0u);
  // Ids equal indices by tessellate's invariant; sorting by id keeps the file right regardless.
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return soup.polygons[a].id < soup.polygons[b].id; });
  std::string out;
  out.reserve(soup.positions.size() * 48 + soup.polygons.size() * 24 + comment.size() + 64);
  std::istringstream lines{std::string(comment)};
  for (std::string line; std::getline(lines, line);) out += "# " + line + "\n";
  size_t next_index = 1;  // OBJ indices are 1-based and count every `v` line so far
  for (uint32_t i : order) {
    const Polygon& polygon = soup.polygons[i];
    for (const Vec3& p : soup.points(polygon)) {
      out += "v ";
      write_number(out, p.x);
      out += ' ';
      write_number(out, p.y);
      out += ' ';
      write_number(out, p.z);
      out += '\n';
    }
    out += 'f';
    for (uint32_t k = 0; k < polygon.vertex_count; ++k) out += ' ' + std::to_string(next_index + k);
    out += '\n';
    next_index += polygon.vertex_count;
  }
  return out;
}

int run_export(std::span<const std::string> argv) {
  ParsedArgs args;
  try {
    args = parse_args(argv, {"--obj"});
    if (args.help) return std::printf("usage: %s\n", export_synopsis), 0;
    if (args.positional.size() != 1) throw UsageError("expected one request file");
    if (!flag(args, "--obj")) throw UsageError("--obj FILE is required");
  } catch (const UsageError& e) {
    return usage_failure(export_synopsis, e.what());
  }
  return run_reporting_errors([&] {
    RenderRequest request = parse_request(read_input(args.positional[0]));
    PolygonSoup soup = tessellate(request.scene.geometry);
    std::string id = scene_id(request.scene.geometry);
    std::string comment = "roomrender " + std::string(version()) + " export of scene " + id + ": " +
                          std::to_string(soup.polygons.size()) + " polygons, world space, metres, +Y up.\n" +
                          "Polygon id k is the k-th f line; faces wind counter-clockwise seen from the front.";
    write_output(*flag(args, "--obj"), encode_obj(soup, comment));
    print_json_line(stdout, {{"polygons", soup.polygons.size()}, {"vertices", soup.positions.size()},
                             {"scene_id", id}, {"obj", *flag(args, "--obj")}});
  });
}

}  // namespace rr::server

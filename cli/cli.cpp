// The roomrender subcommands (see cli.hpp). Flags are `--name VALUE` or `--name=VALUE`; a request
// path of `-` reads stdin. Render overrides (--width, --height, --pipeline) are written into the
// request's "options" before validation, so they are checked exactly like values in the file.
#include "cli/cli.hpp"

#include "render/scene_io/measures_json.hpp"
#include "render/scene_io/errors.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/core/scene_id.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/report_json.hpp"
#include "render/scene_io/scene_json.hpp"
#include "render/import/import_files.hpp"
#include "render/core/png.hpp"
#include "render/core/shading.hpp"
#include "render/core/scene_names.hpp"
#include "render/core/timer.hpp"
#include "cli/bench_render.hpp"

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
#include <thread>
#include <sstream>
#include <vector>

namespace rr::cli {
namespace {

constexpr const char* render_synopsis =
    "roomrender render REQUEST.json -o OUT.png [--ids FILE] [--width N] [--height N] [--pipeline NAME]\n"
    "  roomrender render --obj MODEL.obj [--scale S] -o OUT.png [...the same options]";
constexpr const char* import_synopsis =
    "roomrender import FILE [--format sh3d|r2v|obj] [--scale S] [--width N] [--height N] [--furniture boxes|models]";
constexpr const char* export_synopsis = "roomrender export REQUEST.json --obj FILE";
constexpr const char* serve_synopsis =
    "roomrender serve [--port 8080] [--bind 127.0.0.1] [OPTIONS]  (roomrender serve --help lists them)";
constexpr const char* bench_synopsis =
    "roomrender bench-render (--request FILE | --obj FILE) [--eye x,y,z] [--target x,y,z] [--up x,y,z]\n"
    "                 [--fovy DEG] [--near N] [--far F] [--size WxH] [--light-dir x,y,z] [--pipeline NAME]\n"
    "                 [--shading NAME] [--shadows true|false] [--bsp-cache on|off] [--shadow-cache on|off]\n"
    "                 [--frames K] [--warmup N] [--threads N] [--out FILE.png] [--ids FILE]\n"
    "  roomrender bench-render --list";
constexpr const char* compare_synopsis = "roomrender compare REFERENCE.ids TEST.ids | roomrender compare REFERENCE.png TEST.png";

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
    print_json_line(stderr, {{"error", e.summary()}, {"pointer", e.pointer()}});
  } catch (const std::exception& e) {
    print_json_line(stderr, {{"error", e.what()}, {"pointer", nullptr}});
  }
  return 1;
}

// The request text with the command-line overrides written into its "options". Text that is not
// an object with an object "options" is passed on untouched, so validation reports it as usual.
// The request with --width, --height and --pipeline written into its options (before validation,
// so an override is checked like the member it replaces).
nlohmann::json apply_overrides(nlohmann::json request, const ParsedArgs& args) {
  auto width = flag(args, "--width"), height = flag(args, "--height"), pipeline = flag(args, "--pipeline");
  if (!width && !height && !pipeline) return request;
  if (!request.is_object()) return request;
  nlohmann::json& options = request["options"];
  if (options.is_null()) options = nlohmann::json::object();
  if (!options.is_object()) return request;
  if (width) options["width"] = parse_any_int(*width, "--width");
  if (height) options["height"] = parse_any_int(*height, "--height");
  if (pipeline) options["pipeline"] = *pipeline;
  return request;
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


std::string usage_text() {
  return "roomrender " + std::string(version()) + ": a CPU room renderer served over HTTP\n\nusage:\n  " +
         render_synopsis + "\n  " + import_synopsis + "\n  " + export_synopsis + "\n  " + serve_synopsis +
         "\n  " + bench_synopsis + "\n  " + compare_synopsis +
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
    // total runs from here (parse) to the end of encoding, as the service's does.
    Stopwatch total, parse_clock;
    RenderRequest request = request_from_json(apply_overrides(parse_json_text(text), args));
    RenderContext context;
    context.parse_ms = parse_clock.elapsed_ms();
    context.threads = std::max(1u, std::thread::hardware_concurrency());
    PreparedScene scene = prepare_scene(std::move(request.scene));
    context.tessellate_ms = scene.tessellate_ms;
    context.before_ms = total.elapsed_ms();
    RenderOutcome out = render(request, scene, context);
    write_output(*flag(args, "--output"), out.png);
    if (auto ids = flag(args, "--ids")) write_output(*ids, encode_id_buffer(out.frame.ids));
    nlohmann::ordered_json line = report_json(out.report);
    line["scene_id"] = out.report.scene_id;
    line["width"] = out.report.width;
    line["height"] = out.report.height;
    print_json_line(stdout, line);
  });
}

// Both files are id buffers or both PNGs (told apart by the PNG signature); the first is the
// reference. Prints error_measures_json: visibility for id buffers, shading for PNGs.
int run_compare(std::span<const std::string> argv) {
  ParsedArgs args;
  try {
    args = parse_args(argv, {});
    if (args.help) return std::printf("usage: %s\n", compare_synopsis), 0;
    if (args.positional.size() != 2) throw UsageError("expected two files: the reference, then the one to measure");
  } catch (const UsageError& e) {
    return usage_failure(compare_synopsis, e.what());
  }
  return run_reporting_errors([&] {
    const std::string a = read_input(args.positional[0]), b = read_input(args.positional[1]);
    auto is_png = [](const std::string& bytes) { return bytes.starts_with("\x89PNG\r\n\x1a\n"); };
    if (is_png(a) != is_png(b)) {
      throw std::runtime_error(args.positional[is_png(a) ? 0 : 1] + " is a PNG but " + args.positional[is_png(a) ? 1 : 0] +
                               " is not: compare two id buffers or two PNGs");
    }
    auto decode = [&](const std::string& bytes, size_t k, auto&& fn) {
      try {
        return fn(bytes);
      } catch (const std::exception& e) {
        throw std::runtime_error(args.positional[k] + ": " + e.what());
      }
    };
    ErrorMeasures m;
    if (is_png(a)) {
      const Image ra = decode(a, 0, decode_png), rb = decode(b, 1, decode_png);
      m.width = ra.width, m.height = ra.height;
      m.shading = shading_error(ra, rb);
    } else {
      const IdBuffer ra = decode(a, 0, decode_id_buffer), rb = decode(b, 1, decode_id_buffer);
      m.width = ra.width, m.height = ra.height;
      m.visibility = visibility_error(ra, rb);
    }
    print_json_line(stdout, error_measures_json(m));
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

}  // namespace rr::cli

namespace rr::cli {
namespace {

// "x,y,z" -> a JSON array of three numbers.
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

double parse_double_flag(const std::string& text, const std::string& what) {
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size()) {
    throw UsageError(what + " must be a number, not '" + text + "'");
  }
  return v;
}

bool parse_switch_flag(const std::string& text, const std::string& what, const char* on, const char* off) {
  if (text == on) return true;
  if (text == off) return false;
  throw UsageError(what + " must be " + on + " or " + off + ", not '" + text + "'");
}

// bench-render's camera, light and option flags as a patch of the request: {"camera": {...},
// "options": {...}} and, for --light-dir, "lights". Checked here only for syntax (a usage error);
// the request validator checks the values and names a bad one by its JSON Pointer.
nlohmann::json bench_overrides(const ParsedArgs& args) {
  nlohmann::json camera = nlohmann::json::object(), options = nlohmann::json::object();
  for (auto [name, key] : {std::pair{"--eye", "position"}, {"--target", "target"}, {"--up", "up"}}) {
    if (auto v = flag(args, name)) camera[key] = parse_vec3_flag(*v, name);
  }
  for (auto [name, key] : {std::pair{"--fovy", "fov_y"}, {"--near", "near"}, {"--far", "far"}}) {
    if (auto v = flag(args, name)) camera[key] = parse_double_flag(*v, name);
  }
  if (auto size = flag(args, "--size")) {
    auto x = size->find('x');
    if (x == std::string::npos) throw UsageError("--size must be WxH, not '" + *size + "'");
    options["width"] = parse_any_int(size->substr(0, x), "--size width");
    options["height"] = parse_any_int(size->substr(x + 1), "--size height");
  }
  for (const char* name : {"--pipeline", "--shading"}) {
    if (auto v = flag(args, name)) options[name + 2] = *v;
  }
  if (auto v = flag(args, "--shadows")) options["shadows"] = parse_switch_flag(*v, "--shadows", "true", "false");
  nlohmann::json patch = {{"camera", camera}, {"options", options}};
  if (auto v = flag(args, "--light-dir")) {
    // The flag points toward the light (the OpenGL peer's convention); the format's direction is
    // the one the light travels.
    nlohmann::json toward = parse_vec3_flag(*v, "--light-dir");
    nlohmann::json travels = {-toward[0].get<double>(), -toward[1].get<double>(), -toward[2].get<double>()};
    patch["lights"] = nlohmann::json::array({{{"type", "directional"}, {"direction", travels}}});
  }
  return patch;
}

// Writes the patch into the request; --light-dir replaces the scene's lights by one white
// directional light. A request that is not an object (or whose members are not) is left as it is
// for the validator to report.
nlohmann::json apply_bench_overrides(nlohmann::json request, const nlohmann::json& patch) {
  if (!request.is_object()) return request;
  for (const char* key : {"camera", "options", "scene"}) {
    if (request[key].is_null()) request[key] = nlohmann::json::object();
    if (!request[key].is_object()) return request;
  }
  request["camera"].update(patch["camera"]);
  request["options"].update(patch["options"]);
  if (patch.contains("lights")) request["scene"]["lights"] = patch["lights"];
  return request;
}

// What bench-render can be asked for on this build: the benchmark script iterates these.
void print_bench_modes() {
  nlohmann::ordered_json pipelines = nlohmann::ordered_json::array(), shadings = nlohmann::ordered_json::array();
  for (const PipelineInfo& p : pipeline_table()) pipelines.push_back(p.name);
  for (const auto& s : shading_names) shadings.push_back(s.name);
  print_json_line(stdout, {{"pipelines", pipelines}, {"shadings", shadings}});
}

}  // namespace

int run_bench_render(std::span<const std::string> argv) {
  if (std::find(argv.begin(), argv.end(), "--list") != argv.end()) return print_bench_modes(), 0;
  ParsedArgs args;
  BenchRun run;
  nlohmann::json overrides;
  try {
    args = parse_args(argv, {"--request", "--obj", "--eye", "--target", "--up", "--fovy", "--near", "--far",
                             "--size", "--light-dir", "--pipeline", "--shading", "--shadows", "--bsp-cache",
                             "--shadow-cache", "--frames", "--warmup", "--out", "--ids", "--threads"});
    if (args.help) return std::printf("usage: %s\n", bench_synopsis), 0;
    if (!args.positional.empty()) throw UsageError("unexpected argument " + args.positional[0]);
    if (flag(args, "--request").has_value() == flag(args, "--obj").has_value()) {
      throw UsageError("give exactly one of --request FILE and --obj FILE");
    }
    if (auto v = flag(args, "--frames")) run.frames = parse_int(*v, "--frames", 1, 100000);
    if (auto v = flag(args, "--warmup")) run.warmup = parse_int(*v, "--warmup", 0, 100000);
    run.threads = std::max(1u, std::thread::hardware_concurrency());
    if (auto v = flag(args, "--threads")) run.threads = unsigned(parse_int(*v, "--threads", 1, 64));
    if (auto v = flag(args, "--bsp-cache")) run.bsp_cache = parse_switch_flag(*v, "--bsp-cache", "on", "off");
    if (auto v = flag(args, "--shadow-cache")) {
      run.shadow_cache = parse_switch_flag(*v, "--shadow-cache", "on", "off");
    }
    overrides = bench_overrides(args);
  } catch (const UsageError& e) {
    return usage_failure(bench_synopsis, e.what());
  }
  return run_reporting_errors([&] {
    // --obj goes through the OBJ importer (groups become mesh solids in file order), so polygon id k
    // is the k-th `f` line when groups do not interleave and no face needed repair (docs/import.md).
    const bool from_obj = flag(args, "--obj").has_value();
    std::string input = from_obj ? *flag(args, "--obj") : *flag(args, "--request");
    std::string text = from_obj ? imported_request_text(args, ImportFormat::obj, input) : read_input(input);
    RenderRequest request = request_from_json(apply_bench_overrides(parse_json_text(text), overrides));
    const PreparedScene scene = prepare_scene(std::move(request.scene));
    const PolygonSoup& soup = scene.soup;
    const double setup_ms = scene.tessellate_ms;
    BenchReport report = bench_frames(request, scene, run);
    if (auto out = flag(args, "--out")) {
      write_output(*out, encode_png(report.last.frame.image, request.options.png_compression, run.threads));
    }
    if (auto ids = flag(args, "--ids")) write_output(*ids, encode_id_buffer(report.last.frame.ids));
    nlohmann::ordered_json line = {{"source", from_obj ? "obj" : "request"}, {"input", input},
                                   {"pipeline", pipeline_info(request.options.pipeline).name},
                                   {"shading", shading_names.name(request.options.shading)},
                                   {"shadows", request.options.shadows},
                                   {"width", request.options.width}, {"height", request.options.height},
                                   {"polygons", soup.polygons.size()}, {"triangles", fan_triangle_count(soup)},
                                   {"setup_ms", std::round(setup_ms * 1000.0) / 1000.0}};
    line.update(bench_report_json(report, run));
    print_json_line(stdout, line);
  });
}

}  // namespace rr::cli

// The roomrender subcommands (see cli.hpp) but bench-render (bench_render.cpp). Flag syntax, files
// and JSON lines are args.hpp's; the flags that set request members (camera, size, pipeline, shading,
// shadows, PNG encoder) are request_flags.hpp's one table, shared with bench-render.
#include "cli/cli.hpp"

#include "cli/args.hpp"
#include "cli/bench_render.hpp"
#include "cli/request_flags.hpp"
#include "render/core/error_metrics.hpp"
#include "render/core/png.hpp"
#include "render/core/sample_pattern.hpp"
#include "render/core/scene_id.hpp"
#include "render/core/shading.hpp"
#include "render/core/timer.hpp"
#include "render/import/import_files.hpp"
#include "render/pipelines/pipeline_table.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/measures_json.hpp"
#include "render/scene_io/report_json.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/catalogue_store.hpp"
#include "server/server_config.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <sstream>
#include <thread>
#include <vector>

namespace rr::cli {
namespace {

constexpr const char* render_synopsis =
    "roomrender render REQUEST.json -o OUT.png|- [--ids FILE] [--reference-samples 256] [REQUEST FLAGS]\n"
    "  roomrender render --obj MODEL.obj [--scale S] -o OUT.png|- [...the same options]\n"
    "  -o - writes the PNG to stdout and the timings line to stderr; -o /dev/null: the timings only\n"
    "  --reference-samples S: the reference pipeline's rays per pixel, 1, 4, 8, 16 or 256 (the 16x16\n"
    "  grid: the edge-error ground truth, docs/antialiasing.md); overrides options.antialias";
constexpr const char* import_synopsis =
    "roomrender import FILE [--format sh3d|r2v|obj] [--scale S] [--width N] [--height N] [--furniture boxes|models]";
constexpr const char* export_synopsis = "roomrender export REQUEST.json --obj FILE";
constexpr const char* serve_synopsis =
    "roomrender serve [--port 8080] [--bind 127.0.0.1] [OPTIONS]  (roomrender serve --help lists them)";
constexpr const char* compare_synopsis =
    "roomrender compare REFERENCE.ids TEST.ids | roomrender compare REFERENCE.png TEST.png [--edges REFERENCE.ids]\n"
    "                   [--request REQUEST.json | --obj MODEL.obj] [--test-ids TEST.ids]\n"
    "  --edges: also the edge error (mean and p99 colour error on the edge pixels of REFERENCE.ids)\n"
    "  --request/--obj (with --edges): also the texture error, on the pixels of REFERENCE.ids that show a\n"
    "  textured polygon of that scene away from its edges; --test-ids: only where TEST drew the same polygon";

// --reference-samples: any sample_pattern() count, for the reference pipeline only (the request
// validator keeps options.antialias to 1, 4, 8 and 16; 256 rays per pixel is a measuring tool).
std::optional<int> reference_samples(const ParsedArgs& args) {
  auto text = flag(args, "--reference-samples");
  if (!text) return std::nullopt;
  const int samples = parse_int(*text, "--reference-samples", 1, 256);
  if (!is_sample_count(samples) && samples != 256) throw UsageError("--reference-samples must be 1, 4, 8, 16 or 256");
  return samples;
}

void write_number(std::string& out, double value) {
  char buffer[32];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);  // shortest round-trip form
  out.append(buffer, result.ptr);
}

}  // namespace

ParseLimits request_limits() {
  const char* dir = std::getenv("ROOMRENDER_CATALOGUE_DIR");
  return server::lazy_catalogue_limits(
      ParseLimits{}, dir && *dir ? std::filesystem::path(dir) : server::default_server_config().catalogue_dir);
}

std::string usage_text() {
  return "roomrender " + std::string(version()) + ": a CPU room renderer served over HTTP\n\nusage:\n  " +
         render_synopsis + "\n  " + import_synopsis + "\n  " + export_synopsis + "\n  " + serve_synopsis + "\n  " +
         bench_synopsis + "\n  " + compare_synopsis +
         "\n  roomrender help | --help\n  roomrender --version\n\n"
         "REQUEST.json may be '-' for stdin. render prints one JSON line of timings (ms) and counts;\n"
         "errors are one JSON line on stderr: {\"error\": ..., \"pointer\": ...}. Exit codes: 0 ok,\n"
         "1 failed, 2 usage. serve also reads each option from a ROOMRENDER_* variable (--data-dir:\n"
         "ROOMRENDER_DATA_DIR; flags win).\n\n" +
         request_flags_help();
}

int run_render(std::span<const std::string> argv) {
  ParsedArgs args;
  RequestPatch patch;
  try {
    args = parse_args(argv, with_request_flags({"--output", "--ids", "--obj", "--scale", "--reference-samples"}));
    if (args.help) return std::printf("usage: %s\n\n%s", render_synopsis, request_flags_help().c_str()), 0;
    if (args.positional.size() != (flag(args, "--obj") ? 0u : 1u)) {
      throw UsageError(flag(args, "--obj") ? "give either a request file or --obj, not both"
                                           : "expected one request file");
    }
    if (flag(args, "--scale") && !flag(args, "--obj")) throw UsageError("--scale goes with --obj");
    if (auto scale = flag(args, "--scale")) parse_scale(*scale);
    if (!flag(args, "--output")) throw UsageError("-o OUT.png is required (- for stdout)");
    check_one_stdout(args, {"--output", "--ids"});
    // Parsed now so a malformed value is a usage error naming its flag, not a failed render.
    patch = request_patch(args);
    reference_samples(args);
  } catch (const UsageError& e) {
    return usage_failure(render_synopsis, e.what());
  }
  return run_reporting_errors(
      [&] {
        std::string text = flag(args, "--obj") ? imported_request_text(*flag(args, "--obj"), ImportFormat::obj,
                                                                       import_options(args, patch))
                                               : read_input(args.positional[0]);
        // total runs from here (parse) to the end of encoding, as the service's does.
        Stopwatch total, parse_clock;
        RenderRequest request = request_from_json(apply_request_patch(parse_json_text(text), patch), request_limits());
        if (auto samples = reference_samples(args)) {
          if (request.options.pipeline != pipeline_id("reference")) {
            throw std::runtime_error("--reference-samples needs the reference pipeline (--pipeline reference)");
          }
          request.options.antialias = *samples;
        }
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
        print_json_line(line_stream(args, {"--output", "--ids"}), line);
      },
      patch.flag_by_pointer);
}

namespace {

// compare's texture error: which polygon ids are textured comes from the request (or the OBJ) of
// --request / --obj, tessellated as a render tessellates it; --test-ids keeps the pixels where the
// test drew the reference's polygon.
TexturedPixelError compare_textures(const ParsedArgs& args, const IdBuffer& reference_ids, const Image& reference,
                                    const Image& test) {
  const std::string text = flag(args, "--obj")
                               ? imported_request_text(*flag(args, "--obj"), ImportFormat::obj, ImportOptions{})
                               : read_input(*flag(args, "--request"));
  const RenderRequest request = request_from_json(parse_json_text(text), request_limits());
  std::optional<IdBuffer> test_ids;
  if (auto path = flag(args, "--test-ids")) test_ids = decode_id_buffer(read_input(*path));
  return texture_error(reference_ids, textured_polygons(tessellate(request.scene.geometry)), reference, test,
                       test_ids ? &*test_ids : nullptr);
}

}  // namespace

// Both files are id buffers or both PNGs (told apart by the PNG signature); the first is the
// reference. Prints error_measures_json: visibility for id buffers, shading for PNGs.
int run_compare(std::span<const std::string> argv) {
  ParsedArgs args;
  try {
    args = parse_args(argv, {"--edges", "--request", "--obj", "--test-ids"});
    if (args.help) return std::printf("usage: %s\n", compare_synopsis), 0;
    if (args.positional.size() != 2) throw UsageError("expected two files: the reference, then the one to measure");
    if (flag(args, "--request") && flag(args, "--obj")) throw UsageError("give either --request or --obj, not both");
    const bool textured = flag(args, "--request") || flag(args, "--obj");
    if (textured && !flag(args, "--edges")) {
      throw UsageError("the texture error needs the reference's polygon ids: --edges REFERENCE.ids");
    }
    if (flag(args, "--test-ids") && !textured) throw UsageError("--test-ids goes with --request or --obj");
  } catch (const UsageError& e) {
    return usage_failure(compare_synopsis, e.what());
  }
  return run_reporting_errors([&] {
    const std::string a = read_input(args.positional[0]), b = read_input(args.positional[1]);
    auto is_png = [](const std::string& bytes) { return bytes.starts_with("\x89PNG\r\n\x1a\n"); };
    if (is_png(a) != is_png(b)) {
      throw std::runtime_error(args.positional[is_png(a) ? 0 : 1] + " is a PNG but " +
                               args.positional[is_png(a) ? 1 : 0] + " is not: compare two id buffers or two PNGs");
    }
    auto decode = [&](const std::string& bytes, size_t k, auto&& fn) {
      try {
        return fn(bytes);
      } catch (const std::exception& e) {
        throw std::runtime_error(args.positional[k] + ": " + e.what());
      }
    };
    if (flag(args, "--edges") && !is_png(a)) throw std::runtime_error("--edges measures PNGs: give two PNGs");
    ErrorMeasures m;
    std::optional<EdgeError> edges;
    std::optional<TexturedPixelError> texture;
    if (is_png(a)) {
      const Image ra = decode(a, 0, decode_png), rb = decode(b, 1, decode_png);
      m.width = ra.width, m.height = ra.height;
      m.shading = shading_error(ra, rb);
      if (auto path = flag(args, "--edges")) {
        const IdBuffer ids = decode_id_buffer(read_input(*path));
        edges = edge_error(ids, ra, rb);
        if (flag(args, "--request") || flag(args, "--obj")) texture = compare_textures(args, ids, ra, rb);
      }
    } else {
      const IdBuffer ra = decode(a, 0, decode_id_buffer), rb = decode(b, 1, decode_id_buffer);
      m.width = ra.width, m.height = ra.height;
      m.visibility = visibility_error(ra, rb);
    }
    nlohmann::ordered_json line = error_measures_json(m);
    if (edges) {
      line["edge"] = {{"pixels", edges->edge_pixels},
                      {"share", double(edges->edge_pixels) / double(edges->pixels)},
                      {"mean", edges->mean},
                      {"p99", edges->p99},
                      {"max", edges->max}};
    }
    if (texture) {  // JSON has no infinity: a PSNR of identical pixels (or of none) is null
      line["texture"] = {{"pixels", texture->pixels},
                         {"rmse", texture->rmse},
                         {"psnr_db", std::isfinite(texture->psnr_db) ? nlohmann::ordered_json(texture->psnr_db)
                                                                     : nlohmann::ordered_json(nullptr)}};
    }
    print_json_line(stdout, line);
  });
}

int run_import(std::span<const std::string> argv) {
  ParsedArgs args;
  RequestPatch patch;
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
    patch = request_patch(args);  // only --width and --height are accepted: they aim the camera
    if (auto f = flag(args, "--furniture"); f && *f != "boxes" && *f != "models") {
      throw UsageError("--furniture must be boxes or models, not '" + *f + "'");
    }
  } catch (const UsageError& e) {
    return usage_failure(import_synopsis, e.what());
  }
  return run_reporting_errors([&] {
    std::string text = imported_request_text(args.positional[0], format, import_options(args, patch)) + "\n";
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
    RenderRequest request = parse_request(read_input(args.positional[0]), request_limits());
    PolygonSoup soup = tessellate(request.scene.geometry);
    std::string id = scene_id(request.scene.geometry);
    std::string comment = "roomrender " + std::string(version()) + " export of scene " + id + ": " +
                          std::to_string(soup.polygons.size()) + " polygons, world space, metres, +Y up.\n" +
                          "Polygon id k is the k-th f line; faces wind counter-clockwise seen from the front.";
    write_output(*flag(args, "--obj"), encode_obj(soup, comment));
    print_json_line(stdout, {{"polygons", soup.polygons.size()},
                             {"vertices", soup.positions.size()},
                             {"scene_id", id},
                             {"obj", *flag(args, "--obj")}});
  });
}

}  // namespace rr::cli

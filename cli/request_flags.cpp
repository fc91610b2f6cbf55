// The request-setting flags (see request_flags.hpp): one row per flag, one switch on its kind.
#include "cli/request_flags.hpp"

#include "render/core/scene_names.hpp"
#include "render/import/import_files.hpp"
#include "render/pipelines/pipeline.hpp"

#include <algorithm>

namespace rr::cli {
namespace {

using nlohmann::json;

enum class Kind { vec3, number, number_or_auto, integer, size, name, boolean, light };
enum class Names { none, pipelines, shadings, png, culling, shadow_methods, texture_filters };

struct RequestFlag {
  const char* name;
  const char* pointer;  // the member it sets (--size: width, then height beside it)
  Kind kind;
  const char* value;  // how --help shows the value
  Names names;        // for Kind::name: the table whose names it takes
  const char* help;
};

// The camera flags take OpenGL's look-at conventions, as bench/peer/osmesa_bench.cpp does.
constexpr RequestFlag request_flag_rows[] = {
    {"--eye", "/camera/position", Kind::vec3, "x,y,z", Names::none, "camera position, metres"},
    {"--target", "/camera/target", Kind::vec3, "x,y,z", Names::none, "the point the camera looks at"},
    {"--up", "/camera/up", Kind::vec3, "x,y,z", Names::none, "the camera's up direction"},
    {"--fovy", "/camera/fov_y", Kind::number, "DEG", Names::none, "vertical field of view, degrees"},
    {"--near", "/camera/near", Kind::number, "N", Names::none, "near plane distance, metres"},
    {"--far", "/camera/far", Kind::number, "F", Names::none, "far plane distance, metres"},
    {"--width", "/options/width", Kind::integer, "N", Names::none, "image width, pixels"},
    {"--height", "/options/height", Kind::integer, "N", Names::none, "image height, pixels"},
    {"--size", "/options/width", Kind::size, "WxH", Names::none, "image size, pixels (not with --width/--height)"},
    {"--pipeline", "/options/pipeline", Kind::name, nullptr, Names::pipelines, "hidden-surface pipeline"},
    {"--shading", "/options/shading", Kind::name, nullptr, Names::shadings, "shading mode"},
    {"--shadows", "/options/shadows", Kind::boolean, "true|false", Names::none, "shadows"},
    {"--shadow-method", "/options/shadow/method", Kind::name, nullptr, Names::shadow_methods,
     "shadows from maps, or exact rays toward each light"},
    {"--texture-filter", "/options/texture_filter", Kind::name, nullptr, Names::texture_filters,
     "how textures are filtered"},
    {"--antialias", "/options/antialias", Kind::integer, "S", Names::none,
     "coverage sub-samples per pixel: 1, 4, 8 or 16"},
    {"--exposure", "/options/exposure", Kind::number_or_auto, "E|auto", Names::none,
     "multiplies the lights and ambient (default 1), or auto: a mean luminance of 0.45"},
    {"--png", "/options/png/compression", Kind::name, nullptr, Names::png, "PNG encoder (none: stored, unfiltered)"},
    {"--culling", "/options/culling", Kind::name, nullptr, Names::culling,
     "occlusion culling (the same bytes either way; docs/culling.md)"},
    {"--light-dir", "/scene/lights", Kind::light, "x,y,z", Names::none, "one white light toward x,y,z, no others"},
};

std::string value_names(Names names) {
  std::string out;
  auto add = [&](std::string_view name) {
    if (!out.empty()) out += '|';
    out += name;
  };
  switch (names) {
    case Names::pipelines:
      for (const PipelineInfo& p : pipeline_table()) add(p.name);
      break;
    case Names::shadings:
      for (const auto& row : shading_names) add(row.name);
      break;
    case Names::png:
      for (const auto& row : png_compression_names) add(row.name);
      break;
    case Names::culling:
      for (const auto& row : culling_mode_names) add(row.name);
      break;
    case Names::shadow_methods:
      for (const auto& row : shadow_method_names) add(row.name);
      break;
    case Names::texture_filters:
      for (const auto& row : texture_filter_names) add(row.name);
      break;
    case Names::none:
      break;
  }
  return out;
}

void add_entry(RequestPatch& patch, const std::string& pointer, json value, const char* flag_name) {
  patch.entries.push_back({pointer, std::move(value)});
  patch.flag_by_pointer[pointer] = flag_name;
}

// Parses one present flag's value into the patch (syntax only: ranges and names are the validator's).
void add_flag(RequestPatch& patch, const RequestFlag& row, const std::string& text) {
  switch (row.kind) {
    case Kind::vec3:
      return add_entry(patch, row.pointer, parse_vec3_flag(text, row.name), row.name);
    case Kind::number:
      return add_entry(patch, row.pointer, parse_double_flag(text, row.name), row.name);
    case Kind::number_or_auto:
      if (text == "auto") return add_entry(patch, row.pointer, text, row.name);
      return add_entry(patch, row.pointer, parse_double_flag(text, row.name), row.name);
    case Kind::integer:
      return add_entry(patch, row.pointer, parse_any_int(text, row.name), row.name);
    case Kind::name:
      return add_entry(patch, row.pointer, text, row.name);
    case Kind::boolean:
      return add_entry(patch, row.pointer, parse_switch_flag(text, row.name, "true", "false"), row.name);
    case Kind::size: {
      auto x = text.find('x');
      if (x == std::string::npos) throw UsageError("--size must be WxH, not '" + text + "'");
      add_entry(patch, "/options/width", parse_any_int(text.substr(0, x), "--size width"), row.name);
      return add_entry(patch, "/options/height", parse_any_int(text.substr(x + 1), "--size height"), row.name);
    }
    case Kind::light: {
      // The flag points toward the light (the OpenGL peer's convention); the format's direction is
      // the one the light travels.
      json toward = parse_vec3_flag(text, row.name);
      json travels = {-toward[0].get<double>(), -toward[1].get<double>(), -toward[2].get<double>()};
      return add_entry(patch, row.pointer, json::array({{{"type", "directional"}, {"direction", travels}}}), row.name);
    }
  }
}

}  // namespace

std::vector<std::string_view> with_request_flags(std::initializer_list<std::string_view> own) {
  std::vector<std::string_view> names(own);
  for (const RequestFlag& row : request_flag_rows) names.push_back(row.name);
  return names;
}

std::string request_flags_help() {
  std::string out =
      "REQUEST FLAGS (render, bench-render) set members of the request, written into it before it is\n"
      "checked: a flag wins over the file's value, and a value the file could not hold is reported at\n"
      "the member's JSON Pointer (exit 1, the line names the flag); a malformed one is a usage error.\n";
  for (const RequestFlag& row : request_flag_rows) {
    std::string left = std::string(row.name) + " " + (row.value ? row.value : value_names(row.names));
    left.resize(std::max<size_t>(left.size() + 2, 34), ' ');
    std::string pointer = row.kind == Kind::size ? "/options/width, /options/height" : row.pointer;
    out += "    " + left + row.help + " (" + pointer + ")\n";
  }
  return out;
}

const nlohmann::json* RequestPatch::find(const std::string& pointer) const {
  for (const Entry& e : entries) {
    if (e.pointer == pointer) return &e.value;
  }
  return nullptr;
}

RequestPatch request_patch(const ParsedArgs& args) {
  if (flag(args, "--size") && (flag(args, "--width") || flag(args, "--height"))) {
    throw UsageError("--size sets --width and --height: give one or the other");
  }
  RequestPatch patch;
  for (const RequestFlag& row : request_flag_rows) {
    if (auto text = flag(args, row.name)) add_flag(patch, row, *text);
  }
  return patch;
}

json apply_request_patch(json request, const RequestPatch& patch) {
  for (const RequestPatch::Entry& entry : patch.entries) {
    const std::string& path = entry.pointer;  // "/a/b/c": the table's pointers need no escaping
    json* at = &request;
    size_t from = 1;
    for (size_t slash; at && (slash = path.find('/', from)) != std::string::npos; from = slash + 1) {
      at = at->is_null() || at->is_object() ? &(*at)[path.substr(from, slash - from)] : nullptr;
    }
    if (at && (at->is_null() || at->is_object())) (*at)[path.substr(from)] = entry.value;
  }
  return request;
}

ImportOptions import_options(const ParsedArgs& args, const RequestPatch& patch) {
  ImportOptions options;
  if (auto scale = flag(args, "--scale")) options.scale = parse_scale(*scale);
  // Only the aspect matters here: sizes out of range are reported by the request validator later.
  if (const json* w = patch.find("/options/width")) options.width = std::max(1, w->get<int>());
  if (const json* h = patch.find("/options/height")) options.height = std::max(1, h->get<int>());
  options.furniture_models = flag(args, "--furniture") == "models";
  return options;
}

std::string imported_request_text(const std::string& file, std::optional<ImportFormat> format,
                                  const ImportOptions& options) {
  ImportResult result = import_path(file, format, options);
  for (const std::string& warning : result.warnings) print_json_line(stderr, {{"warning", warning}});
  return result.request.dump();
}

}  // namespace rr::cli

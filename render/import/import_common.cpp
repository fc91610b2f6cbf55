// Shared importer pieces (import_common.hpp) and the format table behind import_file_text: which
// importer reads which format, how a format is recognised from content and name, default scales.
#include "render/import/import_common.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace rr {

namespace import_detail {

void throw_at_line(Kind kind, size_t line, const std::string& detail) {
  throw InputError(kind, "/line/" + std::to_string(line), "line " + std::to_string(line) + ": " + detail);
}

std::optional<std::string_view> LineReader::next() {
  if (pos_ >= text_.size()) return std::nullopt;
  size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  std::string_view line = text_.substr(pos_, end - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end + 1;
  ++line_;
  return line;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

std::optional<double> parse_double(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);  // from_chars refuses '+'
  double value = 0.0;
  auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<long long> parse_long(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  long long value = 0;
  auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size() || field.empty()) return std::nullopt;
  return value;
}

double resolve_scale(const ImportOptions& options, ImportFormat format) {
  if (options.scale == 0.0) return import_format_info(format).default_scale;
  // 1e7 keeps a unit-sized file inside the coordinate limit; below 1e-9 nothing would be visible.
  if (!std::isfinite(options.scale) || options.scale < 1e-9 || options.scale > 1e7) {
    throw InputError(Kind::invalid, "/scale", "scale must be a number in [1e-9, 1e7] metres per unit");
  }
  return options.scale;
}

double round_m(double metres) {
  double rounded = std::round(metres * 1e6) / 1e6;
  return rounded == 0.0 ? 0.0 : rounded;  // no "-0.0" in the output
}

nlohmann::json json_vec2(Vec2 v) { return nlohmann::json::array({round_m(v.x), round_m(v.y)}); }

nlohmann::json json_vec3(Vec3 v) { return nlohmann::json::array({round_m(v.x), round_m(v.y), round_m(v.z)}); }

nlohmann::json json_color(Color c) {
  auto channel = [](float v) { return std::round(double(std::clamp(v, 0.0f, 1.0f)) * 1000.0) / 1000.0; };
  return nlohmann::json::array({channel(c.r), channel(c.g), channel(c.b)});
}

nlohmann::json camera_showing_box(const Box3& box, double aspect, double elevation_deg) {
  Box3 b = box;
  if (b.empty()) b.add(Vec3{0.0}), b.add(Vec3{1.0});
  const Vec3 centre = 0.5 * (b.lo + b.hi);
  const double radius = std::max(0.5 * glm::length(b.hi - b.lo), 0.05);
  const double fov_y_deg = 50.0;
  const double half_y = radians(fov_y_deg) / 2.0;
  const double half_x = std::atan(std::tan(half_y) * aspect);
  // The sphere fits when its centre is radius / sin(half angle) away; 5% margin.
  const double distance = 1.05 * radius / std::sin(std::min(half_x, half_y));
  const double elevation = radians(elevation_deg);
  const Vec3 position = centre + distance * Vec3(0.0, std::sin(elevation), std::cos(elevation));
  const double near = std::max(0.5 * (distance - radius), 1e-3 * radius);
  return {{"position", json_vec3(position)},
          {"target", json_vec3(centre)},
          {"fov_y", fov_y_deg},
          {"near", round_m(near)},
          {"far", round_m(distance + 2.0 * radius)}};
}

nlohmann::json request_options(const ImportOptions& options) {
  return {{"width", options.width}, {"height", options.height}};
}

nlohmann::json default_sun_light() {
  return {{"type", "directional"}, {"direction", {-0.35, -1.0, -0.55}}, {"intensity", 0.75}};
}

}  // namespace import_detail

namespace {

constexpr std::array<ImportFormatInfo, 3> format_table = {{
    {ImportFormat::sweethome3d, "sh3d",
     "Sweet Home 3D home: Home.xml, a .sh3d, or a zip of a home XML and its furniture/ (cm)", 0.01},
    {ImportFormat::r2v, "r2v", "Raster-to-Vector floor plan annotation: walls and openings in image pixels", 0.025},
    {ImportFormat::obj, "obj", "Wavefront OBJ model, or a zip of one with its .mtl diffuse colours", 1.0},
}};

bool contains(std::string_view haystack, std::string_view needle) {
  return haystack.find(needle) != std::string_view::npos;
}

std::string lower_extension(std::string_view file_name) {
  size_t dot = file_name.rfind('.');
  if (dot == std::string_view::npos) return "";
  std::string ext(file_name.substr(dot + 1));
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

std::span<const ImportFormatInfo> import_format_table() { return format_table; }

const ImportFormatInfo* find_import_format(std::string_view name) {
  for (const ImportFormatInfo& info : format_table) {
    if (name == info.name) return &info;
  }
  return nullptr;
}

const ImportFormatInfo& import_format_info(ImportFormat format) {
  for (const ImportFormatInfo& info : format_table) {
    if (info.format == format) return info;
  }
  return format_table[0];  // unreachable: every enumerator has a row
}

std::optional<ImportFormat> detect_import_format(std::string_view bytes, std::string_view file_name) {
  // Content first: a zip, or XML whose root is <home>, is Sweet Home 3D; an R2V line is
  // "x1<TAB>y1<TAB>x2<TAB>y2<TAB>category..."; OBJ has "v " and "f " lines. Only the head is read.
  std::string_view head = bytes.substr(0, 4096);
  if (looks_like_zip(head)) return ImportFormat::sweethome3d;
  if (head.find("<home") != std::string_view::npos) return ImportFormat::sweethome3d;
  if (contains(head, "\twall\t") || contains(head, "\tdoor\t")) return ImportFormat::r2v;
  if (contains(head, "\nv ") || head.starts_with("v ") || contains(head, "\nf ") || contains(head, "mtllib ")) {
    return ImportFormat::obj;
  }
  std::string ext = lower_extension(file_name);
  if (ext == "xml" || ext == "sh3d") return ImportFormat::sweethome3d;
  if (ext == "txt") return ImportFormat::r2v;
  if (ext == "obj") return ImportFormat::obj;
  return std::nullopt;
}

ImportResult import_file_text(std::string_view bytes, ImportFormat format, const ImportOptions& options) {
  if (looks_like_zip(bytes) && format != ImportFormat::r2v) return import_archive(bytes, format, options);
  switch (format) {
    case ImportFormat::sweethome3d:
      return import_sweethome3d(bytes, options);
    case ImportFormat::r2v:
      return import_r2v(bytes, options);
    case ImportFormat::obj:
      return import_obj(bytes, options);
  }
  throw InputError(InputError::Kind::invalid, "/format", "unknown import format");
}

}  // namespace rr

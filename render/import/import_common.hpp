// Pieces every importer shares (render/import/ only): source-located errors, line splitting,
// number parsing, the bounding box of what was imported, and the default camera, lights and options
// written around an imported scene. World space: metres, +Y up, plan points (x, z).
#pragma once

#include "render/core/math.hpp"
#include "render/import/import.hpp"
#include "render/scene_io/errors.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rr::import_detail {

using Kind = InputError::Kind;

// An error at a line of a line-based source file: pointer "/line/N", message "line N: detail".
[[noreturn]] void throw_at_line(Kind kind, size_t line, const std::string& detail);

// Splits text into lines (LF or CRLF), with the 1-based line number of each.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}
  // The next line without its end-of-line characters, or nullopt at the end.
  std::optional<std::string_view> next();
  size_t line_number() const { return line_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  size_t line_ = 0;
};

// Splits on spaces and tabs, skipping empty fields.
std::vector<std::string_view> split_fields(std::string_view line);

// The whole of `field` as a finite double, or nullopt.
std::optional<double> parse_double(std::string_view field);
// The whole of `field` as a long long, or nullopt.
std::optional<long long> parse_long(std::string_view field);

// The scale to use: options.scale, or the format's default when it is 0. Throws InputError
// (pointer "/scale") when it is not finite and > 0.
double resolve_scale(const ImportOptions& options, ImportFormat format);

// Axis-aligned box of everything imported, for the default camera and the floor.
struct Box3 {
  Vec3 lo{std::numeric_limits<double>::max()};
  Vec3 hi{-std::numeric_limits<double>::max()};
  void add(Vec3 p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return lo.x > hi.x; }
};

// Rounded to the micrometre, so cm -> m conversions print short and equal inputs stay equal.
double round_m(double metres);
nlohmann::json json_vec2(Vec2 v);
nlohmann::json json_vec3(Vec3 v);
nlohmann::json json_color(Color c);

// A camera `elevation_deg` above the +Z side of `box`, aimed at its centre, far enough back that
// the box's bounding sphere fits both fields of view at `aspect` (width / height).
nlohmann::json camera_showing_box(const Box3& box, double aspect, double elevation_deg = 50.0);

// {"width", "height"} from the options (checked by parse_request like any request).
nlohmann::json request_options(const ImportOptions& options);

// A directional light from above and in front, so walls facing different ways shade differently.
nlohmann::json default_sun_light();

}  // namespace rr::import_detail

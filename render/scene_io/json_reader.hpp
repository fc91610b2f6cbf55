// Typed, pointer-carrying access to parsed JSON, used by scene_json to read requests. Every read
// checks the JSON type and a numeric range and throws InputError naming the exact JSON Pointer of the
// offending value; absent optional members yield the caller's default. No scene knowledge here.
#pragma once

#include "render/scene_io/errors.hpp"
#include "render/core/math.hpp"

#include <nlohmann/json.hpp>

#include <initializer_list>
#include <limits>
#include <span>
#include <string>
#include <string_view>

namespace rr {

// An interval for a number. Open ends exclude the bound; `kind_above` lets a limit on size or work
// (image side, cylinder segments) report too_large while bad values below stay invalid.
struct NumberRange {
  double lo = -std::numeric_limits<double>::max();
  double hi = std::numeric_limits<double>::max();
  bool lo_open = false;
  bool hi_open = false;
  InputError::Kind kind_above = InputError::Kind::invalid;
};

// A short number for messages: "5.2", "4096", "1e-09".
std::string format_number(double value);

[[noreturn]] void throw_invalid(const std::string& pointer, const std::string& detail);
[[noreturn]] void throw_too_large(const std::string& pointer, const std::string& detail);

// Reads of a single value at `pointer`.
double read_number(const nlohmann::json& value, const std::string& pointer, const NumberRange& range);
long long read_integer(const nlohmann::json& value, const std::string& pointer, const NumberRange& range);
Vec2 read_vec2(const nlohmann::json& value, const std::string& pointer, const NumberRange& range);
Vec3 read_vec3(const nlohmann::json& value, const std::string& pointer, const NumberRange& range);
Color read_color(const nlohmann::json& value, const std::string& pointer);
const nlohmann::json& expect_array(const nlohmann::json& value, const std::string& pointer);

// One JSON object whose keys are all in an allowed list (additionalProperties: false).
class ObjectReader {
 public:
  ObjectReader(const nlohmann::json& value, std::string pointer,
               std::span<const std::string_view> allowed_keys);
  ObjectReader(const nlohmann::json& value, std::string pointer,
               std::initializer_list<std::string_view> allowed_keys)
      : ObjectReader(value, std::move(pointer), std::span(allowed_keys.begin(), allowed_keys.size())) {}

  const std::string& pointer() const { return pointer_; }
  std::string at(std::string_view key) const { return pointer_append(pointer_, std::string(key)); }
  const nlohmann::json* find(std::string_view key) const;
  const nlohmann::json& require(std::string_view key) const;  // throws when absent

  double number(std::string_view key, double fallback, const NumberRange& range) const;
  double number(std::string_view key, const NumberRange& range) const;
  long long integer(std::string_view key, long long fallback, const NumberRange& range) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::string string(std::string_view key, const std::string& fallback) const;
  Vec2 vec2(std::string_view key, Vec2 fallback, const NumberRange& range) const;
  Vec2 vec2(std::string_view key, const NumberRange& range) const;
  Vec3 vec3(std::string_view key, Vec3 fallback, const NumberRange& range) const;
  Vec3 vec3(std::string_view key, const NumberRange& range) const;
  Color color(std::string_view key, Color fallback) const;
  // The member as an array (or an empty array when absent and not required).
  const nlohmann::json& array(std::string_view key, bool required = false) const;

 private:
  const nlohmann::json& object_;
  std::string pointer_;
};

}  // namespace rr

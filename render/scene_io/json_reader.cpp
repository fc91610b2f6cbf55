// Typed reads of parsed JSON with JSON Pointers in every error (see json_reader.hpp). Numbers must be
// finite even though parse_json_text already rejects non-finite ones: request_from_json also takes
// JSON built in code, where NaN can be stored.
#include "render/scene_io/json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rr {

using nlohmann::json;

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

void throw_invalid(const std::string& pointer, const std::string& detail) {
  throw InputError(InputError::Kind::invalid, pointer, detail);
}

void throw_too_large(const std::string& pointer, const std::string& detail) {
  throw InputError(InputError::Kind::too_large, pointer, detail);
}

namespace {

void check_range(double v, const std::string& pointer, const NumberRange& range) {
  if (v < range.lo || (range.lo_open && v == range.lo)) {
    throw_invalid(pointer,
                  std::string(range.lo_open ? "must be greater than " : "must be at least ") + format_number(range.lo));
  }
  if (v > range.hi || (range.hi_open && v == range.hi)) {
    throw InputError(range.kind_above, pointer,
                     std::string(range.hi_open ? "must be less than " : "must be at most ") + format_number(range.hi));
  }
}

// A fixed-size array of numbers, each checked against `range` at its own pointer.
template <int N>
glm::vec<N, double> read_vector(const json& value, const std::string& pointer, const NumberRange& range) {
  if (!value.is_array() || value.size() != N) {
    throw_invalid(pointer, "must be an array of " + std::to_string(N) + " numbers");
  }
  glm::vec<N, double> out;
  for (int i = 0; i < N; ++i) {
    out[i] = read_number(value[size_t(i)], pointer_append(pointer, size_t(i)), range);
  }
  return out;
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

const char* const color_rule = "must be a colour: \"#rrggbb\" or [r, g, b] with components in [0, 1]";

Color read_hex_color(const std::string& text, const std::string& pointer) {
  if (text.size() != 7 || text[0] != '#') throw_invalid(pointer, color_rule);
  Color out;
  for (int channel = 0; channel < 3; ++channel) {
    int high = hex_digit(text[size_t(1 + 2 * channel)]);
    int low = hex_digit(text[size_t(2 + 2 * channel)]);
    if (high < 0 || low < 0) throw_invalid(pointer, color_rule);
    out[channel] = float(high * 16 + low) / 255.0f;
  }
  return out;
}

}  // namespace

double read_number(const json& value, const std::string& pointer, const NumberRange& range) {
  if (!value.is_number()) throw_invalid(pointer, "must be a number");
  double v = value.get<double>();
  if (!std::isfinite(v)) throw_invalid(pointer, "must be a finite number");
  check_range(v, pointer, range);
  return v;
}

long long read_integer(const json& value, const std::string& pointer, const NumberRange& range) {
  // JSON Schema's "integer": any number with a zero fractional part, so 2.0 is accepted too and
  // the server agrees with the published schema.
  // Every integer member of a request is read here, so 16 and 16.0 mean the same everywhere.
  if (!value.is_number()) throw_invalid(pointer, "must be an integer");
  double v = value.get<double>();
  if (!std::isfinite(v) || v != std::floor(v)) {
    throw_invalid(pointer, "must be an integer (got " + format_number(v) + ")");
  }
  check_range(v, pointer, range);
  // Outside +-2^62 a double cannot be cast to long long safely; no integer member comes near it.
  constexpr double cast_limit = 4611686018427387904.0;
  if (v < -cast_limit || v > cast_limit) {
    throw InputError(range.kind_above, pointer, "must be at most " + format_number(range.hi));
  }
  return value.is_number_integer() ? value.get<long long>() : static_cast<long long>(v);
}

Vec2 read_vec2(const json& value, const std::string& pointer, const NumberRange& range) {
  return read_vector<2>(value, pointer, range);
}

Vec3 read_vec3(const json& value, const std::string& pointer, const NumberRange& range) {
  return read_vector<3>(value, pointer, range);
}

Color read_color(const json& value, const std::string& pointer) {
  if (value.is_string()) return read_hex_color(value.get_ref<const std::string&>(), pointer);
  if (!value.is_array() || value.size() != 3) throw_invalid(pointer, color_rule);
  Vec3 rgb = read_vec3(value, pointer, NumberRange{0.0, 1.0});
  return Color(rgb);
}

const json& expect_array(const json& value, const std::string& pointer) {
  if (!value.is_array()) throw_invalid(pointer, "must be an array");
  return value;
}

void ErrorList::add(std::string pointer, std::string detail) {
  if (errors_.size() == max_listed_errors) {
    truncated_ = true;
    throw Full{};
  }
  errors_.push_back({std::move(pointer), std::move(detail)});
}

void ErrorList::add(const InputError& error) {
  for (const FieldProblem& e : error.errors()) add(e.pointer, e.detail);
}

void ErrorList::throw_if_any() const {
  if (!errors_.empty()) throw InputError(InputError::Kind::invalid, errors_, truncated_);
}

ObjectReader::ObjectReader(const json& value, std::string pointer, ErrorList& errors,
                           std::span<const std::string_view> allowed_keys)
    : object_(value), pointer_(std::move(pointer)), errors_(errors) {
  if (!value.is_object()) throw_invalid(pointer_, "must be an object");
  for (const auto& [key, member] : value.items()) {
    if (std::find(allowed_keys.begin(), allowed_keys.end(), key) != allowed_keys.end()) continue;
    std::string expected;
    for (std::string_view allowed : allowed_keys) {
      expected += (expected.empty() ? "" : ", ") + std::string(allowed);
    }
    errors_.add(pointer_append(pointer_, key), "unknown key (expected one of: " + expected + ")");
  }
}

const json* ObjectReader::find(std::string_view key) const {
  auto it = object_.find(key);
  return it == object_.end() ? nullptr : &*it;
}

const json& ObjectReader::require(std::string_view key) const {
  const json* member = find(key);
  if (!member) throw_invalid(pointer_, "missing required key \"" + std::string(key) + "\"");
  return *member;
}

template <class T, class Read>
T ObjectReader::optional(std::string_view key, T fallback, Read read) const {
  const json* member = find(key);
  if (!member) return fallback;
  T out = fallback;
  errors_.attempt([&] { out = read(*member, at(key)); });
  return out;
}

template <class T, class Read>
T ObjectReader::required(std::string_view key, Read read) const {
  T out{};
  errors_.attempt([&] { out = read(require(key), at(key)); });
  return out;
}

double ObjectReader::number(std::string_view key, double fallback, const NumberRange& range) const {
  return optional(key, fallback, [&](const json& v, const std::string& p) { return read_number(v, p, range); });
}

double ObjectReader::number(std::string_view key, const NumberRange& range) const {
  return required<double>(key, [&](const json& v, const std::string& p) { return read_number(v, p, range); });
}

long long ObjectReader::integer(std::string_view key, long long fallback, const NumberRange& range) const {
  return optional(key, fallback, [&](const json& v, const std::string& p) { return read_integer(v, p, range); });
}

bool ObjectReader::boolean(std::string_view key, bool fallback) const {
  return optional(key, fallback, [](const json& v, const std::string& p) {
    if (!v.is_boolean()) throw_invalid(p, "must be true or false");
    return v.get<bool>();
  });
}

std::string ObjectReader::string(std::string_view key, const std::string& fallback) const {
  return optional(key, fallback, [](const json& v, const std::string& p) {
    if (!v.is_string()) throw_invalid(p, "must be a string");
    return v.get<std::string>();
  });
}

Vec2 ObjectReader::vec2(std::string_view key, Vec2 fallback, const NumberRange& range) const {
  return optional(key, fallback, [&](const json& v, const std::string& p) { return read_vec2(v, p, range); });
}

Vec2 ObjectReader::vec2(std::string_view key, const NumberRange& range) const {
  return required<Vec2>(key, [&](const json& v, const std::string& p) { return read_vec2(v, p, range); });
}

Vec3 ObjectReader::vec3(std::string_view key, Vec3 fallback, const NumberRange& range) const {
  return optional(key, fallback, [&](const json& v, const std::string& p) { return read_vec3(v, p, range); });
}

Vec3 ObjectReader::vec3(std::string_view key, const NumberRange& range) const {
  return required<Vec3>(key, [&](const json& v, const std::string& p) { return read_vec3(v, p, range); });
}

Color ObjectReader::color(std::string_view key, Color fallback) const {
  return optional(key, fallback, [](const json& v, const std::string& p) { return read_color(v, p); });
}

const json& ObjectReader::array(std::string_view key, bool required) const {
  static const json empty = json::array();
  const json* member = required ? &require(key) : find(key);
  return member ? expect_array(*member, at(key)) : empty;
}

}  // namespace rr

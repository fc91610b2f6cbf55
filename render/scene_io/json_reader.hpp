// Typed, pointer-carrying access to parsed JSON, used by scene_json to read requests. Every read
// checks the JSON type and a numeric range; the read_* functions throw InputError naming the exact
// JSON Pointer of the offending value, while ObjectReader records invalid members in an ErrorList and
// reads on, so one pass finds every independent error. Absent optional members yield the caller's
// default. No scene knowledge here.
#pragma once

#include "render/core/math.hpp"
#include "render/scene_io/errors.hpp"

#include <nlohmann/json.hpp>

#include <initializer_list>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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

// The invalid-input problems of one request, gathered while reading goes on past them. Only
// Kind::invalid is gathered: malformed text and documented limits stop reading at once (they are
// answered alone, 400 / 413), and so does a problem past max_listed_errors.
class ErrorList {
 public:
  // Thrown by add() when the list is full and another problem arrives; the reader's entry point
  // catches it and throws the (truncated) list. Not an InputError, so attempt() lets it through.
  struct Full {};

  void add(std::string pointer, std::string detail);
  void add(const InputError& error);
  size_t size() const { return errors_.size(); }

  // Runs `read`; an InputError of Kind::invalid that it throws is added here and false returned.
  template <class Read>
  bool attempt(Read&& read) {
    try {
      std::forward<Read>(read)();
      return true;
    } catch (const InputError& e) {
      if (e.kind() != InputError::Kind::invalid) throw;
      add(e);
      return false;
    }
  }

  // Throws InputError(invalid) listing every problem, when there is one.
  void throw_if_any() const;

 private:
  std::vector<FieldProblem> errors_;
  bool truncated_ = false;
};

// One JSON object whose keys are all in an allowed list (additionalProperties: false).
// Throws when `value` is not an object; an unknown key, or a member of the wrong type or range, is
// added to `errors` and its read yields the fallback (or a zero value for a required member), so a
// check that combines members must first see that none of them failed (ErrorList::size()).
class ObjectReader {
 public:
  ObjectReader(const nlohmann::json& value, std::string pointer, ErrorList& errors,
               std::span<const std::string_view> allowed_keys);
  ObjectReader(const nlohmann::json& value, std::string pointer, ErrorList& errors,
               std::initializer_list<std::string_view> allowed_keys)
      : ObjectReader(value, std::move(pointer), errors, std::span(allowed_keys.begin(), allowed_keys.size())) {}

  const std::string& pointer() const { return pointer_; }
  ErrorList& errors() const { return errors_; }
  std::string at(std::string_view key) const { return pointer_append(pointer_, std::string(key)); }
  const nlohmann::json* find(std::string_view key) const;
  const nlohmann::json& require(std::string_view key) const;  // throws when absent
  // Runs read(member, its pointer) when the member is present, adding what it throws to errors().
  template <class Read>
  void member(std::string_view key, Read&& read) const {
    if (const nlohmann::json* value = find(key)) errors_.attempt([&] { read(*value, at(key)); });
  }

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
  // The member as an array (or an empty array when absent and not required). Throws.
  const nlohmann::json& array(std::string_view key, bool required = false) const;

 private:
  // `read(member, pointer)` for a present member, else `fallback`; an error it throws is recorded
  // and gives `fallback` too.
  template <class T, class Read>
  T optional(std::string_view key, T fallback, Read read) const;
  // The same for a member that must be there: absent is recorded as a missing key.
  template <class T, class Read>
  T required(std::string_view key, Read read) const;

  const nlohmann::json& object_;
  std::string pointer_;
  ErrorList& errors_;
};

}  // namespace rr

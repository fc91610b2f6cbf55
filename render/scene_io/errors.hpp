// Errors raised at the boundary (parsing, validation, limits). Each names the offending part of the
// request as a JSON Pointer (RFC 6901) so clients can show the error at the field. The core code
// behind validation assumes valid input and does not throw these.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rr {

// One problem at one place: a JSON Pointer into the input and what is wrong there.
struct FieldProblem {
  std::string pointer;
  std::string detail;
};

// An invalid input lists at most this many problems; reading stops at the next one (docs/api.md,
// "Errors"), so a request with thousands of bad elements costs and answers no more than this.
inline constexpr size_t max_listed_errors = 100;

class InputError : public std::runtime_error {
 public:
  enum class Kind {
    malformed,  // not JSON, or JSON we refuse to read (depth, duplicate keys): HTTP 400
    invalid,    // well-formed but semantically wrong: HTTP 422
    too_large,  // exceeds a documented limit on size or work: HTTP 413
  };
  InputError(Kind kind, std::string pointer, const std::string& detail)
      : InputError(kind, std::vector<FieldProblem>{FieldProblem{std::move(pointer), detail}}, false) {}
  // Several problems in the order they were found; `truncated` when max_listed_errors cut the list.
  // The first one is pointer() and what(), so a reader that wants one error reads those.
  InputError(Kind kind, std::vector<FieldProblem> errors, bool truncated);

  Kind kind() const { return kind_; }
  const std::string& pointer() const { return errors_.front().pointer; }
  const std::vector<FieldProblem>& errors() const { return errors_; }
  bool truncated() const { return truncated_; }

  // One line naming the first problem's place: "/scene/walls/2/height: must be greater than 0 (and
  // 2 more errors)". A problem at "" (the whole input) is told by its detail alone.
  std::string summary() const;

  // The same problems with every pointer passed through `map` (a request's pointers told in terms
  // of another document).
  template <class Map>
  InputError with_pointers(Map map) const {
    std::vector<FieldProblem> moved = errors_;
    for (FieldProblem& e : moved) e.pointer = map(e.pointer);
    return InputError(kind_, std::move(moved), truncated_);
  }

 private:
  Kind kind_;
  std::vector<FieldProblem> errors_;  // never empty
  bool truncated_;
};

// Client text quoted in an error (a key, an enum value, a query parameter, a pointer token) is cut
// to this many bytes, so an answer stays small whatever the request held (docs/api.md, "Errors").
inline constexpr size_t max_quoted_input_bytes = 64;

// How many leading bytes of `text` an error quotes: all of it when it fits, else at most
// max_quoted_input_bytes ending on a UTF-8 character boundary.
size_t quoted_input_length(std::string_view text);

// What follows a cut quote: "…(4194304 bytes)", the length of the whole text.
std::string truncation_marker(size_t total_bytes);

// `text` as an error quotes it: whole, or its first bytes (quoted_input_length) + truncation_marker.
std::string quote_input(std::string_view text);

// Appends a reference token to a JSON Pointer, escaping '~' and '/' as RFC 6901 requires. A token
// longer than max_quoted_input_bytes is cut by quote_input first: these pointers only name places
// in errors and warnings, and the marker shows that the pointer no longer resolves.
std::string pointer_append(const std::string& pointer, const std::string& token);
std::string pointer_append(const std::string& pointer, size_t index);

}  // namespace rr

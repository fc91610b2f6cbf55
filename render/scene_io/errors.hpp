// Errors raised at the boundary (parsing, validation, limits). Each names the offending part of the
// request as a JSON Pointer (RFC 6901) so clients can show the error at the field. The core code
// behind validation assumes valid input and does not throw these.
#pragma once

#include <stdexcept>
#include <string>

namespace rr {

class InputError : public std::runtime_error {
 public:
  enum class Kind {
    malformed,  // not JSON, or JSON we refuse to read (depth, duplicate keys): HTTP 400
    invalid,    // well-formed but semantically wrong: HTTP 422
    too_large,  // exceeds a documented limit on size or work: HTTP 413
  };
  InputError(Kind kind, std::string pointer, const std::string& detail)
      : std::runtime_error(detail), kind_(kind), pointer_(std::move(pointer)) {}
  Kind kind() const { return kind_; }
  const std::string& pointer() const { return pointer_; }

 private:
  Kind kind_;
  std::string pointer_;
};

// Appends a reference token to a JSON Pointer, escaping '~' and '/' as RFC 6901 requires.
std::string pointer_append(const std::string& pointer, const std::string& token);
std::string pointer_append(const std::string& pointer, size_t index);

}  // namespace rr

// RFC 9457 problem details: every error the service answers with is built here, and this is the one
// place that maps an error to an HTTP status (InputError::Kind -> 400/422/413). Output is the JSON
// text of an `application/problem+json` body; nothing here knows about sockets or httplib.
#pragma once

#include "render/errors.hpp"

#include <exception>
#include <string>
#include <string_view>
#include <vector>

namespace rr::server {

inline constexpr const char* problem_content_type = "application/problem+json";

// One entry of the problem's "errors" array: where in the request, and what is wrong there.
struct FieldError {
  std::string pointer;  // JSON Pointer (RFC 6901) into the request body; "" is the whole body
  std::string detail;
};

struct Problem {
  int status = 500;
  std::string body;  // problem+json text
};

// The HTTP reason phrase for a status ("Unprocessable Content" for 422), or "Error" when unknown.
std::string_view status_title(int status);

// A problem+json body with type "about:blank" and, when `title` is empty, the status's reason phrase
// as its title (RFC 9457 section 4.2.1 asks for exactly that pairing).
std::string make_problem(int status, std::string_view title, std::string_view detail,
                         const std::vector<FieldError>& errors = {});

// A problem for a bare HTTP status that no handler explained (httplib's own rejections: a broken
// request line, a target too long, ...), with a generic detail.
Problem status_problem(int status);

// The status an input error maps to: malformed 400, invalid 422, too_large 413.
int status_for(InputError::Kind kind);

// The problem answering an InputError: its message as detail and one FieldError at its pointer.
Problem problem_from_input_error(const InputError& error);

// The problem answering any other exception: 500 with a fixed detail, never the exception's text
// (it can carry paths and internals that clients must not see).
Problem internal_error_problem();

// Any exception a handler let escape: InputError -> its problem; anything else -> the internal
// error problem, with the exception's text put in `log_detail` for the server's own log (left empty
// for InputError, which is the client's mistake, not ours).
Problem problem_from_exception(std::exception_ptr error, std::string& log_detail);

}  // namespace rr::server

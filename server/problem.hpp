// RFC 9457 problem details: every error the service answers with is built here, and this is the one
// place that maps an error to an HTTP status (InputError::Kind -> 400/422/413). Output is the JSON
// text of an `application/problem+json` body; nothing here knows about sockets or httplib.
#pragma once

#include "render/scene_io/errors.hpp"

#include <exception>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rr::server {

inline constexpr const char* problem_content_type = "application/problem+json";

// One entry of the problem's "errors" array: where in the request, and what is wrong there.
struct FieldError {
  std::string pointer;  // JSON Pointer (RFC 6901) into the request body; "" is the whole body
  std::string detail;
  std::string parameter = {};  // the query parameter the value came from, when it came from one
};

using HeaderList = std::vector<std::pair<std::string, std::string>>;

struct Problem {
  int status = 500;
  std::string body;         // problem+json text
  HeaderList headers = {};  // e.g. Retry-After with 503, Allow with 405
};

// An HTTP-level refusal a handler throws (404 no such scene, 503 saturated, 504 deadline, ...): its
// message is the problem's detail, so it must be written for the client.
class HttpError : public std::runtime_error {
 public:
  HttpError(int status, const std::string& detail, std::vector<FieldError> errors = {}, HeaderList headers = {})
      : std::runtime_error(detail), status_(status), errors_(std::move(errors)), headers_(std::move(headers)) {}
  int status() const { return status_; }
  const std::vector<FieldError>& errors() const { return errors_; }
  const HeaderList& headers() const { return headers_; }

 private:
  int status_;
  std::vector<FieldError> errors_;
  HeaderList headers_;
};

// The HTTP reason phrase for a status, as the status line gives it ("Unprocessable Entity" for 422),
// or "Error" when unknown.
std::string_view status_title(int status);

// A problem+json body with type "about:blank" and, when `title` is empty, the status's reason phrase
// as its title (RFC 9457 section 4.2.1 asks for exactly that pairing). `errors_truncated` says that
// more errors were found than `errors` lists.
std::string make_problem(int status, std::string_view title, std::string_view detail,
                         const std::vector<FieldError>& errors = {}, bool errors_truncated = false);

// A problem for a bare HTTP status that no handler explained (httplib's own rejections: a broken
// request line, a target too long, ...), with a generic detail.
Problem status_problem(int status);

// The status an input error maps to: malformed 400, invalid 422, too_large 413.
int status_for(InputError::Kind kind);

// The problem answering an InputError: its summary (the first error's pointer and message, and how
// many more) as detail, one FieldError per error, and errors_truncated when the list was cut.
Problem problem_from_input_error(const InputError& error);

// The problem answering any other exception: 500 with a fixed detail, never the exception's text
// (it can carry paths and internals that clients must not see).
Problem internal_error_problem();

// Any exception a handler let escape: InputError -> its problem; HttpError -> its status, detail,
// errors and headers; anything else -> the internal
// error problem, with the exception's text put in `log_detail` for the server's own log (left empty
// for InputError, which is the client's mistake, not ours).
Problem problem_from_exception(std::exception_ptr error, std::string& log_detail);

}  // namespace rr::server

// Problem details (RFC 9457) for every error the service returns; see problem.hpp. Titles follow the
// HTTP reason phrases so a problem with type "about:blank" reads like its status line.
#include "server/problem.hpp"

#include "server/document_store.hpp"

#include <nlohmann/json.hpp>

namespace rr::server {

std::string_view status_title(int status) {
  switch (status) {
    case 400:
      return "Bad Request";
    case 401:
      return "Unauthorized";
    case 403:
      return "Forbidden";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 406:
      return "Not Acceptable";
    case 408:
      return "Request Timeout";
    case 409:
      return "Conflict";
    case 411:
      return "Length Required";
    // httplib writes the status line with the RFC 7231 names for 413 and 422, so titles use them too.
    case 413:
      return "Payload Too Large";
    case 414:
      return "URI Too Long";
    case 415:
      return "Unsupported Media Type";
    case 416:
      return "Range Not Satisfiable";
    case 422:
      return "Unprocessable Entity";
    case 429:
      return "Too Many Requests";
    case 431:
      return "Request Header Fields Too Large";
    case 500:
      return "Internal Server Error";
    case 501:
      return "Not Implemented";
    case 503:
      return "Service Unavailable";
    case 504:
      return "Gateway Timeout";
    case 507:
      return "Insufficient Storage";
    default:
      return "Error";
  }
}

std::string make_problem(int status, std::string_view title, std::string_view detail,
                         const std::vector<FieldError>& errors, bool errors_truncated) {
  nlohmann::json body = {
      {"type", "about:blank"},
      {"title", title.empty() ? status_title(status) : title},
      {"status", status},
      {"detail", detail},
  };
  if (!errors.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (const FieldError& e : errors) {
      nlohmann::json entry = {{"pointer", e.pointer}, {"detail", e.detail}};
      if (!e.parameter.empty()) entry["parameter"] = e.parameter;
      list.push_back(std::move(entry));
    }
    body["errors"] = std::move(list);
    if (errors_truncated) body["errors_truncated"] = true;
  }
  // `replace` keeps a stray invalid UTF-8 byte in a message from turning into a second error.
  return body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

Problem status_problem(int status) {
  std::string_view detail;
  switch (status) {
    case 400:
      detail = "The request could not be read as HTTP.";
      break;
    case 404:
      detail = "There is no resource at this path.";
      break;
    case 413:
      detail = "The request body exceeds the size limit.";
      break;
    case 414:
      detail = "The request target is longer than the server accepts.";
      break;
    case 415:
      detail = "The request body's encoding or media type is not accepted.";
      break;
    default:
      detail = status >= 500 ? "The server failed to handle the request." : "The request was refused.";
  }
  return {status, make_problem(status, "", detail)};
}

int status_for(InputError::Kind kind) {
  switch (kind) {
    case InputError::Kind::malformed:
      return 400;
    case InputError::Kind::invalid:
      return 422;
    case InputError::Kind::too_large:
      return 413;
  }
  return 400;  // unreachable for valid enumerators; keeps -Wreturn-type quiet
}

Problem problem_from_input_error(const InputError& error) {
  int status = status_for(error.kind());
  std::vector<FieldError> errors;
  errors.reserve(error.errors().size());
  for (const FieldProblem& e : error.errors()) errors.push_back({e.pointer, e.detail});
  return {status, make_problem(status, "", error.summary(), errors, error.truncated())};
}

Problem internal_error_problem() {
  return {500, make_problem(500, "", "The server failed to handle the request; it has been logged.")};
}

Problem problem_from_exception(std::exception_ptr error, std::string& log_detail) {
  log_detail.clear();
  try {
    std::rethrow_exception(error);
  } catch (const InputError& e) {
    return problem_from_input_error(e);
  } catch (const HttpError& e) {
    return {e.status(), make_problem(e.status(), "", e.what(), e.errors()), e.headers()};
  } catch (const StoreUnavailable& e) {
    return {503, make_problem(503, "", e.what()), {{"Retry-After", std::to_string(e.retry_after_s())}}};
  } catch (const std::exception& e) {
    log_detail = e.what();
  } catch (...) {
    log_detail = "non-standard exception";
  }
  return internal_error_problem();
}

}  // namespace rr::server

// Who may do what. In: a request's Origin, Host and Authorization headers and its route's Access;
// out: the CORS headers its answer carries, the caller's owner name, or a refusal (403 from a
// disallowed origin, 401 without a valid bearer token). Reads are open to every origin; writes only
// to the origins the operator lists and, when a token file is given, only with a token.
#pragma once

#include "server/problem.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace httplib {
struct Request;
}

namespace rr::server {

// What a route does to stored state, as CORS and tokens judge it.
enum class Access {
  read,               // any origin, no token
  write,              // --cors-origins only; a token when tokens are on
  write_when_stored,  // a write when the query has store=1 (imports), else a read
  owner_read,         // a read that answers per caller: a token when tokens are on (GET /v1/scenes)
};

bool is_write(Access access, const httplib::Request& req);

// The token file: one token per line, "name:token" or a bare token; blank lines and lines starting
// with '#' are skipped. Tokens use the RFC 6750 b64token characters (no ':' or spaces), so a name is
// everything before the last ':'. Two tokens may share a name (rotation): they are one owner. A
// bare token's owner is "token-" and a hash of it, so its scenes stay its own across file edits.
class TokenTable {
 public:
  TokenTable() = default;
  // Throws std::runtime_error naming the file and line (never the token). An empty path: no tokens.
  static TokenTable load(const std::filesystem::path& file);

  bool empty() const { return tokens_.empty(); }
  size_t size() const { return tokens_.size(); }
  // The owner of the token in an Authorization value ("Bearer <token>"). Every configured token is
  // compared in full, without stopping at the first differing byte or the first match, so timing
  // tells nothing about how close a guess came.
  std::optional<std::string> owner_of(std::string_view authorization) const;

  struct Token {
    std::string owner;
    std::string secret;
  };

 private:
  std::vector<Token> tokens_;
};

// --cors-origins, --api-token-file and --allow-listing, as the screening of every request uses them.
struct AccessPolicy {
  std::vector<std::string> write_origins;  // "https://app.example.com"; "*" lets every origin write
  TokenTable tokens;
  bool allow_listing = false;  // GET /v1/scenes on a server without tokens
};

// A refusal screening answers with a problem body.
struct Refusal {
  int status = 403;
  std::string detail;
  HeaderList headers;
};

// The CORS headers of the answer to `req` (a read: "*"; a write: the echoed origin when it may write).
HeaderList cors_headers(const AccessPolicy& policy, const httplib::Request& req, bool write);
// 403 when a browser on another origin sends a write that origin may not make.
std::optional<Refusal> screen_origin(const AccessPolicy& policy, const httplib::Request& req, bool write);
// With tokens on: the caller's owner name, else a 401. Without tokens: "" (everyone is one owner).
std::optional<Refusal> screen_token(const AccessPolicy& policy, const httplib::Request& req, std::string& owner);

// The answer to a CORS preflight (OPTIONS with Access-Control-Request-Method) for a path whose
// routes take `methods` (with their Access): 204 and the allow headers, or a refusal.
struct RouteMethod {
  std::string method;
  Access access;
};
struct Preflight {
  std::optional<Refusal> refusal;
  HeaderList headers;
};
Preflight answer_preflight(const AccessPolicy& policy, const httplib::Request& req,
                           const std::vector<RouteMethod>& methods);

}  // namespace rr::server

// CORS and bearer tokens (see access.hpp). Reads answer "Access-Control-Allow-Origin: *": they carry
// no cookies, the answer is the same for every origin, so shared caches keep one copy (no Vary), and
// a token sent by a page is its own choice to send. Writes echo an allowed origin with Vary: Origin,
// since their answer depends on it; a page may not make a write the operator did not allow even when
// a browser would send it without a preflight.
#include "server/access.hpp"

#include "render/core/hash.hpp"

#include <httplib.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <stdexcept>

namespace rr::server {

namespace {

// Headers a page may read from our answers (beyond the CORS-safelisted ones).
constexpr const char* exposed_headers =
    "Server-Timing, X-Scene-Id, X-Cache, X-Shadow-Cache, X-Exposure, X-Warning-Count, ETag, Location, Retry-After, "
    "WWW-Authenticate";
constexpr const char* allowed_request_headers = "Content-Type, Authorization, Accept, If-None-Match";
// Seconds a browser may reuse a preflight's answer (Chromium caps it at 7200).
constexpr const char* preflight_max_age = "7200";
constexpr const char* bearer_challenge = "Bearer realm=\"roomrender\"";

const std::regex owner_pattern("[A-Za-z0-9._@-]{1,64}");
const std::regex token_pattern("[A-Za-z0-9._~+/-]+=*");  // RFC 6750 b64token
constexpr size_t min_token_chars = 16;

std::string trim(std::string_view text) {
  size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string_view::npos) return "";
  size_t end = text.find_last_not_of(" \t\r");
  return std::string(text.substr(begin, end - begin + 1));
}

// Runs over the longer of the two whatever the bytes, so time depends on lengths alone.
bool same_secret(std::string_view a, std::string_view b) {
  const size_t n = std::max(a.size(), b.size());
  volatile unsigned char diff = a.size() != b.size();
  for (size_t i = 0; i < n; ++i) {
    unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
    unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
    diff = diff | (x ^ y);
  }
  return diff == 0;
}

// "https://app.example.com:8443" -> "app.example.com:8443".
std::string_view authority_of(std::string_view origin) {
  size_t scheme = origin.find("://");
  return scheme == std::string_view::npos ? std::string_view() : origin.substr(scheme + 3);
}

// The server's own pages (Origin naming the Host the request was sent to) always may write, as
// before CORS existed; other origins only when listed.
bool origin_may_write(const AccessPolicy& policy, const httplib::Request& req, const std::string& origin) {
  if (origin.empty()) return true;  // not a cross-origin browser request
  if (!authority_of(origin).empty() && authority_of(origin) == req.get_header_value("Host")) return true;
  const auto& list = policy.write_origins;
  return std::find(list.begin(), list.end(), origin) != list.end() ||
         std::find(list.begin(), list.end(), "*") != list.end();
}

Refusal origin_refusal(const std::string& origin) {
  return {403,
          "Writes from the origin " + origin +
              " are not allowed; the server's operator lists the origins that may write with --cors-origins.",
          {}};
}

}  // namespace

bool is_write(Access access, const httplib::Request& req) {
  switch (access) {
    case Access::read:
    case Access::owner_read:
      return false;
    case Access::write:
      return true;
    // Anything but "0" counts, so no spelling of store=1 the handler accepts ("1.0") passes as a read.
    case Access::write_when_stored:
      return req.has_param("store") && req.get_param_value("store") != "0";
  }
  return true;
}

TokenTable TokenTable::load(const std::filesystem::path& file) {
  TokenTable table;
  if (file.empty()) return table;
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read the token file " + file.string());
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::string text = trim(line);
    if (text.empty() || text.starts_with('#')) continue;
    const std::string where = file.string() + ":" + std::to_string(number) + ": ";
    Token token;
    size_t colon = text.rfind(':');
    token.secret = colon == std::string::npos ? text : trim(text.substr(colon + 1));
    token.owner = colon == std::string::npos ? "token-" + hash_hex(text) : trim(text.substr(0, colon));
    if (!std::regex_match(token.owner, owner_pattern)) {
      throw std::runtime_error(where + "a token's name is 1-64 of A-Z a-z 0-9 . _ @ -");
    }
    if (!std::regex_match(token.secret, token_pattern) || token.secret.size() < min_token_chars) {
      throw std::runtime_error(where + "a token is at least 16 of A-Z a-z 0-9 - . _ ~ + / (then any '=')");
    }
    for (const Token& other : table.tokens_) {
      if (other.secret == token.secret) throw std::runtime_error(where + "this token is listed twice");
    }
    table.tokens_.push_back(std::move(token));
  }
  return table;
}

std::optional<std::string> TokenTable::owner_of(std::string_view authorization) const {
  constexpr std::string_view scheme = "bearer ";
  if (authorization.size() <= scheme.size()) return std::nullopt;
  for (size_t i = 0; i < scheme.size(); ++i) {  // the scheme is case-insensitive (RFC 9110 11.1)
    if (std::tolower(static_cast<unsigned char>(authorization[i])) != scheme[i]) return std::nullopt;
  }
  const std::string presented = trim(authorization.substr(scheme.size()));
  std::optional<std::string> owner;
  for (const Token& token : tokens_) {
    if (same_secret(presented, token.secret)) owner = token.owner;
  }
  return owner;
}

HeaderList cors_headers(const AccessPolicy& policy, const httplib::Request& req, bool write) {
  if (!write) {
    return {{"Access-Control-Allow-Origin", "*"},
            {"Access-Control-Expose-Headers", exposed_headers},
            {"Timing-Allow-Origin", "*"}};
  }
  HeaderList headers = {{"Vary", "Origin"}};
  const std::string origin = req.get_header_value("Origin");
  if (!origin.empty() && origin_may_write(policy, req, origin)) {
    headers.push_back({"Access-Control-Allow-Origin", origin});
    headers.push_back({"Access-Control-Expose-Headers", exposed_headers});
  }
  return headers;
}

std::optional<Refusal> screen_origin(const AccessPolicy& policy, const httplib::Request& req, bool write) {
  const std::string origin = req.get_header_value("Origin");
  if (!write || origin_may_write(policy, req, origin)) return std::nullopt;
  return origin_refusal(origin);
}

std::optional<Refusal> screen_token(const AccessPolicy& policy, const httplib::Request& req, std::string& owner) {
  owner.clear();
  if (policy.tokens.empty()) return std::nullopt;
  if (!req.has_header("Authorization")) {
    return Refusal{401,
                   "This server takes writes only with a token: send Authorization: Bearer <token>.",
                   {{"WWW-Authenticate", bearer_challenge}}};
  }
  std::optional<std::string> found = policy.tokens.owner_of(req.get_header_value("Authorization"));
  if (!found) {
    return Refusal{401,
                   "The Authorization header holds no bearer token this server accepts.",
                   {{"WWW-Authenticate", std::string(bearer_challenge) + ", error=\"invalid_token\""}}};
  }
  owner = *found;
  return std::nullopt;
}

Preflight answer_preflight(const AccessPolicy& policy, const httplib::Request& req,
                           const std::vector<RouteMethod>& methods) {
  const std::string origin = req.get_header_value("Origin");
  const std::string wanted = req.get_header_value("Access-Control-Request-Method");
  std::string allowed;
  bool wanted_exists = false, wanted_allowed = false, any_write = false;
  for (const RouteMethod& m : methods) {
    const bool write = is_write(m.access, req);
    any_write = any_write || write;
    const bool ok = !write || origin_may_write(policy, req, origin);
    const std::string names = m.method == "GET" ? "GET, HEAD" : m.method;
    bool named = m.method == wanted || (m.method == "GET" && wanted == "HEAD");
    wanted_exists = wanted_exists || named;
    wanted_allowed = wanted_allowed || (named && ok);
    if (ok) allowed += (allowed.empty() ? "" : ", ") + names;
  }
  if (!wanted_exists) {
    return {Refusal{405, wanted + " is not allowed here; a page may use " + allowed + ".", {}}, {}};
  }
  if (!wanted_allowed) return {origin_refusal(origin), {}};
  // One answer for reads and writes of a path: echo the origin when a write is among them.
  Preflight out;
  out.headers = {{"Access-Control-Allow-Origin", any_write && !origin.empty() ? origin : "*"},
                 {"Access-Control-Allow-Methods", allowed},
                 {"Access-Control-Allow-Headers", allowed_request_headers},
                 {"Access-Control-Max-Age", preflight_max_age},
                 {"Vary", "Origin"}};
  return out;
}

}  // namespace rr::server
